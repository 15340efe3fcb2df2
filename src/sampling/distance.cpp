// Stage "distance": unsigned distance to the nearest triangle by a best-first walk of the AABB
// trees (AABB_tree::traversal_with_priority with our traits), signed by the occupancy mask.
//
// Why not AABB_tree::closest_point_and_primitive: where the nearest point is a vertex or an
// edge shared by several triangles (the common case next to a finely tessellated surface),
// CGAL reports whichever tied triangle its walk meets first, so the double-rounded distance
// could differ by an ulp with the hint, the thread split or the tree shape. Here the answer is
// min over all triangles t of squared_distance(p, t), one fixed double formula per
// (point, triangle): a minimum does not depend on the order it is taken in. The walk prunes a
// box only when it is farther than the best so far plus a rounding slack, so the triangle that
// attains the minimum is never pruned. Hints (the previous node's nearest triangle) only
// tighten the first bound.
#include "tpmsfill/sampling/distance.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>
#include <utility>

#include "core/index_limits.hpp"
#include "core/parallel.hpp"
#include "core/stage_progress.hpp"
#include "sampling/internal/mesh_index_impl.hpp"
#include "tpmsfill/error.hpp"

namespace tpmsfill {
namespace {

using detail::TreeNode;
using detail::TrianglePrimitive;

/// p minus its nearest point on triangle abc (Ericson, Real-Time Collision Detection, 5.1.5),
/// in double. Degenerate (collinear) triangles fall into the edge/vertex regions.
Vec3 offset_from_triangle(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c) {
  const Vec3 ab = b - a, ac = c - a, ap = p - a;
  const double d1 = dot(ab, ap), d2 = dot(ac, ap);
  if (d1 <= 0 && d2 <= 0) return ap;  // vertex a
  const Vec3 bp = p - b;
  const double d3 = dot(ab, bp), d4 = dot(ac, bp);
  if (d3 >= 0 && d4 <= d3) return bp;  // vertex b
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0 && d1 >= 0 && d3 <= 0) {  // edge ab
    const double t = d1 / (d1 - d3);
    return ap - t * ab;
  }
  const Vec3 cp = p - c;
  const double d5 = dot(ab, cp), d6 = dot(ac, cp);
  if (d6 >= 0 && d5 <= d6) return cp;  // vertex c
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0 && d2 >= 0 && d6 <= 0) {  // edge ac
    const double t = d2 / (d2 - d6);
    return ap - t * ac;
  }
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0) {  // edge bc
    const double t = (d4 - d3) / ((d4 - d3) + (d5 - d6));
    return bp - t * (c - b);
  }
  const double sum = va + vb + vc;
  if (!(sum > 0)) {  // degenerate triangle that slipped through: nearest of the three edges
    auto seg = [&](const Vec3& s, const Vec3& e) {
      const Vec3 d = e - s, sp = p - s;
      const double len2 = dot(d, d);
      const double t = len2 > 0 ? std::clamp(dot(sp, d) / len2, 0.0, 1.0) : 0.0;
      return sp - t * d;
    };
    const Vec3 o[3] = {seg(a, b), seg(b, c), seg(c, a)};
    const auto nearer = [](const Vec3& x, const Vec3& y) { return dot(x, x) < dot(y, y); };
    return *std::min_element(o, o + 3, nearer);
  }
  const double v = vb / sum, w = vc / sum;  // interior: p minus its projection
  return ap - v * ab - w * ac;
}

/// Squared distance from p to triangle abc.
double squared_distance(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c) {
  const Vec3 o = offset_from_triangle(p, a, b, c);
  return dot(o, o);
}

double box_gap(double x, double lo, double hi) {
  return x < lo ? lo - x : (x > hi ? x - hi : 0.0);
}

/// Squared distance from p to a box (0 inside).
double squared_distance(const Vec3& p, const CGAL::Bbox_3& b) {
  const double dx = box_gap(p.x, b.xmin(), b.xmax()), dy = box_gap(p.y, b.ymin(), b.ymax()),
               dz = box_gap(p.z, b.zmin(), b.zmax());
  return dx * dx + dy * dy + dz * dz;
}

/// Squared distance from p to a triangle's bounding box (0 inside).
double squared_distance_to_box(const Vec3& p, const std::array<Vec3, 3>& v) {
  double sum = 0;
  for (int a = 0; a < 3; ++a) {
    const auto [lo, hi] = detail::corner_range(v, a);
    const double g = box_gap(p[a], lo, hi);
    sum += g * g;
  }
  return sum;
}

/// Traversal traits (AABB_tree::traversal_with_priority): nearest box first, prune boxes
/// beyond the best distance plus `slack_` mm.
class Nearest {
 public:
  using Priority = double;  // higher first: minus the squared box distance

  Nearest(const detail::MeshIndexAccess::Impl& index, double slack)
      : triangles_(index.triangles), order_(index.order.data()), slack_(slack) {}

  /// Starts a query at p, bounded by triangle `hint` when it is not detail::kNoIndex.
  void start(const Vec3& p, std::uint32_t hint) {
    best_ = std::numeric_limits<double>::infinity();
    bound_ = best_;
    best_id_ = detail::kNoIndex;
    if (hint != detail::kNoIndex) consider(p, hint);
  }

  bool go_further() const { return true; }
  bool do_intersect(const Vec3& p, const TreeNode& node) const {
    return squared_distance(p, node.bbox()) <= bound_;
  }
  std::pair<bool, double> do_intersect_with_priority(const Vec3& p, const TreeNode& node) const {
    const double d = squared_distance(p, node.bbox());
    return {d <= bound_, -d};
  }
  // A bucket's triangles are tested as the tree tests its boxes first: one beyond the bound
  // by its own box cannot be the nearest (the slack covers the box formula's rounding).
  void intersection(const Vec3& p, const TrianglePrimitive& primitive) {
    primitive.for_each_triangle(order_, [&](std::uint32_t id) {
      const std::array<Vec3, 3> v = triangles_[id];
      if (squared_distance_to_box(p, v) <= bound_) consider(p, id, v);
    });
  }

  double best() const { return best_; }
  std::uint32_t best_id() const { return best_id_; }

 private:
  void consider(const Vec3& p, std::uint32_t id) { consider(p, id, triangles_[id]); }
  void consider(const Vec3& p, std::uint32_t id, const std::array<Vec3, 3>& v) {
    const double d = squared_distance(p, v[0], v[1], v[2]);
    if (d < best_ || (d == best_ && id < best_id_)) {
      best_ = d;
      best_id_ = id;
      const double r = std::sqrt(d) + slack_;
      bound_ = r * r;
    }
  }

  const detail::TriangleArray& triangles_;
  const std::uint32_t* order_;
  double slack_;
  double best_ = 0, bound_ = 0;
  std::uint32_t best_id_ = detail::kNoIndex;
};

// The walk's rounding slack for points within `reach` mm of the origin: the point-triangle
// and point-box formulas round far below 1e-9 of the largest coordinate, and a box is pruned
// only beyond best + slack, so the minimiser always survives.
double rounding_slack(double reach) {
  return 1e-9 * (reach + 1.0);
}

/// Nodes per chunk: the unit of parallel work and of hint reuse (fixed, so that the visiting
/// order inside a chunk does not depend on the thread count; the result would not either).
constexpr std::size_t kChunk = 512;

/// Signed distances at nodes node_of(0..n-1) into out[0..n-1].
template <class NodeOf>
void compute(const MeshIndex& index, const Mask& inside, std::size_t n, const NodeOf& node_of,
             float* out, const DistanceOptions& options) {
  const auto& impl = detail::MeshIndexAccess::impl(index);
  const Grid& grid = inside.grid;
  const std::size_t nx = static_cast<std::size_t>(grid.dims[0]);
  const std::size_t ny = static_cast<std::size_t>(grid.dims[1]);
  double reach = impl.magnitude;
  for (int a = 0; a < 3; ++a)
    reach = std::max({reach, std::fabs(grid.coordinate(a, 0)),
                      std::fabs(grid.coordinate(a, std::max(grid.dims[a] - 1, 0)))});
  const double slack = rounding_slack(reach);

  const std::size_t chunks = (n + kChunk - 1) / kChunk;
  detail::ProgressCounter progress(options.progress, "distance", n);
  detail::parallel_for(chunks, 1, [&](std::size_t cb, std::size_t ce) {
    Nearest nearest(impl, slack);
    // Hints: the previous node's answer when it is the x-neighbour, else the last answer in
    // the same grid column (i) of this chunk, usually one row (one voxel in y) away. Band
    // nodes come in short runs across each wall, so "the previous node" alone is often on
    // the other wall.
    std::vector<std::uint32_t> column(nx, detail::kNoIndex);
    for (std::size_t c = cb; c < ce; ++c) {
      std::fill(column.begin(), column.end(), detail::kNoIndex);
      std::uint32_t hint = detail::kNoIndex;
      std::uint64_t previous = ~std::uint64_t{0};
      const std::size_t end = std::min(n, (c + 1) * kChunk);
      for (std::size_t q = c * kChunk; q < end; ++q) {
        const std::uint64_t node = node_of(q);
        const auto i = static_cast<int>(node % nx);
        const auto j = static_cast<int>((node / nx) % ny);
        const auto k = static_cast<int>(node / (nx * ny));
        const Vec3 p = grid.node(i, j, k);
        if (node != previous + 1 || hint == detail::kNoIndex)
          hint = column[static_cast<std::size_t>(i)];
        nearest.start(p, options.reuse_hints ? hint : detail::kNoIndex);
        for (const auto& tree : impl.trees) tree->traversal_with_priority(p, nearest);
        hint = nearest.best_id();
        column[static_cast<std::size_t>(i)] = hint;
        previous = node;
        const auto d = static_cast<float>(std::sqrt(nearest.best()));
        out[q] = inside.values[node] ? -d : d;
      }
      progress.add(end - c * kChunk);
    }
  });
  progress.finish();
}

void require_mask(const Mask& inside) {
  if (inside.values.size() != inside.grid.node_count())
    throw InputError("the occupancy mask has " + std::to_string(inside.values.size()) +
                     " values for " + std::to_string(inside.grid.node_count()) + " grid nodes");
}

}  // namespace

std::vector<Vec3> closest_points(const MeshIndex& index, const std::vector<Vec3>& points) {
  const auto& impl = detail::MeshIndexAccess::impl(index);
  double reach = impl.magnitude;
  for (std::size_t q = 0; q < points.size(); ++q) {
    const Vec3 p = points[q];
    if (!(std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z)))
      throw InputError("closest_points: point " + std::to_string(q) + " is not finite");
    reach = std::max({reach, std::fabs(p.x), std::fabs(p.y), std::fabs(p.z)});
  }
  const double slack = rounding_slack(reach);
  std::vector<Vec3> out(points.size());
  detail::parallel_for(points.size(), kChunk, [&](std::size_t begin, std::size_t end) {
    Nearest nearest(impl, slack);
    for (std::size_t q = begin; q < end; ++q) {
      nearest.start(points[q], detail::kNoIndex);
      for (const auto& tree : impl.trees) tree->traversal_with_priority(points[q], nearest);
      const std::array<Vec3, 3> v = impl.triangles[nearest.best_id()];
      out[q] = points[q] - offset_from_triangle(points[q], v[0], v[1], v[2]);
    }
  });
  return out;
}

std::vector<float> band_distances(const MeshIndex& index, const Mask& inside, const Band& band,
                                  const DistanceOptions& options) {
  if (!(band.grid == inside.grid))
    throw InputError("the band and the occupancy mask live on different grids");
  require_mask(inside);
  const std::size_t nodes = inside.grid.node_count();
  for (std::size_t q = 0; q < band.nodes.size(); ++q)
    if (band.nodes[q] >= nodes)
      throw InputError("band node " + std::to_string(band.nodes[q]) + " is outside the grid (" +
                       std::to_string(nodes) + " nodes)");
  std::vector<float> out(band.nodes.size());
  compute(
      index, inside, band.nodes.size(), [&](std::size_t q) { return band.nodes[q]; }, out.data(),
      options);
  return out;
}

Field signed_distance_field(const MeshIndex& index, const Mask& inside,
                            const DistanceOptions& options) {
  require_mask(inside);
  Field field;
  field.grid = inside.grid;
  field.values.resize(inside.grid.node_count());
  compute(
      index, inside, field.values.size(), [](std::size_t q) { return std::uint64_t{q}; },
      field.values.data(), options);
  return field;
}

}  // namespace tpmsfill
