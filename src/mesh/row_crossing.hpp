/// @file row_crossing.hpp
/// @brief Does the line {(x, y, z) : x ∈ ℝ} cross a triangle, and in which direction? Decided
/// exactly (CGAL Epick orientation) with a fixed tie-break, so every line crosses a closed
/// surface an even number of times. Shared by classify (one line per grid row) and clean
/// (whether one piece lies inside another).
///
/// The perturbation. The line's point p = (y, z) is moved to p' = (y + ε, z + ε²), 0 < ε ≪ 1.
/// For an edge (a, b) of a projected triangle, orientation(a, b, p') is the sign of
///   (b.y − a.y)(p.z + ε² − a.z) − (b.z − a.z)(p.y + ε − a.y)
/// = orientation(a, b, p) + (a.z − b.z)·ε + (b.y − a.y)·ε²,
/// so where orientation(a, b, p) = 0 it is sign(a.z − b.z) when a.z ≠ b.z, else
/// sign(b.y − a.y) (never 0: a ≠ b for an edge of a non-degenerate projected triangle).
/// p' lies on no line through two distinct input points, so it is strictly inside or strictly
/// outside every projected triangle of non-zero area: an edge shared by two triangles on
/// opposite sides is counted by exactly one, a vertex by exactly one of its fan, and a
/// triangle seen edge-on (zero projected area) by none.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>

#include "mesh/cgal_types.hpp"

namespace tpmsfill::detail {

/// A crossing of the +x line with a triangle: where, and +1 when the line passes from the
/// triangle's front (the side its normal points to) to its back (entering a closed outward
/// shell: the winding number goes up by one), −1 the other way.
struct RowCrossing {
  double x = 0;
  int sign = 0;
  bool cap = false;  ///< the triangle is a hole cap (set by the caller)
};

/// Does the perturbed point p' lie strictly left of a → b (points in the yz plane)?
inline bool left_of_perturbed(const Kernel::Point_2& a, const Kernel::Point_2& b,
                              const Kernel::Point_2& p) {
  switch (CGAL::orientation(a, b, p)) {
    case CGAL::LEFT_TURN:
      return true;
    case CGAL::RIGHT_TURN:
      return false;
    default:
      if (a.y() != b.y()) return a.y() > b.y();  // sign(a.z − b.z), z is Point_2::y()
      return b.x() > a.x();                      // sign(b.y − a.y), y is Point_2::x()
  }
}

/// Crossing of the perturbed line through (y, z) with triangle v (corners in winding order),
/// or sign 0 when it misses. x is computed in double by barycentric weights (exact when the
/// corners share one x, clamped to the corners' range).
inline RowCrossing row_crossing(const std::array<Vec3, 3>& v, double y, double z) {
  // Cheap exact rejection: the perturbed point needs y ∈ [min, max) and z ∈ [min, max).
  if (y < std::fmin(std::fmin(v[0].y, v[1].y), v[2].y) ||
      y >= std::fmax(std::fmax(v[0].y, v[1].y), v[2].y) ||
      z < std::fmin(std::fmin(v[0].z, v[1].z), v[2].z) ||
      z >= std::fmax(std::fmax(v[0].z, v[1].z), v[2].z))
    return {};
  using Point2 = Kernel::Point_2;
  int ia = 0, ib = 1, ic = 2;
  Point2 a(v[ia].y, v[ia].z), b(v[ib].y, v[ib].z), c(v[ic].y, v[ic].z);
  const CGAL::Orientation o = CGAL::orientation(a, b, c);
  if (o == CGAL::COLLINEAR) return {};  // seen edge-on: never a crossing
  // Counter-clockwise in (y, z) means the normal has a positive x component: the +x line
  // leaves through the front side.
  const int sign = o == CGAL::COUNTERCLOCKWISE ? -1 : 1;
  if (o == CGAL::CLOCKWISE) {
    std::swap(b, c);
    std::swap(ib, ic);
  }
  const Point2 p(y, z);
  if (!left_of_perturbed(a, b, p) || !left_of_perturbed(b, c, p) || !left_of_perturbed(c, a, p))
    return {};
  auto area2 = [](double ay, double az, double by, double bz, double cy, double cz) {
    return (by - ay) * (cz - az) - (bz - az) * (cy - ay);
  };
  const Vec3 &A = v[ia], &B = v[ib], &C = v[ic];
  const double total = area2(A.y, A.z, B.y, B.z, C.y, C.z);
  const double wb = area2(A.y, A.z, y, z, C.y, C.z) / total;  // weight of B
  const double wc = area2(A.y, A.z, B.y, B.z, y, z) / total;  // weight of C
  double x = A.x + (wb * (B.x - A.x) + wc * (C.x - A.x));
  x = std::clamp(x, std::fmin(std::fmin(A.x, B.x), C.x), std::fmax(std::fmax(A.x, B.x), C.x));
  return {x, sign};
}

/// Does the ray from p along +x (p itself excluded, the line perturbed as above) cross
/// triangle v? Exact: the side of p against the triangle's plane decides, not the computed x.
inline bool ray_crosses(const std::array<Vec3, 3>& v, const Vec3& p) {
  const RowCrossing c = row_crossing(v, p.y, p.z);
  if (c.sign == 0) return false;
  // The crossing lies at x > p.x when p is on the front side of a triangle the line enters
  // (sign +1) or on the back side of one it leaves.
  const CGAL::Orientation side = CGAL::orientation(to_cgal(v[0]), to_cgal(v[1]), to_cgal(v[2]),
                                                   to_cgal(p));  // POSITIVE: in front
  if (side == CGAL::COPLANAR) return false;
  return (side == CGAL::POSITIVE) == (c.sign > 0);
}

}  // namespace tpmsfill::detail
