// Distance fields from a mesh, a point cloud or a CT (scanned_field.hpp).
#include "tpmsfill/scan/scanned_field.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <string>

#include "core/parallel.hpp"
#include "tpmsfill/error.hpp"
#include "tpmsfill/grid.hpp"
#include "tpmsfill/mesh/clean.hpp"
#include "tpmsfill/sampling/classify.hpp"
#include "tpmsfill/sampling/distance.hpp"
#include "tpmsfill/sampling/spatial.hpp"

namespace tpmsfill {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

// The grid of cell centres over `box`, refused with the voxel that fits when too large.
Grid field_grid(const Box3& box, const ScannedFieldOptions& o) {
  if (!(o.voxel > 0) || !std::isfinite(o.voxel)) throw InputError("the voxel size must be > 0");
  if (o.padding < 2) throw InputError("the padding must be at least 2 cells");
  const GridOptions g{.voxel_size = o.voxel, .padding = o.padding};
  const std::uint64_t cells = grid_node_count(box, g);
  if (cells > o.max_cells) {
    char fit[64];
    std::snprintf(fit, sizeof fit, "%.4g mm",
                  o.voxel * std::cbrt(static_cast<double>(cells) / o.max_cells) * 1.01);
    throw ResourceError("the field would have " + std::to_string(cells) + " cells, over the " +
                        "limit of " + std::to_string(o.max_cells) + "; a voxel of " + fit +
                        " or more fits");
  }
  return make_grid(box, g);
}

ScalarVolume volume_on(const Grid& grid, FieldSign sign) {
  ScalarVolume v;
  v.dims = grid.dims;
  v.spacing = {grid.spacing, grid.spacing, grid.spacing};
  v.origin = grid.origin;
  v.sign = sign;
  v.values.resize(grid.node_count());
  return v;
}

// Squared distance transform of one line, f(q) = min_v (s (q − v))² + g(v) (Felzenszwalb &
// Huttenlocher's lower envelope of parabolas, in doubles for an axis's own spacing s).
void envelope(const double* g, int n, std::size_t stride, double s, double* out,
              std::vector<int>& v, std::vector<double>& z) {
  v.assign(n, 0);
  z.assign(n + 1, 0);
  int k = -1;
  for (int q = 0; q < n; ++q) {
    const double gq = g[q * stride];
    if (!std::isfinite(gq)) continue;
    double cut = -kInf;
    while (k >= 0) {
      const int p = v[k];
      const double sp = s * p, sq = s * q;
      cut = ((gq + sq * sq) - (g[p * stride] + sp * sp)) / (2 * (sq - sp));
      if (cut > z[k]) break;
      --k;
    }
    ++k;
    v[k] = q;
    z[k] = k == 0 ? -kInf : cut;
    z[k + 1] = kInf;
  }
  if (k < 0) {
    for (int q = 0; q < n; ++q) out[q * stride] = kInf;
    return;
  }
  for (int q = 0, j = 0; q < n; ++q) {
    while (z[j + 1] < s * q) ++j;
    const double d = s * (q - v[j]);
    out[q * stride] = d * d + g[v[j] * stride];
  }
}

// Squared distance (mm²) from every cell centre to the nearest cell with feature[n] set.
std::vector<double> squared_distance(const std::vector<std::uint8_t>& feature,
                                     std::array<int, 3> dims, std::array<double, 3> spacing) {
  std::vector<double> d(feature.size());
  for (std::size_t n = 0; n < d.size(); ++n) d[n] = feature[n] ? 0 : kInf;
  const std::array<std::size_t, 3> stride{1, std::size_t(dims[0]), std::size_t(dims[0]) * dims[1]};
  for (int axis = 0; axis < 3; ++axis) {
    const int o1 = (axis + 1) % 3, o2 = (axis + 2) % 3;
    detail::parallel_for(std::size_t(dims[o2]), 1, [&](std::size_t begin, std::size_t end) {
      std::vector<int> v;
      std::vector<double> z, line(dims[axis]), out(dims[axis]);
      for (std::size_t i2 = begin; i2 < end; ++i2)
        for (int i1 = 0; i1 < dims[o1]; ++i1) {
          const std::size_t base = i1 * stride[o1] + i2 * stride[o2];
          for (int q = 0; q < dims[axis]; ++q) line[q] = d[base + q * stride[axis]];
          envelope(line.data(), dims[axis], 1, spacing[axis], out.data(), v, z);
          for (int q = 0; q < dims[axis]; ++q) d[base + q * stride[axis]] = out[q];
        }
    });
  }
  return d;
}

// Points in a k-d tree of our own, for exact nearest-point queries: each node splits its
// points at the median along the widest axis of their bounding box, down to leaves of at most
// kLeaf points, stored contiguously. A query visits nodes nearest-first and skips every node
// whose box is no nearer than the best point so far, so its cost depends on the points near
// the answer, not on how far away they are (a uniform bucket grid searched in growing shells
// scans every empty bucket up to the answer) nor on the cloud's shape (flat, collinear).
class PointTree {
 public:
  explicit PointTree(const std::vector<Vec3>& p) : points_(p) {
    nodes_.reserve(2 * (p.size() / kLeaf + 1));
    nodes_.push_back({});
    build(0, 0, static_cast<std::uint32_t>(p.size()));
  }

  // Squared distance to the nearest point, and that point in *nearest; `hint` is a point of
  // the cloud (the neighbouring cell's answer) whose distance bounds the search from the start.
  // The result is the least of the same dot products whatever the order of the visits.
  double nearest(Vec3 q, Vec3 hint, Vec3* nearest) const {
    double best = dot(hint - q, hint - q);
    *nearest = hint;
    struct Visit {
      std::uint32_t node;
      double bound;
    };
    Visit stack[2 * 64];  // depth < 64: every split halves the points
    int top = 0;
    stack[top++] = {0, box_distance(nodes_[0].box, q)};
    while (top > 0) {
      const Visit v = stack[--top];
      if (v.bound >= best) continue;
      const Node& node = nodes_[v.node];
      if (node.left == 0) {
        for (std::uint32_t n = node.begin; n < node.end; ++n)
          if (const double d = dot(points_[n] - q, points_[n] - q); d < best)
            best = d, *nearest = points_[n];
        continue;
      }
      const double a = box_distance(nodes_[node.left].box, q);
      const double b = box_distance(nodes_[node.left + 1].box, q);
      const bool left_first = a <= b;  // the nearer child is popped first
      stack[top++] = {node.left + (left_first ? 1u : 0u), left_first ? b : a};
      stack[top++] = {node.left + (left_first ? 0u : 1u), left_first ? a : b};
    }
    return best;
  }
  const Vec3& first() const { return points_.front(); }

 private:
  static constexpr std::uint32_t kLeaf = 8;
  struct Node {
    Box3 box;  // of the node's points
    std::uint32_t begin = 0, end = 0;
    std::uint32_t left = 0;  // children left and left + 1; 0 for a leaf
  };

  static double box_distance(const Box3& box, Vec3 q) {
    double d = 0;
    for (int a = 0; a < 3; ++a) {
      const double out = std::max({box.min[a] - q[a], q[a] - box.max[a], 0.0});
      d += out * out;
    }
    return d;
  }

  void build(std::uint32_t at, std::uint32_t begin, std::uint32_t end) {
    Box3 box;
    for (std::uint32_t n = begin; n < end; ++n) box.extend(points_[n]);
    nodes_[at].box = box;
    nodes_[at].begin = begin;
    nodes_[at].end = end;
    if (end - begin <= kLeaf) return;
    const Vec3 e = box.size();
    const int axis = e.x >= e.y && e.x >= e.z ? 0 : (e.y >= e.z ? 1 : 2);
    const std::uint32_t mid = begin + (end - begin) / 2;
    std::nth_element(points_.begin() + begin, points_.begin() + mid, points_.begin() + end,
                     [axis](const Vec3& a, const Vec3& b) { return a[axis] < b[axis]; });
    const auto left = static_cast<std::uint32_t>(nodes_.size());
    nodes_[at].left = left;
    nodes_.resize(nodes_.size() + 2);
    build(left, begin, mid);
    build(left + 1, mid, end);
  }

  std::vector<Node> nodes_;
  std::vector<Vec3> points_;
};

}  // namespace

ScalarVolume field_from_mesh(const TriangleSoup& mesh, const ScannedFieldOptions& o) {
  if (mesh.triangles.empty()) throw InputError("the mesh has no triangles");
  const Grid grid = field_grid(bounding_box(mesh), o);
  const CleanResult cleaned = clean_soup(mesh, {.progress = o.progress});
  if (cleaned.soup.triangles.empty())
    throw InputError("the mesh encloses no volume: no triangle has three distinct corners");
  const MeshIndex index = build_index(cleaned.soup, {.hole_caps = &cleaned.caps});
  const Occupancy occupancy =
      classify_grid(index, grid, {.rule = InsideRule::Winding, .progress = o.progress});
  if (std::find(occupancy.inside.values.begin(), occupancy.inside.values.end(), 1) ==
      occupancy.inside.values.end())
    throw InputError("the mesh encloses no cell at a voxel of " + std::to_string(o.voxel) +
                     " mm (an open sheet, or a voxel larger than the part)");
  const Field f = signed_distance_field(index, occupancy.inside, {.progress = o.progress});
  ScalarVolume v = volume_on(grid, FieldSign::Signed);
  std::copy(f.values.begin(), f.values.end(), v.values.begin());
  return v;
}

ScalarVolume field_from_points(const std::vector<Vec3>& points, const ScannedFieldOptions& o) {
  if (points.empty()) throw InputError("the point cloud has no points");
  Box3 box;
  for (const Vec3& p : points) {
    if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z))
      throw InputError("the point cloud holds a point that is not finite");
    box.extend(p);
  }
  const Grid grid = field_grid(box, o);
  if (points.size() >= std::numeric_limits<std::uint32_t>::max())
    throw InputError("the point cloud has more than 2^32 - 1 points");
  const PointTree tree(points);
  ScalarVolume v = volume_on(grid, FieldSign::Unsigned);
  const std::size_t nx = grid.dims[0];
  // Along a row, the previous cell's nearest point starts the search (it is at most a voxel
  // farther from this cell than from that one), so most nodes are skipped at once.
  detail::parallel_for(grid.row_count(), 16, [&](std::size_t begin, std::size_t end) {
    for (std::size_t row = begin; row < end; ++row) {
      const int j = static_cast<int>(row % grid.dims[1]), k = static_cast<int>(row / grid.dims[1]);
      Vec3 hint = tree.first();
      for (std::size_t i = 0; i < nx; ++i)
        v.values[row * nx + i] =
            std::sqrt(tree.nearest(grid.node(static_cast<int>(i), j, k), hint, &hint));
    }
  });
  return v;
}

ScalarVolume field_from_ct(const ScalarVolume& ct, double iso, bool solid_below) {
  require_valid(ct);
  if (!std::isfinite(iso)) throw InputError("the iso-value must be a finite number");
  std::array<double, 3> s = ct.spacing;
  if (!ct.has_physical_size())
    for (int a = 0; a < 3; ++a) s[a] = 1.0 / ct.dims[a];
  std::vector<std::uint8_t> solid(ct.count()), empty(ct.count());
  std::size_t solids = 0;
  for (std::size_t n = 0; n < solid.size(); ++n) {
    solid[n] = solid_below ? ct.values[n] <= iso : ct.values[n] >= iso;
    empty[n] = !solid[n];
    solids += solid[n];
  }
  if (solids == 0 || solids == solid.size())
    throw InputError(std::string(solids == 0 ? "no" : "every") + " cell of the CT is " +
                     (solid_below ? "at or below " : "at or above ") + std::to_string(iso) +
                     ": there is no surface to measure from");
  const std::vector<double> to_empty = squared_distance(empty, ct.dims, s);
  const std::vector<double> to_solid = squared_distance(solid, ct.dims, s);
  // Neighbours across the surface get ±(their distance − h/2): the zero level lies between.
  const double h = std::min({s[0], s[1], s[2]});
  ScalarVolume v = ct;
  v.spacing = ct.has_physical_size() ? ct.spacing : std::array<double, 3>{};
  v.sign = FieldSign::Signed;
  for (std::size_t n = 0; n < v.values.size(); ++n)
    v.values[n] = solid[n] ? -(std::sqrt(to_empty[n]) - 0.5 * h) : std::sqrt(to_solid[n]) - 0.5 * h;
  return v;
}

}  // namespace tpmsfill
