#include "io/internal/triangulate_polygon.hpp"

#include <algorithm>
#include <cmath>
#include <cstddef>

namespace tpmsfill::detail {
namespace {

struct Point2 {
  double x, y;
};

double orient(Point2 a, Point2 b, Point2 c) {
  return (b.x - a.x) * (c.y - a.y) - (b.y - a.y) * (c.x - a.x);
}

// Closed test: a point on the boundary of the ear blocks it, so an ear never swallows a corner
// that touches it (a pinch, a collinear run) and the result never overlaps itself.
bool in_closed_triangle(Point2 p, Point2 a, Point2 b, Point2 c) {
  return orient(a, b, p) >= 0 && orient(b, c, p) >= 0 && orient(c, a, p) >= 0;
}

void fan(std::span<const std::uint32_t> polygon, std::vector<Triangle>& out) {
  for (std::size_t i = 1; i + 1 < polygon.size(); ++i)
    out.push_back({polygon[0], polygon[i], polygon[i + 1]});
}

// Newell's normal: exact for planar polygons, the best-fit plane's normal for non-planar ones,
// and its direction follows the winding even for concave outlines.
Vec3 newell_normal(std::span<const Vec3> points, std::span<const std::uint32_t> polygon) {
  Vec3 n;
  const Vec3 origin = points[polygon[0]];
  for (std::size_t i = 0; i < polygon.size(); ++i) {
    const Vec3 a = points[polygon[i]] - origin;
    const Vec3 b = points[polygon[(i + 1) % polygon.size()]] - origin;
    n.x += (a.y - b.y) * (a.z + b.z);
    n.y += (a.z - b.z) * (a.x + b.x);
    n.z += (a.x - b.x) * (a.y + b.y);
  }
  return n;
}

bool has_repeated_index(std::span<const std::uint32_t> polygon) {
  std::vector<std::uint32_t> sorted(polygon.begin(), polygon.end());
  std::sort(sorted.begin(), sorted.end());
  return std::adjacent_find(sorted.begin(), sorted.end()) != sorted.end();
}

// Point-in-triangle tests allowed per polygon before giving up on clipping: 16 n^2 (plus a
// floor) is far above what real polygons need, and keeps a file full of badly concave polygons
// (fuzzers make them) from taking cubic time.
std::size_t test_budget(std::size_t n) {
  return std::min<std::size_t>(std::size_t{1} << 25, (std::size_t{1} << 16) + 16 * n * n);
}

bool ear_clip(std::span<const Vec3> points, std::span<const std::uint32_t> polygon, Vec3 normal,
              std::vector<Triangle>& out) {
  const std::size_t n = polygon.size();
  // Orthonormal (u, v) with u x v along the normal: counter-clockwise about the normal stays
  // counter-clockwise in the plane.
  const Vec3 nn = (1.0 / norm(normal)) * normal;
  const Vec3 axis = std::fabs(nn.x) <= std::fabs(nn.y) && std::fabs(nn.x) <= std::fabs(nn.z)
                        ? Vec3{1, 0, 0}
                        : (std::fabs(nn.y) <= std::fabs(nn.z) ? Vec3{0, 1, 0} : Vec3{0, 0, 1});
  Vec3 u = cross(axis, nn);
  u = (1.0 / norm(u)) * u;
  const Vec3 v = cross(nn, u);
  const Vec3 origin = points[polygon[0]];
  std::vector<Point2> p(n);
  for (std::size_t i = 0; i < n; ++i) {
    const Vec3 d = points[polygon[i]] - origin;
    p[i] = {dot(d, u), dot(d, v)};
  }

  std::vector<std::size_t> prev(n), next(n);
  for (std::size_t i = 0; i < n; ++i) {
    prev[i] = (i + n - 1) % n;
    next[i] = (i + 1) % n;
  }
  // Only corners that are not strictly convex can lie inside an ear of a simple polygon.
  std::vector<char> reflex(n);
  std::vector<std::size_t> reflex_list;
  auto classify = [&](std::size_t i) {
    const bool r = orient(p[prev[i]], p[i], p[next[i]]) <= 0;
    if (r && !reflex[i]) reflex_list.push_back(i);
    if (!r && reflex[i]) std::erase(reflex_list, i);
    reflex[i] = r;
  };
  for (std::size_t i = 0; i < n; ++i) classify(i);

  std::size_t budget = test_budget(n);
  auto is_ear = [&](std::size_t i) {
    if (reflex[i]) return false;
    const std::size_t a = prev[i], c = next[i];
    for (std::size_t r : reflex_list) {
      if (r == a || r == i || r == c) continue;
      if (budget == 0) return false;
      --budget;
      if (in_closed_triangle(p[r], p[a], p[i], p[c])) return false;
    }
    return true;
  };

  const std::size_t first = out.size();
  std::size_t remaining = n, cur = 0, misses = 0;
  while (remaining > 3) {
    if (is_ear(cur)) {
      const std::size_t a = prev[cur], c = next[cur];
      out.push_back({polygon[a], polygon[cur], polygon[c]});
      next[a] = c;
      prev[c] = a;
      if (reflex[cur]) std::erase(reflex_list, cur);
      --remaining;
      classify(a);
      classify(c);
      cur = a;
      misses = 0;
    } else {
      cur = next[cur];
      if (++misses > remaining || budget == 0) {
        out.resize(first);
        return false;
      }
    }
  }
  out.push_back({polygon[prev[cur]], polygon[cur], polygon[next[cur]]});
  return true;
}

}  // namespace

bool triangulate_polygon(std::span<const Vec3> points, std::span<const std::uint32_t> polygon,
                         std::vector<Triangle>& out) {
  if (polygon.size() == 3) {
    out.push_back({polygon[0], polygon[1], polygon[2]});
    return true;
  }
  const Vec3 normal = newell_normal(points, polygon);
  const double length = norm(normal);
  if (!(length > 0) || !std::isfinite(length) || has_repeated_index(polygon) ||
      !ear_clip(points, polygon, normal, out)) {
    fan(polygon, out);
    return false;
  }
  return true;
}

}  // namespace tpmsfill::detail
