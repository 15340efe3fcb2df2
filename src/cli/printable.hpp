/// @file printable.hpp
/// @brief Text from files made safe for a terminal before it is printed.
#pragma once

#include <cstdio>
#include <string>
#include <string_view>

namespace tpmsfill::cli {

/// `text` with its control characters shown as \xNN: what a file says (a provenance, a name in
/// an error, a library's warning about it) cannot move the cursor, recolour the terminal or
/// set its title.
inline std::string printable(std::string_view text) {
  std::string out;
  out.reserve(text.size());
  for (const char c : text) {
    const auto u = static_cast<unsigned char>(c);
    if (u < 0x20 || u == 0x7f) {
      char escaped[5];
      std::snprintf(escaped, sizeof escaped, "\\x%02x", u);
      out += escaped;
    } else {
      out += c;
    }
  }
  return out;
}

}  // namespace tpmsfill::cli
