// Surface-to-surface distances by CGAL's AABB tree over the target's triangles.
#include "mesh/surface_deviation.hpp"

#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_tree.h>
#include <CGAL/AABB_triangle_primitive.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <iterator>
#include <vector>

#include "core/parallel.hpp"
#include "mesh/cgal_types.hpp"

namespace tpmsfill::detail {
namespace {

using Triangle3 = Kernel::Triangle_3;
using Primitive = CGAL::AABB_triangle_primitive<Kernel, std::vector<Triangle3>::const_iterator>;
using Tree = CGAL::AABB_tree<CGAL::AABB_traits<Kernel, Primitive>>;

/// Barycentric weights of a triangle's samples: the grid of order n, then the centroid
/// unless the grid holds it.
std::vector<std::array<double, 3>> sample_weights(int n) {
  std::vector<std::array<double, 3>> w;
  for (int i = 0; i <= n; ++i)
    for (int j = 0; i + j <= n; ++j)
      w.push_back({static_cast<double>(i) / n, static_cast<double>(j) / n,
                   static_cast<double>(n - i - j) / n});
  if (n % 3 != 0) w.push_back({1.0 / 3.0, 1.0 / 3.0, 1.0 / 3.0});
  return w;
}

/// A soup's non-degenerate triangles (exact test), in its order and orientation.
std::vector<Triangle3> proper_triangles(const TriangleSoup& soup) {
  std::vector<Triangle3> out;
  out.reserve(soup.triangles.size());
  for (const Triangle& t : soup.triangles) {
    const Point3 a = to_cgal(soup.points[t[0]]), b = to_cgal(soup.points[t[1]]),
                 c = to_cgal(soup.points[t[2]]);
    if (!CGAL::collinear(a, b, c)) out.emplace_back(a, b, c);
  }
  return out;
}

/// The winding number of a closed soup (its triangles in `tree`) at q: signed crossings of a
/// ray, +1 where the ray leaves through a face (runs along its normal), −1 where it enters.
long winding_number(const Tree& tree, const Point3& q, std::vector<Tree::Primitive_id>& hits) {
  const Kernel::Vector_3 direction(0.5772156649, 0.6180339887, 0.5320888862);
  hits.clear();
  tree.all_intersected_primitives(Kernel::Ray_3(q, direction), std::back_inserter(hits));
  long winding = 0;
  for (const Tree::Primitive_id& id : hits) {
    const Triangle3& w = *id;
    const Kernel::Vector_3 normal =
        CGAL::cross_product(w.vertex(1) - w.vertex(0), w.vertex(2) - w.vertex(0));
    winding += CGAL::to_double(normal * direction) > 0 ? 1 : -1;
  }
  return winding;
}

}  // namespace

DistanceStats surface_distances(const TriangleSoup& from, const TriangleSoup& to, bool skip_inside,
                                int grid, std::size_t max_samples, const TriangleSoup* buried_in) {
  const std::vector<Triangle3> target = proper_triangles(to);
  const std::vector<Triangle3> walls =
      buried_in ? proper_triangles(*buried_in) : std::vector<Triangle3>{};
  Tree solid(walls.begin(), walls.end());
  if (!walls.empty()) solid.build();
  DistanceStats stats;
  if (target.empty() || from.triangles.empty()) return stats;
  Tree tree(target.begin(), target.end());
  tree.accelerate_distance_queries();
  // Both trees are built lazily: build them here, so the parallel queries only read.
  tree.build();
  (void)tree.squared_distance(target.front().vertex(0));

  // The grid's points per triangle, every stride-th triangle.
  const std::vector<std::array<double, 3>> weights = sample_weights(std::max(grid, 1));
  const std::size_t per = weights.size();
  const std::size_t stride =
      std::max<std::size_t>(1, per * from.triangles.size() / std::max<std::size_t>(max_samples, 1));
  const std::size_t used = (from.triangles.size() + stride - 1) / stride;
  // Inside: an odd number of crossings along a ray in a direction no axis-aligned part lines
  // up with. NaN marks a skipped sample.
  const Kernel::Vector_3 direction(0.5772156649, 0.6180339887, 0.5320888862);
  auto inside = [&](const Point3& p) {
    return tree.number_of_intersected_primitives(Kernel::Ray_3(p, direction)) % 2 == 1;
  };
  std::vector<double> d(per * used);
  parallel_for(used, 256, [&](std::size_t begin, std::size_t end) {
    std::vector<Tree::Primitive_id> hits;
    for (std::size_t i = begin; i < end; ++i) {
      const Triangle& t = from.triangles[i * stride];
      const Vec3 a = from.points[t[0]], b = from.points[t[1]], c = from.points[t[2]];
      // Buried: the sample's outer side (a ten-thousandth of the triangle's size along its
      // normal) lies inside the solid.
      const Vec3 normal = cross(b - a, c - a);
      const double length = norm(normal);
      const Vec3 off = length > 0 ? (1e-4 / std::sqrt(length)) * normal : Vec3{};
      for (std::size_t k = 0; k < per; ++k) {
        const std::array<double, 3>& w = weights[k];
        const Vec3 q = w[0] * a + w[1] * b + w[2] * c;
        const Point3 p = to_cgal(q);
        const double distance = std::sqrt(CGAL::to_double(tree.squared_distance(p)));
        const bool skip =
            distance > 0 &&
            ((skip_inside && inside(p)) ||
             (!walls.empty() && length > 0 && winding_number(solid, to_cgal(q + off), hits) >= 1));
        d[per * i + k] = skip ? NAN : distance;
      }
    }
  });
  std::erase_if(d, [](double v) { return std::isnan(v); });
  if (d.empty()) return stats;
  std::sort(d.begin(), d.end());
  stats.samples = d.size();
  stats.max = d.back();
  stats.p95 = d[static_cast<std::size_t>(0.95 * static_cast<double>(d.size() - 1))];
  return stats;
}

}  // namespace tpmsfill::detail
