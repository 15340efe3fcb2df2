// A Progress that draws one self-overwriting line on stderr ("  [3/9] classify  42%  (31 %
// overall)"), for commands run on a terminal.
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
    stage_ = stage.count > 0 ? "[" + std::to_string(stage.index) + "/" +
                                   std::to_string(stage.count) + "] " + std::string(stage.name)
                             : std::string(stage.name);
    shown_ = -1;
    draw(0);
  }
  bool report(double fraction) override { return report(fraction, -1); }
  bool report(double fraction, double overall) override {
    std::lock_guard lock(mutex_);
    overall_ = overall;
    draw(static_cast<int>(fraction * 100));
    return true;
  }
  /// Erases the line (call before printing the result).
  void clear() {
    std::lock_guard lock(mutex_);
    std::fprintf(stderr, "\r%60s\r", "");
  }

 private:
  void draw(int percent) {
    if (percent == shown_) return;
    shown_ = percent;
    if (overall_ >= 0)
      std::fprintf(stderr, "\r  %-26s %3d%%  (%3d %% overall)", stage_.c_str(), percent,
                   static_cast<int>(overall_ * 100));
    else
      std::fprintf(stderr, "\r  %-26s %3d%%", stage_.c_str(), percent);
    std::fflush(stderr);
  }
  std::mutex mutex_;
  std::string stage_;
  int shown_ = -1;
  double overall_ = -1;
};

}  // namespace tpmsfill::cli
