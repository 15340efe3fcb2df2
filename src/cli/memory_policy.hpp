// How the `tpmsfill` process asks glibc to manage its memory: one job a process, whose stages
// allocate, free and allocate again arrays of hundreds of MB.
#pragma once

#if defined(__GLIBC__)
#include <malloc.h>
#endif
#include <climits>

namespace tpmsfill::cli {

/// Freed memory stays in the heap (no mmap below 1 GiB, no trimming), so each stage's grid
/// arrays reuse resident pages instead of faulting in fresh zeroed ones: a sixth of a femur
/// job's time at 0.05 mm went to page faults (docs/benchmarks.md, section 17). Under --memory
/// too: a job in slabs allocates the same arrays slab after slab, and returning them at once
/// made every slab fault its arrays in afresh (the femur at 1.1·10⁹ samples under --memory 2G:
/// 37 s so, 18 s reusing them, its peak 1.03 against 1.57 GB; section 32). Called once, first
/// thing in main().
inline void keep_freed_memory() {
#if defined(__GLIBC__)
  mallopt(M_MMAP_THRESHOLD, 1 << 30);
  mallopt(M_TRIM_THRESHOLD, INT_MAX);
#endif
}

/// Returns what is free in the heap to the system. After reading a large input: its bytes
/// and any transient copies are freed, and the stages that follow would otherwise stack their
/// own arrays on top of those resident holes (peak memory on a 4.7·10⁶-triangle STL).
inline void release_freed_memory() {
#if defined(__GLIBC__)
  malloc_trim(0);
#endif
}

}  // namespace tpmsfill::cli
