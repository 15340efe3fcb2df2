// The reports' one number formatter: printf's formats, numbers only, into a string of any
// length.
#pragma once

#include <cstdio>
#include <string>
#include <type_traits>

namespace tpmsfill::detail {

/// `fmt` filled with `numbers`, each passed as a double (so its conversions are %f, %g, %e and
/// their kin, whatever the argument's type). One argument per conversion.
template <typename... Numbers>
std::string format(const char* fmt, Numbers... numbers) {
  static_assert(sizeof...(Numbers) > 0 && (std::is_arithmetic_v<Numbers> && ...),
                "format() takes one or more numbers");
  const int size = std::snprintf(nullptr, 0, fmt, static_cast<double>(numbers)...);
  if (size <= 0) return {};
  std::string text(static_cast<std::size_t>(size), '\0');
  std::snprintf(text.data(), text.size() + 1, fmt, static_cast<double>(numbers)...);
  return text;
}

}  // namespace tpmsfill::detail
