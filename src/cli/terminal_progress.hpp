// A Progress that draws one self-overwriting line on stderr, for commands run on a terminal:
// "  [3/9] classify  42%  (overall 31%)" for a planned job's stage, "[9/9] validate: edges"
// for a part of one, "  repair soup  50%" for a stage announced without a plan. In a job that
// `tpmsfill serve` runs, it writes "stage<TAB>percent<TAB>overall" lines to the service's pipe
// instead, and answers false (cancel) once the service asked the job to stop.
#pragma once

#include <unistd.h>

#include <atomic>
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

/// Whether a command shows progress: not --quiet, and on a terminal or for the service.
inline bool progress_wanted(bool quiet) {
  return !quiet && (isatty(STDERR_FILENO) || service_progress_fd() >= 0);
}

class TerminalProgress : public Progress {
 public:
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
    if (service_progress_fd() >= 0) return;
    if (width_ > 0) std::fprintf(stderr, "\r%*s\r", width_, "");
    std::fflush(stderr);
    width_ = 0;
  }

 private:
  void draw(int percent) {
    if (percent == shown_) return;
    shown_ = percent;
    if (service_progress_fd() >= 0) {
      dprintf(service_progress_fd(), "%s\t%d\t%.4f\n", label_.c_str(), percent,
              overall_ >= 0 ? overall_ : -1.0);
      return;
    }
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
  std::mutex mutex_;
  std::string label_;
  int shown_ = -1;
  double overall_ = -1;
  int width_ = 0;  ///< the widest line drawn, in characters, for clear()
};

}  // namespace tpmsfill::cli
