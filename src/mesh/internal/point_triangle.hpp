/// @file point_triangle.hpp
/// @brief Squared distance from a point to a triangle, in double arithmetic: the closest point
/// is found by the Voronoi region of the triangle's features (three corners, three edges, the
/// face) the point falls in. Arithmetic only (no yes/no decision rests on it beyond a
/// distance compared with a tolerance), so plain doubles; degenerate triangles are fine (the
/// closest point then lies on an edge).
#pragma once

#include "tpmsfill/types.hpp"

namespace tpmsfill::detail {

inline double squared_distance_to_triangle(Vec3 p, Vec3 a, Vec3 b, Vec3 c) {
  const Vec3 ab = b - a, ac = c - a, ap = p - a;
  auto squared = [&](Vec3 q) { return dot(p - q, p - q); };
  const Vec3 n = cross(ab, ac);
  if (!(dot(n, n) > 0)) {  // degenerate (collinear or repeated corners): the nearest edge
    auto segment = [&](Vec3 s, Vec3 t) {
      const Vec3 st = t - s;
      const double len2 = dot(st, st);
      double u = len2 > 0 ? dot(p - s, st) / len2 : 0;
      u = u < 0 ? 0 : (u > 1 ? 1 : u);
      return squared(s + u * st);
    };
    const double x = segment(a, b), y = segment(b, c), z = segment(c, a);
    return x < y ? (x < z ? x : z) : (y < z ? y : z);
  }
  const double d1 = dot(ab, ap), d2 = dot(ac, ap);
  if (d1 <= 0 && d2 <= 0) return squared(a);
  const Vec3 bp = p - b;
  const double d3 = dot(ab, bp), d4 = dot(ac, bp);
  if (d3 >= 0 && d4 <= d3) return squared(b);
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0 && d1 >= 0 && d3 <= 0) return squared(a + (d1 / (d1 - d3)) * ab);
  const Vec3 cp = p - c;
  const double d5 = dot(ab, cp), d6 = dot(ac, cp);
  if (d6 >= 0 && d5 <= d6) return squared(c);
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0 && d2 >= 0 && d6 <= 0) return squared(a + (d2 / (d2 - d6)) * ac);
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0 && d4 - d3 >= 0 && d5 - d6 >= 0)
    return squared(b + ((d4 - d3) / ((d4 - d3) + (d5 - d6))) * (c - b));
  const double sum = va + vb + vc;
  const double v = vb / sum, w = vc / sum;
  return squared(a + v * ab + w * ac);
}

}  // namespace tpmsfill::detail
