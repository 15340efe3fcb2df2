// Every large C++ allocation of the `tpmsfill` process on huge pages where the kernel offers
// them on request: the replaceable global operator new and delete (so the library, CGAL's
// tree and the standard containers all use them).
//
// Why: a job's arrays are hundreds of MB of fresh memory (the soup, the search tree's nodes and
// primitives, the grids), and on a machine whose transparent huge pages are given only on
// request ("madvise") every 4 KB page of them costs a page fault on first touch. On the 2-core
// development machine those faults were the largest item of the tube's read and index stages
// (docs/benchmarks.md §32). The library advises its own grids (core/grid_buffer.hpp); what it
// cannot reach, a program can: advise every block of 4 MB or more as it is allocated.
// Where the blocks live changes, never their contents: outputs are identical.
#if !defined(__SANITIZE_ADDRESS__) && !defined(TPMSFILL_NO_HUGE_PAGE_NEW)

#include <cstddef>
#include <cstdlib>
#include <new>

#include "core/grid_buffer.hpp"

namespace {

void* allocate(std::size_t bytes) {
  void* p = std::malloc(bytes == 0 ? 1 : bytes);
  using namespace tpmsfill::detail;
  if (p != nullptr && bytes >= 2 * kHugePageBytes) advise_huge_pages(p, bytes);
  return p;
}

}  // namespace

// The standard's loop: on failure call the new-handler, if any, and try again.
void* operator new(std::size_t bytes) {
  for (;;) {
    if (void* p = allocate(bytes)) return p;
    std::new_handler handler = std::get_new_handler();
    if (handler == nullptr) throw std::bad_alloc();
    handler();
  }
}

void* operator new[](std::size_t bytes) {
  return ::operator new(bytes);
}

void operator delete(void* p) noexcept {
  std::free(p);
}
void operator delete[](void* p) noexcept {
  std::free(p);
}
void operator delete(void* p, std::size_t) noexcept {
  std::free(p);
}
void operator delete[](void* p, std::size_t) noexcept {
  std::free(p);
}

#endif
