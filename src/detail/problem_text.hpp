/// @file problem_text.hpp
/// @brief Wording shared by the sentences check_mesh() and validate_mesh() write.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <string>

namespace tpmsfill::detail {

/// "1 border edge", "3 border edges".
inline std::string plural(std::uint64_t n, const char* one, const char* many) {
  return std::to_string(n) + " " + (n == 1 ? one : many);
}

/// Three significant digits, never in exponent notation for everyday magnitudes.
inline std::string short_number(double v) {
  if (!std::isfinite(v) || v == 0) return v == 0 ? "0" : std::to_string(v);
  double magnitude = std::floor(std::log10(std::fabs(v)));
  if (magnitude < -6 || magnitude > 15) {
    char buffer[32];
    std::snprintf(buffer, sizeof buffer, "%.3g", v);
    return buffer;
  }
  int decimals = std::max(0, 2 - static_cast<int>(magnitude));
  char buffer[64];
  std::snprintf(buffer, sizeof buffer, "%.*f", decimals, v);
  return buffer;
}

}  // namespace tpmsfill::detail
