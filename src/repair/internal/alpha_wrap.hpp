// CGAL's 3D alpha wrapping (CGAL/alpha_wrap_3.h) behind a plain-data call. It lives in its
// own translation unit (src/repair/repair_wrap.cpp) because it is one of CGAL's slowest headers to
// compile, and it can then compile beside src/repair/repair.cpp.
#pragma once

#include "tpmsfill/types.hpp"

namespace tpmsfill::detail {

/// The alpha wrap of `soup` (repeated-corner triangles are ignored): a closed, outward,
/// 2-manifold mesh without self-intersections that encloses the soup at about `offset` mm.
/// Preconditions: alpha > 0, offset > 0, indices in range.
TriangleSoup alpha_wrap(const TriangleSoup& soup, double alpha, double offset);

}  // namespace tpmsfill::detail
