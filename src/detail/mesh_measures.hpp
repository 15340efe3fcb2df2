/// @file mesh_measures.hpp
/// @brief The one formula for a triangle's signed volume and area, shared by the stages that
/// sum them (check, clean, validate, components, repair, the cap winding's patches).
///
/// Every caller sums these in its own order; the formulas themselves are written once, in one
/// operation order, so each sum rounds exactly as it did when it was written inline.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <vector>

#include "tpmsfill/types.hpp"

namespace tpmsfill::detail {

/// Six times the signed volume of the tetrahedron (o, a, b, c): (a − o)·((b − o) × (c − o)).
/// Summed over a closed, outward mesh (any o) it is six times the enclosed volume; a nearby
/// o (the bounding box's centre) keeps the terms small.
inline double six_volume(Vec3 o, Vec3 a, Vec3 b, Vec3 c) {
  return dot(a - o, cross(b - o, c - o));
}

/// Twice the area of triangle (a, b, c): |(b − a) × (c − a)|.
inline double double_area(Vec3 a, Vec3 b, Vec3 c) {
  return norm(cross(b - a, c - a));
}

/// six_volume() of triangle t of `mesh` about `o`.
inline double six_volume(const TriangleSoup& mesh, const Triangle& t, Vec3 o) {
  return six_volume(o, mesh.points[t[0]], mesh.points[t[1]], mesh.points[t[2]]);
}

/// double_area() of triangle t of `mesh`.
inline double double_area(const TriangleSoup& mesh, const Triangle& t) {
  return double_area(mesh.points[t[0]], mesh.points[t[1]], mesh.points[t[2]]);
}

/// Centre of the bounding box of the points with used[i] set (the origin when there are
/// none): where validate and components measure volumes about.
inline Vec3 box_centre(const TriangleSoup& mesh, const std::vector<std::uint8_t>& used) {
  double lo[3] = {std::numeric_limits<double>::infinity(), std::numeric_limits<double>::infinity(),
                  std::numeric_limits<double>::infinity()};
  double hi[3] = {-lo[0], -lo[0], -lo[0]};
  for (std::size_t i = 0; i < mesh.points.size(); ++i)
    if (used[i])
      for (int a = 0; a < 3; ++a) {
        lo[a] = std::min(lo[a], mesh.points[i][a]);
        hi[a] = std::max(hi[a], mesh.points[i][a]);
      }
  if (!(lo[0] <= hi[0])) return {};
  return {0.5 * (lo[0] + hi[0]), 0.5 * (lo[1] + hi[1]), 0.5 * (lo[2] + hi[2])};
}

}  // namespace tpmsfill::detail
