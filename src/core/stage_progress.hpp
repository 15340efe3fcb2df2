/// @file stage_progress.hpp
/// @brief The one progress idiom every stage uses (as OpenVDB's null-safe interrupter): a
/// stage begins, reports fractions and throws Cancelled once its Progress says stop. Callers
/// never test the pointer; a null Progress means no reporting.
#pragma once

#include <algorithm>
#include <atomic>
#include <cstddef>
#include <string_view>

#include "tpmsfill/error.hpp"
#include "tpmsfill/progress.hpp"

namespace tpmsfill::detail {

/// progress->begin(stage), when there is a progress.
inline void begin_stage(Progress* progress, std::string_view stage) {
  if (progress) progress->begin(stage);
}

/// progress->report(fraction), when there is a progress.
/// @throws Cancelled  the progress asked to stop
inline void report_or_cancel(Progress* progress, double fraction) {
  if (progress && !progress->report(fraction)) throw Cancelled("cancelled");
}

/// Counts finished work units from many threads and forwards the fraction to a Progress,
/// at most about 100 times; throws Cancelled (from the calling thread) once it says stop.
class ProgressCounter {
 public:
  ProgressCounter(Progress* progress, const char* stage, std::size_t total)
      : progress_(progress), total_(std::max<std::size_t>(total, 1)) {
    begin_stage(progress_, stage);
  }
  /// Adds `units` finished units. Cheap when no Progress is attached.
  void add(std::size_t units) {
    if (!progress_) return;
    const std::size_t before = done_.fetch_add(units, std::memory_order_relaxed);
    const std::size_t step = total_ / 100 + 1;
    if ((before + units) / step != before / step) {
      if (!progress_->report(static_cast<double>(std::min(before + units, total_)) /
                             static_cast<double>(total_)))
        cancelled_.store(true, std::memory_order_relaxed);
    }
    if (cancelled_.load(std::memory_order_relaxed)) throw Cancelled("cancelled");
  }
  void finish() { report_or_cancel(progress_, 1.0); }

 private:
  Progress* progress_;
  std::size_t total_;
  std::atomic<std::size_t> done_{0};
  std::atomic<bool> cancelled_{false};
};

}  // namespace tpmsfill::detail
