// A Progress that draws one self-overwriting line on stderr, for commands run on a terminal:
// "  [3/9] classify  42%  (overall 31%)" for a planned job's stage, "[9/9] validate: edges"
// for a part of one, "  repair soup  50%" for a stage announced without a plan.
#pragma once

#include <cstdio>
#include <mutex>
#include <string>
#include <string_view>
#include <tpmsfill/progress.hpp>

namespace tpmsfill::cli {

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
    return true;
  }
  /// Erases the line (call before printing the result).
  void clear() {
    std::lock_guard lock(mutex_);
    if (width_ > 0) std::fprintf(stderr, "\r%*s\r", width_, "");
    std::fflush(stderr);
    width_ = 0;
  }

 private:
  void draw(int percent) {
    if (percent == shown_) return;
    shown_ = percent;
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
