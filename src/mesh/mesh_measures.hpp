/// @file mesh_measures.hpp
/// @brief The one formula for a triangle's signed volume and area, shared by the stages that
/// sum them (check, clean, validate, components, repair, the cap winding's patches).
///
/// Every caller sums these in its own order; the formulas themselves are written once, in one
/// operation order, so each sum rounds exactly as it did when it was written inline.
#pragma once

#include <cmath>
#include <cstdint>
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
  Box3 box;
  for (std::size_t i = 0; i < mesh.points.size(); ++i)
    if (used[i]) box.extend(mesh.points[i]);
  return box.centre();
}

}  // namespace tpmsfill::detail
