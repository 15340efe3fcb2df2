/// @file grid_buffer.hpp
/// @brief A zeroed vector for a whole grid's values, backed by huge pages where the kernel
/// offers them on request.
///
/// Why: a grid's field or mask is hundreds of MB of fresh memory, and zeroing it touches every
/// 4 KB page once, each touch a page fault. On the 2-core development machine (transparent huge
/// pages on request only, "madvise") those faults and the zeroing were a quarter of a fill's
/// samples (docs/benchmarks.md §31). Asking for huge pages before the first touch makes one
/// fault serve 2 MB. The contents are those of std::vector<T>(n): only where they live changes.
#pragma once

#include <sys/mman.h>

#include <cstddef>
#include <cstdint>
#include <vector>

namespace tpmsfill::detail {

inline constexpr std::size_t kHugePageBytes = std::size_t{2} << 20;

/// Asks for huge pages on the whole 2 MB pages inside [p, p + bytes), before they are first
/// touched. Advice is a hint: its result is ignored.
inline void advise_huge_pages(const void* p, std::size_t bytes) {
  constexpr std::uintptr_t kHuge = kHugePageBytes;
  const auto begin = reinterpret_cast<std::uintptr_t>(p);
  const std::uintptr_t first = (begin + kHuge - 1) / kHuge * kHuge;
  const std::uintptr_t last = (begin + bytes) / kHuge * kHuge;
  if (last > first) (void)::madvise(reinterpret_cast<void*>(first), last - first, MADV_HUGEPAGE);
}

/// v.resize(n); when `v` is empty, its new storage is advised to use huge pages before it is
/// zeroed (a vector that grows keeps resize's own growth, so appending stays linear). Small
/// buffers (below 4 MB) are left as they are.
template <class T>
void resize_on_huge_pages(std::vector<T>& v, std::size_t n) {
  const std::size_t bytes = n * sizeof(T);
  if (v.empty() && bytes >= 2 * kHugePageBytes) {
    v.reserve(n);
    advise_huge_pages(v.data(), bytes);
  }
  v.resize(n);
}

/// std::vector<T>(n) on huge pages (resize_on_huge_pages).
template <class T>
std::vector<T> grid_buffer(std::size_t n) {
  std::vector<T> v;
  resize_on_huge_pages(v, n);
  return v;
}

}  // namespace tpmsfill::detail
