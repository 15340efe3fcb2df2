/// @file surface_normals.hpp
/// @brief Angle-weighted vertex normals of a surface, per position: points with bit-identical
/// coordinates (a seam's two copies) get the same normal. Shared by the conformal stage's two
/// maps (conformal.cpp, vertex_map.cpp).
#pragma once

#include <array>
#include <cmath>
#include <cstdint>
#include <map>
#include <vector>

#include "tpmsfill/types.hpp"

namespace tpmsfill::detail {

inline Vec3 unit_or_zero(Vec3 v) {
  const double n = norm(v);
  return n > 0 ? (1 / n) * v : v;
}

inline std::vector<Vec3> angle_weighted_normals(const TriangleSoup& m) {
  std::map<std::array<double, 3>, Vec3> at;
  auto pos = [&](std::uint32_t i) {
    const Vec3 p = m.points[i];
    return std::array<double, 3>{p.x, p.y, p.z};
  };
  for (const Triangle& t : m.triangles) {
    const Vec3 n =
        unit_or_zero(cross(m.points[t[1]] - m.points[t[0]], m.points[t[2]] - m.points[t[0]]));
    for (int c = 0; c < 3; ++c) {
      const Vec3 a = m.points[t[(c + 1) % 3]] - m.points[t[c]],
                 b = m.points[t[(c + 2) % 3]] - m.points[t[c]];
      at[pos(t[c])] = at[pos(t[c])] + std::atan2(norm(cross(a, b)), dot(a, b)) * n;
    }
  }
  std::vector<Vec3> normals(m.points.size());
  for (std::size_t i = 0; i < m.points.size(); ++i)
    normals[i] = unit_or_zero(at[pos(static_cast<std::uint32_t>(i))]);
  return normals;
}

}  // namespace tpmsfill::detail
