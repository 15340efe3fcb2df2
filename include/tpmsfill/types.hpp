/// @file types.hpp
/// @brief Plain data passed between pipeline stages: points, boxes and triangle soups.
///
/// All lengths are millimetres. Nothing here owns behaviour beyond small arithmetic helpers:
/// stages are free functions over these values (see the headers named after each stage).
#pragma once

#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <vector>

namespace tpmsfill {

/// A point or vector in millimetres.
struct Vec3 {
  double x = 0, y = 0, z = 0;

  friend bool operator==(const Vec3&, const Vec3&) = default;
  friend Vec3 operator+(Vec3 a, Vec3 b) { return {a.x + b.x, a.y + b.y, a.z + b.z}; }
  friend Vec3 operator-(Vec3 a, Vec3 b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
  friend Vec3 operator*(double s, Vec3 a) { return {s * a.x, s * a.y, s * a.z}; }
  double operator[](int axis) const { return axis == 0 ? x : (axis == 1 ? y : z); }
};

inline double dot(Vec3 a, Vec3 b) {
  return a.x * b.x + a.y * b.y + a.z * b.z;
}
inline Vec3 cross(Vec3 a, Vec3 b) {
  return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
inline double norm(Vec3 a) {
  return std::sqrt(dot(a, a));
}

/// Axis-aligned box. Default-constructed it is empty (min > max), so extend() works from it.
struct Box3 {
  Vec3 min{std::numeric_limits<double>::infinity(), std::numeric_limits<double>::infinity(),
           std::numeric_limits<double>::infinity()};
  Vec3 max{-std::numeric_limits<double>::infinity(), -std::numeric_limits<double>::infinity(),
           -std::numeric_limits<double>::infinity()};

  bool empty() const { return !(min.x <= max.x && min.y <= max.y && min.z <= max.z); }
  Vec3 size() const { return empty() ? Vec3{} : max - min; }
  void extend(Vec3 p) {
    min = {std::fmin(min.x, p.x), std::fmin(min.y, p.y), std::fmin(min.z, p.z)};
    max = {std::fmax(max.x, p.x), std::fmax(max.y, p.y), std::fmax(max.z, p.z)};
  }
};

/// Indices of a triangle's three corners into TriangleSoup::points, counter-clockwise seen
/// from outside (right-hand rule: the normal points out of the solid).
using Triangle = std::array<std::uint32_t, 3>;

/// A triangle soup: points and triangles that index them. It promises only that every index
/// is < points.size(); points may repeat (STL stores three per facet), triangles may be
/// degenerate, duplicated, non-manifold or inconsistently oriented. check_mesh() says which.
struct TriangleSoup {
  std::vector<Vec3> points;
  std::vector<Triangle> triangles;
};

/// Bounding box of the points referenced by at least one triangle (empty if there are none).
inline Box3 bounding_box(const TriangleSoup& soup) {
  Box3 box;
  for (const Triangle& t : soup.triangles)
    for (std::uint32_t v : t) box.extend(soup.points[v]);
  return box;
}

}  // namespace tpmsfill
