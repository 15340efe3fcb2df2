// Argument checks whose messages read like the tool's own ("--scale must be > 0"), in place of
// CLI11's stock validators (which print ranges to 300 digits). CLI11 reports a failed check as
// "NAME: MESSAGE"; usage_error() (usage_errors.hpp) turns that into one sentence.
#pragma once

#include <CLI/CLI.hpp>
#include <cmath>
#include <filesystem>
#include <optional>
#include <string>

namespace tpmsfill::cli {

namespace detail {
// The argument as a number, or nothing when it is not one (the type conversion then reports
// it). "nan" and "inf" are numbers here, so that the range checks refuse them.
inline std::optional<double> as_number(const std::string& text) {
  try {
    std::size_t used = 0;
    const double v = std::stod(text, &used);
    if (used == text.size()) return v;
  } catch (const std::exception&) {
  }
  return std::nullopt;
}
}  // namespace detail

/// A finite number > 0.
inline CLI::Validator positive() {
  return CLI::Validator(
      [](std::string& text) -> std::string {
        const std::optional<double> v = detail::as_number(text);
        return !v || (*v > 0 && std::isfinite(*v)) ? "" : "must be > 0";
      },
      "> 0");
}

/// A number in [lo, hi]; the message names both ends as given.
inline CLI::Validator between(double lo, double hi, const std::string& range) {
  return CLI::Validator(
      [=](std::string& text) -> std::string {
        const std::optional<double> v = detail::as_number(text);
        return !v || (*v >= lo && *v <= hi) ? "" : "must be " + range;
      },
      range);
}

/// An existing file (not a folder).
inline CLI::Validator existing_file() {
  return CLI::Validator(
      [](std::string& text) -> std::string {
        std::error_code ec;
        if (std::filesystem::is_directory(text, ec)) return "'" + text + "' is a folder";
        return std::filesystem::exists(text, ec) ? "" : "no such file '" + text + "'";
      },
      "FILE");
}

}  // namespace tpmsfill::cli
