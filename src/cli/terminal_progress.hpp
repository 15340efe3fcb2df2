// A Progress on stderr. On a terminal it draws one self-overwriting line:
// "  [3/9] classify  42%  (overall 31%)" for a planned job's stage, "[9/9] validate: edges"
// for a part of one, "  repair soup  50%" for a stage announced without a plan. Off a terminal
// (a log, a pipe, a batch queue) it writes a line every 10 s once a job has run 5 s, so short
// jobs print nothing; `--progress json` writes one JSON object a line for scripts. In a job
// that `tpmsfill serve` runs, it writes "stage<TAB>percent<TAB>overall" lines to the service's
// pipe instead, and answers false (cancel) once the service asked the job to stop.
#pragma once

#include <unistd.h>

#include <atomic>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <mutex>
#include <string>
#include <string_view>
#include <tpmsfill/progress.hpp>

namespace tpmsfill::cli {

/// The pipe `tpmsfill serve` reads a job's progress from (TPMSFILL_PROGRESS_FD), or -1.
inline int service_progress_fd() {
  static const int fd = [] {
    const char* value = std::getenv("TPMSFILL_PROGRESS_FD");
    return value ? std::atoi(value) : -1;
  }();
  return fd;
}

/// Set by SIGTERM in a job the service runs (main.cpp): the next report() cancels the job.
inline std::atomic<bool>& cancel_requested() {
  static std::atomic<bool> flag{false};
  return flag;
}

/// How progress is shown (`--progress`): auto is a bar on a terminal and lines elsewhere.
enum class ProgressMode { Auto, Bar, Lines, Json, None };

/// The mode `--progress` set for this run (main.cpp adds the flag to every command that shows
/// progress).
inline ProgressMode& progress_mode() {
  static ProgressMode mode = ProgressMode::Auto;
  return mode;
}

/// The mode of `--progress NAME`: auto, bar, lines, json or none (the flag checks the name).
inline ProgressMode progress_mode_named(std::string_view name) {
  return name == "bar"     ? ProgressMode::Bar
         : name == "lines" ? ProgressMode::Lines
         : name == "json"  ? ProgressMode::Json
         : name == "none"  ? ProgressMode::None
                           : ProgressMode::Auto;
}

/// Whether a command shows progress: not --quiet nor --progress none, or for the service.
inline bool progress_wanted(bool quiet) {
  return service_progress_fd() >= 0 || (!quiet && progress_mode() != ProgressMode::None);
}

class TerminalProgress : public Progress {
 public:
  TerminalProgress()
      : mode_(progress_mode() != ProgressMode::Auto ? progress_mode()
              : isatty(STDERR_FILENO)               ? ProgressMode::Bar
                                                    : ProgressMode::Lines) {}

  void begin(std::string_view stage) override { begin(StageInfo{stage}); }
  void begin(const StageInfo& stage) override {
    std::lock_guard lock(mutex_);
    std::string label(stage.name);
    if (stage.count > 0)
      label = "[" + std::to_string(stage.index) + "/" + std::to_string(stage.count) + "] " + label;
    if (!stage.step.empty()) label += ": " + std::string(stage.step);
    label_ = std::move(label);
    // A stage outside any plan has no overall; a planned one shows the last until it reports.
    if (stage.count <= 0)
      overall_ = -1;
    else if (overall_ < 0)
      overall_ = 0;
    shown_ = -1;
    if (mode_ == ProgressMode::Json) last_line_ = {};  // every stage's start is a line
    draw(0);
  }
  bool report(double fraction) override { return report(fraction, -1); }
  bool report(double fraction, double overall) override {
    std::lock_guard lock(mutex_);
    if (overall >= 0) overall_ = overall;
    draw(static_cast<int>(fraction * 100));
    return !cancel_requested();
  }
  /// Erases the line (call before printing the result).
  void clear() {
    std::lock_guard lock(mutex_);
    if (service_progress_fd() >= 0 || mode_ != ProgressMode::Bar) return;
    if (width_ > 0) std::fprintf(stderr, "\r%*s\r", width_, "");
    std::fflush(stderr);
    width_ = 0;
  }

 private:
  void draw(int percent) {
    // Lines and JSON are paced by the clock (write_line), the bar and the service by change.
    const bool paced = service_progress_fd() < 0 && mode_ != ProgressMode::Bar;
    if (percent == shown_ && !paced) return;
    shown_ = percent;
    if (service_progress_fd() >= 0) {
      dprintf(service_progress_fd(), "%s\t%d\t%.4f\n", label_.c_str(), percent,
              overall_ >= 0 ? overall_ : -1.0);
      return;
    }
    if (mode_ != ProgressMode::Bar) return write_line(percent);
    int n;
    if (overall_ >= 0)
      n = std::fprintf(stderr, "\r  %-30s %3d%%  (overall %3d%%)", label_.c_str(), percent,
                       static_cast<int>(overall_ * 100));
    else
      n = std::fprintf(stderr, "\r  %-30s %3d%%", label_.c_str(), percent);
    // Pad over what a longer line before left behind.
    if (n - 1 < width_) std::fprintf(stderr, "%*s", width_ - (n - 1), "");
    if (n - 1 > width_) width_ = n - 1;
    std::fflush(stderr);
  }
  // Lines: the first after 5 s, then one every 10 s; JSON: every stage's start and one a second.
  void write_line(int percent) {
    const auto now = std::chrono::steady_clock::now();
    const double elapsed = std::chrono::duration<double>(now - start_).count();
    const bool json = mode_ == ProgressMode::Json;
    if (json ? last_line_ != std::chrono::steady_clock::time_point{} &&
                   now - last_line_ < std::chrono::seconds(1)
             : elapsed < 5 || (last_line_ != std::chrono::steady_clock::time_point{} &&
                               now - last_line_ < std::chrono::seconds(10)))
      return;
    last_line_ = now;
    if (json) {
      std::string label;  // the label as a JSON string: quotes and backslashes escaped
      for (const char c : label_) {
        if (c == '"' || c == '\\') label += '\\';
        if (static_cast<unsigned char>(c) >= 0x20) label += c;
      }
      std::fprintf(stderr,
                   "{\"stage\": \"%s\", \"percent\": %d, \"overall\": %.4f, \"seconds\": %.1f}\n",
                   label.c_str(), percent, overall_ >= 0 ? overall_ : -1.0, elapsed);
    } else if (overall_ >= 0) {
      std::fprintf(stderr, "tpmsfill: %s %d%% (overall %d%%), %.0f s\n", label_.c_str(), percent,
                   static_cast<int>(overall_ * 100), elapsed);
    } else {
      std::fprintf(stderr, "tpmsfill: %s %d%%, %.0f s\n", label_.c_str(), percent, elapsed);
    }
    std::fflush(stderr);
  }

  const ProgressMode mode_;
  const std::chrono::steady_clock::time_point start_ = std::chrono::steady_clock::now();
  std::chrono::steady_clock::time_point last_line_{};
  std::mutex mutex_;
  std::string label_;
  int shown_ = -1;
  double overall_ = -1;
  int width_ = 0;  ///< the widest line drawn, in characters, for clear()
};

}  // namespace tpmsfill::cli
