// Exact orientation signs (exact_orientation.hpp): CGAL Epick's filtered predicates.
#include "mesh/exact_orientation.hpp"

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>

namespace tpmsfill::detail {

namespace {
using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
}

int orientation_3(Vec3 a, Vec3 b, Vec3 c, Vec3 d) {
  using P = Kernel::Point_3;
  return static_cast<int>(
      CGAL::orientation(P(a.x, a.y, a.z), P(b.x, b.y, b.z), P(c.x, c.y, c.z), P(d.x, d.y, d.z)));
}

int orientation_2(std::array<double, 2> a, std::array<double, 2> b, std::array<double, 2> c) {
  using P = Kernel::Point_2;
  return static_cast<int>(CGAL::orientation(P(a[0], a[1]), P(b[0], b[1]), P(c[0], c[1])));
}

}  // namespace tpmsfill::detail
