// The page `tpmsfill serve` answers at / (issue 19), embedded in the program at build time:
// index.html and style.css from src/service/web, app.js bundled there by esbuild with three.js
// (CMakeLists.txt). Nothing is read from disk or fetched from elsewhere at run time.
#pragma once

#include <optional>
#include <string_view>

namespace tpmsfill::service {

struct WebAsset {
  std::string_view body;
  std::string_view gzipped;  ///< the same bytes gzipped at build time (gzip -9)
  const char* content_type;
};

/// The embedded file served at path ("/" is index.html), or nullopt.
std::optional<WebAsset> web_asset(std::string_view path);

/// False when the program was built without npm: app.js then only says how to get the page.
bool web_page_bundled();

}  // namespace tpmsfill::service
