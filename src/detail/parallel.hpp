/// @file parallel.hpp
/// @brief The one parallel loop tpmsfill uses, and a helper that reports progress from it.
///
/// Results must not depend on the thread count: bodies write by index (count → exclusive
/// scan → fill), never by atomic append, and reductions combine per-chunk results in chunk
/// order (see deterministic_sum).
#pragma once

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <atomic>
#include <cstddef>
#include <vector>

#include "tpmsfill/error.hpp"
#include "tpmsfill/progress.hpp"

namespace tpmsfill::detail {

/// Calls body(begin, end) over [0, n) in chunks of about `grain`, in parallel when n > grain.
template <class Body>
void parallel_for(std::size_t n, std::size_t grain, const Body& body) {
  if (n == 0) return;
  grain = std::max<std::size_t>(grain, 1);
  if (n <= grain) {
    body(std::size_t{0}, n);
    return;
  }
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, grain),
                    [&](const tbb::blocked_range<std::size_t>& r) { body(r.begin(), r.end()); });
}

/// Sum of f(i) over [0, n), computed per fixed chunk of `chunk` items and added in chunk
/// order, so the rounding is the same for every thread count.
template <class F>
double deterministic_sum(std::size_t n, std::size_t chunk, const F& f) {
  chunk = std::max<std::size_t>(chunk, 1);
  const std::size_t chunks = (n + chunk - 1) / chunk;
  std::vector<double> partial(chunks, 0.0);
  parallel_for(chunks, 1, [&](std::size_t b, std::size_t e) {
    for (std::size_t c = b; c < e; ++c) {
      double s = 0;
      const std::size_t end = std::min(n, (c + 1) * chunk);
      for (std::size_t i = c * chunk; i < end; ++i) s += f(i);
      partial[c] = s;
    }
  });
  double total = 0;
  for (double p : partial) total += p;
  return total;
}

/// Counts finished work units from many threads and forwards the fraction to a Progress,
/// at most about 100 times; throws Cancelled (from the calling thread) once it says stop.
class ProgressCounter {
 public:
  ProgressCounter(Progress* progress, const char* stage, std::size_t total)
      : progress_(progress), total_(std::max<std::size_t>(total, 1)) {
    if (progress_) progress_->begin(stage);
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
  void finish() {
    if (progress_ && !progress_->report(1.0)) throw Cancelled("cancelled");
  }

 private:
  Progress* progress_;
  std::size_t total_;
  std::atomic<std::size_t> done_{0};
  std::atomic<bool> cancelled_{false};
};

}  // namespace tpmsfill::detail
