// A Progress that draws one self-overwriting line on stderr ("  fill holes        42%"), for
// commands run on a terminal.
#pragma once

#include <cstdio>
#include <mutex>
#include <string>
#include <string_view>
#include <tpmsfill/progress.hpp>

namespace tpmsfill::cli {

class TerminalProgress : public Progress {
 public:
  void begin(std::string_view stage) override {
    std::lock_guard lock(mutex_);
    stage_ = stage;
    shown_ = -1;
    draw(0);
  }
  bool report(double fraction) override {
    std::lock_guard lock(mutex_);
    draw(static_cast<int>(fraction * 100));
    return true;
  }
  /// Erases the line (call before printing the result).
  void clear() {
    std::lock_guard lock(mutex_);
    std::fprintf(stderr, "\r%40s\r", "");
  }

 private:
  void draw(int percent) {
    if (percent == shown_) return;
    shown_ = percent;
    std::fprintf(stderr, "\r  %-18s %3d%%", stage_.c_str(), percent);
    std::fflush(stderr);
  }
  std::mutex mutex_;
  std::string stage_;
  int shown_ = -1;
};

}  // namespace tpmsfill::cli
