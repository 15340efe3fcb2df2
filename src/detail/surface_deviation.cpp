// Surface-to-surface distances by CGAL's AABB tree over the target's triangles.
#include "detail/surface_deviation.hpp"

#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_tree.h>
#include <CGAL/AABB_triangle_primitive.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <vector>

#include "detail/cgal_types.hpp"
#include "detail/parallel.hpp"

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

}  // namespace

DistanceStats surface_distances(const TriangleSoup& from, const TriangleSoup& to, bool skip_inside,
                                int grid, std::size_t max_samples) {
  std::vector<Triangle3> target;
  target.reserve(to.triangles.size());
  for (const Triangle& t : to.triangles) {
    const Point3 a = to_cgal(to.points[t[0]]), b = to_cgal(to.points[t[1]]),
                 c = to_cgal(to.points[t[2]]);
    if (!CGAL::collinear(a, b, c)) target.emplace_back(a, b, c);  // exact: no degenerate
  }
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
    for (std::size_t i = begin; i < end; ++i) {
      const Triangle& t = from.triangles[i * stride];
      const Vec3 a = from.points[t[0]], b = from.points[t[1]], c = from.points[t[2]];
      for (std::size_t k = 0; k < per; ++k) {
        const std::array<double, 3>& w = weights[k];
        const Point3 p = to_cgal(w[0] * a + w[1] * b + w[2] * c);
        const double distance = std::sqrt(CGAL::to_double(tree.squared_distance(p)));
        d[per * i + k] = skip_inside && distance > 0 && inside(p) ? NAN : distance;
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
