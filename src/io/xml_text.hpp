/// @file xml_text.hpp
/// @brief Text made safe for XML 1.0 content and attribute values: the SVG layers' titles and
/// the metadata tpmsfill puts in a 3MF package (lib3mf 1.8 writes it as given).
#pragma once

#include <string>
#include <string_view>

namespace tpmsfill::detail {

/// `text` with & < > " ' escaped and the control characters XML 1.0 forbids (all below 0x20
/// but tab and line breaks) dropped.
inline std::string xml_escaped(std::string_view text) {
  std::string out;
  out.reserve(text.size());
  for (const char c : text) {
    switch (c) {
      case '&':
        out += "&amp;";
        break;
      case '<':
        out += "&lt;";
        break;
      case '>':
        out += "&gt;";
        break;
      case '"':
        out += "&quot;";
        break;
      case '\'':
        out += "&apos;";
        break;
      default:
        if (static_cast<unsigned char>(c) >= 0x20 || c == '\t' || c == '\n' || c == '\r') out += c;
    }
  }
  return out;
}

}  // namespace tpmsfill::detail
