// The page's files, embedded with the assembler's .incbin: the bytes go into .rodata as they
// are, with no generated source to compile (app.js is 600 KB). The paths are compile
// definitions set by CMakeLists.txt, which also makes this file depend on them.
#include "service/web_assets.hpp"

// Defines SYMBOL and SYMBOL_end around FILE's bytes (a zero byte follows, unused).
#define TPMSFILL_EMBED(symbol, file)                                                        \
  asm(".section .rodata\n.balign 16\n.global " #symbol "\n.hidden " #symbol "\n" #symbol    \
      ":\n.incbin \"" file "\"\n.global " #symbol "_end\n.hidden " #symbol "_end\n" #symbol \
      "_end:\n.byte 0\n.previous\n");                                                       \
  extern "C" const char symbol[];                                                           \
  extern "C" const char symbol##_end[];

TPMSFILL_EMBED(tpmsfill_web_index_html, TPMSFILL_WEB_SOURCE_DIR "/index.html")
TPMSFILL_EMBED(tpmsfill_web_style_css, TPMSFILL_WEB_SOURCE_DIR "/style.css")
TPMSFILL_EMBED(tpmsfill_web_app_js, TPMSFILL_WEB_BUILD_DIR "/app.js")
TPMSFILL_EMBED(tpmsfill_web_index_html_gz, TPMSFILL_WEB_BUILD_DIR "/index.html.gz")
TPMSFILL_EMBED(tpmsfill_web_style_css_gz, TPMSFILL_WEB_BUILD_DIR "/style.css.gz")
TPMSFILL_EMBED(tpmsfill_web_app_js_gz, TPMSFILL_WEB_BUILD_DIR "/app.js.gz")

namespace tpmsfill::service {

std::optional<WebAsset> web_asset(std::string_view path) {
  const auto view = [](const char* begin, const char* end) {
    return std::string_view(begin, static_cast<std::size_t>(end - begin));
  };
  if (path == "/" || path == "/index.html")
    return WebAsset{view(tpmsfill_web_index_html, tpmsfill_web_index_html_end),
                    view(tpmsfill_web_index_html_gz, tpmsfill_web_index_html_gz_end),
                    "text/html; charset=utf-8"};
  if (path == "/style.css")
    return WebAsset{view(tpmsfill_web_style_css, tpmsfill_web_style_css_end),
                    view(tpmsfill_web_style_css_gz, tpmsfill_web_style_css_gz_end),
                    "text/css; charset=utf-8"};
  if (path == "/app.js")
    return WebAsset{view(tpmsfill_web_app_js, tpmsfill_web_app_js_end),
                    view(tpmsfill_web_app_js_gz, tpmsfill_web_app_js_gz_end),
                    "text/javascript; charset=utf-8"};
  return std::nullopt;
}

bool web_page_bundled() {
  return TPMSFILL_WEB_BUNDLED;
}

}  // namespace tpmsfill::service
