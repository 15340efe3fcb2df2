// The preflight of a long command (fill, slice, material slice): once its input is read and
// its options reviewed, before any work, what the job will make and cost on stderr, and past
// the limits (an output few tools open, a job that holds the machine for hours) a refusal
// that says what would bring it under them, unless --yes.
#pragma once

#include <CLI/CLI.hpp>
#include <cstdint>
#include <nlohmann/json.hpp>
#include <string>

namespace tpmsfill::cli {

class TerminalProgress;

/// Past these a job asks for --yes.
constexpr double kOutputLimitBytes = 2e9;
constexpr double kTimeLimitSeconds = 3600;

struct Preflight {
  std::uint64_t samples = 0;  ///< field samples (0: the command samples no field)
  /// What the job makes, as said after the samples: "about 648 k triangles".
  std::string made;
  /// The same for `--progress json`, put into {"preflight": {...}} with the figures below.
  nlohmann::ordered_json made_json = nlohmann::ordered_json::object();
  double bytes = 0;    ///< the output's size forecast
  std::string format;  ///< the output's format, as the command names it
  double seconds_low = 0, seconds_high = 0;
  std::uint64_t memory_bytes = 0;  ///< the peak planned (0: not forecast)
  /// What makes the job smaller, for the refusal: "a larger --voxel or --cell".
  std::string smaller;
};

/// Prints the preflight (one JSON object a line with `--progress json`; else a line when the
/// slow end reaches 5 s or the output 100 MB) and refuses a job past the limits unless `yes`.
/// `progress` is cleared first; nothing is printed without one (--quiet).
/// @throws InputError  past a limit without `yes`
void run_preflight(const Preflight& p, bool yes, TerminalProgress* progress);

/// `--yes` on `sub`: run a job the preflight forecasts past its limits.
void add_yes_flag(CLI::App* sub, bool& yes);

/// "648 k", "33.8 MB", "7.48 GB": three digits and an SI prefix.
std::string si_text(double value, const char* unit);
/// "648 k", "12": a count the same way.
std::string count_text(double n);
/// "1.5 s", "12 min", "2.3 h".
std::string seconds_text(double seconds);

}  // namespace tpmsfill::cli
