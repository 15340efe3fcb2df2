/// @file json_depth.hpp
/// @brief The nesting depth JSON may have, checked on the text before it is parsed: recipes and
/// the service's options are read from strangers, and every walk over a parsed document (a
/// dump, a key search, a destructor) recurses once per level.
#pragma once

#include <cstdint>
#include <optional>
#include <string_view>

namespace tpmsfill::detail {

/// The deepest nesting of arrays and objects read. A recipe nests four levels (a blend's ramp
/// in the blends in the lattice); a document 30,000 deep overflowed a request thread's stack.
inline constexpr int kMaxJsonDepth = 64;

/// Where `text` first opens a level beyond `max_depth`: its byte offset, or nothing. Brackets
/// inside strings do not count; text that is not JSON is left to the parser.
inline std::optional<std::uint64_t> json_too_deep(std::string_view text,
                                                  int max_depth = kMaxJsonDepth) {
  int depth = 0;
  bool in_string = false, escaped = false;
  for (std::size_t i = 0; i < text.size(); ++i) {
    const char c = text[i];
    if (in_string) {
      if (escaped)
        escaped = false;
      else if (c == '\\')
        escaped = true;
      else if (c == '"')
        in_string = false;
    } else if (c == '"') {
      in_string = true;
    } else if (c == '[' || c == '{') {
      if (++depth > max_depth) return i;
    } else if ((c == ']' || c == '}') && depth > 0) {
      --depth;
    }
  }
  return std::nullopt;
}

}  // namespace tpmsfill::detail
