/// @file parallel.hpp
/// @brief The one parallel loop tpmsfill uses, and a sum that rounds the same way for every
/// thread count.
///
/// Results must not depend on the thread count: bodies write by index (count → exclusive
/// scan → fill), never by atomic append, and reductions combine per-chunk results in chunk
/// order (see deterministic_sum).
#pragma once

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cstddef>
#include <vector>

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

/// A stable compaction of [0, n) by keep(i), per fixed chunk of `chunk` items: chunk c's kept
/// items take the places [offsets[c], offsets[c + 1]) in order; offsets.back() is the count.
template <class Keep>
std::vector<std::size_t> compaction_offsets(std::size_t n, std::size_t chunk, const Keep& keep) {
  chunk = std::max<std::size_t>(chunk, 1);
  const std::size_t chunks = (n + chunk - 1) / chunk;
  std::vector<std::size_t> offsets(chunks + 1, 0);
  parallel_for(chunks, 1, [&](std::size_t b, std::size_t e) {
    for (std::size_t c = b; c < e; ++c) {
      std::size_t kept = 0;
      for (std::size_t i = c * chunk; i < std::min(n, (c + 1) * chunk); ++i)
        kept += keep(i) ? 1 : 0;
      offsets[c + 1] = kept;
    }
  });
  for (std::size_t c = 0; c < chunks; ++c) offsets[c + 1] += offsets[c];
  return offsets;
}

/// The compaction's second pass, once the output is sized to offsets.back(): put(i, place) for
/// every kept i, place being its index in the output. `offsets` from compaction_offsets with
/// the same n, chunk and keep.
template <class Keep, class Put>
void for_each_kept(const std::vector<std::size_t>& offsets, std::size_t n, std::size_t chunk,
                   const Keep& keep, const Put& put) {
  chunk = std::max<std::size_t>(chunk, 1);
  parallel_for(offsets.size() - 1, 1, [&](std::size_t b, std::size_t e) {
    for (std::size_t c = b; c < e; ++c) {
      std::size_t place = offsets[c];
      for (std::size_t i = c * chunk; i < std::min(n, (c + 1) * chunk); ++i)
        if (keep(i)) put(i, place++);
    }
  });
}

}  // namespace tpmsfill::detail
