#include "cli/preflight.hpp"

#include <cmath>
#include <cstdio>
#include <tpmsfill/error.hpp>

#include "cli/ranks.hpp"
#include "cli/terminal_progress.hpp"

namespace tpmsfill::cli {
namespace {

// Jobs whose forecast reaches these get the preflight line (smaller ones finish before it
// would be read).
constexpr double kPreflightSeconds = 5;
constexpr double kPreflightBytes = 1e8;

}  // namespace

std::string si_text(double value, const char* unit) {
  static constexpr const char* kPrefix[] = {"", "k", "M", "G", "T"};
  int p = 0;
  for (; p < 4 && value >= 1000; ++p) value /= 1000;
  char b[32];
  std::snprintf(b, sizeof b, "%.3g %s%s", value, kPrefix[p], unit);
  return b;
}

std::string count_text(double n) {
  std::string s = si_text(n, "");
  if (s.back() == ' ') s.pop_back();
  return s;
}

std::string seconds_text(double s) {
  char b[32];
  if (s < 60)
    std::snprintf(b, sizeof b, "%.2g s", s);
  else if (s < 3600)
    std::snprintf(b, sizeof b, "%.0f min", s / 60);
  else
    std::snprintf(b, sizeof b, "%.1f h", s / 3600);
  return b;
}

void add_yes_flag(CLI::App* sub, bool& yes) {
  sub->add_flag("--yes", yes,
                "Run a job the preflight forecasts past its limits (an output over 2 GB, or over "
                "an hour); without it such a job is refused before any work");
}

void run_preflight(const Preflight& p, bool yes, TerminalProgress* progress) {
  if (progress && rank() == 0) {
    progress->clear();
    if (progress_mode() == ProgressMode::Json) {
      nlohmann::ordered_json j = nlohmann::ordered_json::object();
      if (p.samples) j["samples"] = p.samples;
      j.update(p.made_json);
      j["bytes"] = std::round(p.bytes);
      j["format"] = p.format;
      j["seconds"] = {p.seconds_low, p.seconds_high};
      if (p.memory_bytes) j["memory_bytes"] = p.memory_bytes;
      std::fprintf(stderr, "%s\n", nlohmann::ordered_json{{"preflight", j}}.dump().c_str());
    } else if (p.seconds_high >= kPreflightSeconds || p.bytes >= kPreflightBytes) {
      std::string line = "tpmsfill: preflight: ";
      if (p.samples) line += count_text(static_cast<double>(p.samples)) + " samples, ";
      line += p.made + " (" + si_text(p.bytes, "B") + " of " + p.format + "), " +
              seconds_text(p.seconds_low) + " to " + seconds_text(p.seconds_high);
      if (p.memory_bytes)
        line += ", about " + si_text(static_cast<double>(p.memory_bytes), "B") + " of memory";
      std::fprintf(stderr, "%s\n", line.c_str());
    }
    std::fflush(stderr);
  }
  if (yes) return;
  std::string over;
  if (p.bytes > kOutputLimitBytes)
    over = "write about " + si_text(p.bytes, "B") + " (over the " +
           si_text(kOutputLimitBytes, "B") + " limit)";
  const double middle = std::sqrt(p.seconds_low * p.seconds_high);
  if (middle > kTimeLimitSeconds)
    over += (over.empty() ? "" : " and ") + std::string("take about ") + seconds_text(middle) +
            " (over the " + seconds_text(kTimeLimitSeconds) + " limit)";
  if (!over.empty())
    throw InputError("the job would " + over + ": " + p.made +
                     (p.samples ? " from " + count_text(static_cast<double>(p.samples)) + " samples"
                                : std::string()) +
                     "; " + p.smaller + " makes it smaller, and --yes runs it as it is");
}

}  // namespace tpmsfill::cli
