// Marching cubes in two passes over layers of nodes along z, so that the output order does not
// depend on the thread count: count (edge vertices, triangles and centroid vertices per layer)
// → exclusive scan → fill by index. Memory beyond the output is a few rows of vertex ids per
// task: each task rolls two layers of edge-vertex ids instead of one id per grid edge.
#include "tpmsfill/marching_cubes.hpp"

#include <algorithm>
#include <cstdint>
#include <limits>
#include <string>

#include "detail/mc_tables.hpp"
#include "detail/parallel.hpp"
#include "tpmsfill/error.hpp"

namespace tpmsfill {
namespace {

constexpr std::uint32_t kNone = std::numeric_limits<std::uint32_t>::max();
// Edge parameters are clamped to [kDelta, 1 - kDelta] so a vertex never sits on a grid node
// and two vertices on edges sharing a node never coincide.
constexpr double kDelta = 1e-4;

/// Vertex ids of the +x, +y, +z edges of every node (i + nx·j) of one node layer.
struct LayerIds {
  std::vector<std::uint32_t> edge[3];
};

struct LayerCounts {
  std::size_t edge_vertices = 0, centroids = 0, triangles = 0;
};

struct Extractor {
  const Grid& grid;
  const float* v;
  float iso;
  int nx, ny, nz;
  std::size_t sx, sy, sz;  // index strides
  const detail::McTables& tables;

  bool inside(std::size_t n) const { return v[n] < iso; }  // == iso counts as outside

  // Corner configuration of cell (i, j, k): bit c set when corner c is inside.
  unsigned config(std::size_t base) const {
    unsigned c = 0;
    for (unsigned corner = 0; corner < 8; ++corner)
      c |= static_cast<unsigned>(
               inside(base + (corner & 1) * sx + (corner >> 1 & 1) * sy + (corner >> 2) * sz))
           << corner;
    return c;
  }

  std::size_t corner_index(std::size_t base, int corner) const {
    return base + (corner & 1) * sx + (corner >> 1 & 1) * sy + (corner >> 2) * sz;
  }

  // Table key: configuration plus the asymptotic decider on each ambiguous face: inside
  // corners (a, c) are connected when (a - iso)(c - iso) > (b - iso)(d - iso). Each difference
  // is rounded to float once, the same way for every cube (its sign is kept: two distinct
  // floats never differ by less than the smallest subnormal), and the product of two floats
  // is exact in double, so the comparison is exact: both cubes sharing a face agree, and on
  // the checkerboard configurations opposite faces cannot contradict each other (see the
  // table test). A tie counts as separated: the saddle at the iso-value is outside, as nodes
  // at the iso-value are.
  unsigned key(std::size_t base, unsigned config) const {
    unsigned decisions = 0;
    for (unsigned amb = tables.ambiguous_faces[config]; amb; amb &= amb - 1) {
      const int f = __builtin_ctz(amb);
      const auto& q = tables.face_corners[f];
      double d[4];
      for (int i = 0; i < 4; ++i) d[i] = static_cast<float>(v[corner_index(base, q[i])] - iso);
      const bool first_diagonal_inside = (config >> q[0] & 1) != 0;
      const double in = first_diagonal_inside ? d[0] * d[2] : d[1] * d[3];
      const double out = first_diagonal_inside ? d[1] * d[3] : d[0] * d[2];
      if (in > out) decisions |= 1u << f;
    }
    return config | decisions << 8;
  }

  bool crossed(std::size_t n, std::size_t stride) const { return inside(n) != inside(n + stride); }

  Vec3 edge_point(int i, int j, int k, int axis) const {
    const int at[3] = {i, j, k};
    const std::size_t n = grid.index(i, j, k);
    const std::size_t stride = axis == 0 ? sx : (axis == 1 ? sy : sz);
    const double v0 = v[n], v1 = v[n + stride];
    const double t = std::clamp((static_cast<double>(iso) - v0) / (v1 - v0), kDelta, 1 - kDelta);
    double p[3];
    for (int a = 0; a < 3; ++a) p[a] = grid.coordinate(a, at[a]);
    const double c1 = grid.coordinate(axis, at[axis] + 1);
    p[axis] = p[axis] + t * (c1 - p[axis]);
    return {p[0], p[1], p[2]};
  }

  LayerCounts count(int k) const {
    LayerCounts r;
    for (int j = 0; j < ny; ++j)
      for (int i = 0; i < nx; ++i) {
        const std::size_t n = grid.index(i, j, k);
        r.edge_vertices += (i + 1 < nx && crossed(n, sx)) + (j + 1 < ny && crossed(n, sy)) +
                           (k + 1 < nz && crossed(n, sz));
      }
    if (k + 1 < nz)
      for (int j = 0; j + 1 < ny; ++j)
        for (int i = 0; i + 1 < nx; ++i) {
          const std::size_t base = grid.index(i, j, k);
          const unsigned c = config(base);
          if (c == 0 || c == 255) continue;
          const detail::McCase& mc = tables.cases[key(base, c)];
          r.triangles += mc.triangle_count;
          r.centroids += mc.centroid_count;
        }
    return r;
  }

  // Numbers the crossed edges of node layer k from `first` on, in index order (x, y, z edge of
  // each node); writes their points when `points` is given (the layer's owner does).
  void number(int k, std::uint32_t first, LayerIds& ids, Vec3* points) const {
    const std::size_t layer = static_cast<std::size_t>(nx) * static_cast<std::size_t>(ny);
    for (auto& e : ids.edge) e.assign(layer, kNone);
    std::uint32_t id = first;
    for (int j = 0; j < ny; ++j)
      for (int i = 0; i < nx; ++i) {
        const std::size_t n = grid.index(i, j, k), m = static_cast<std::size_t>(i) + sy * j;
        const bool has[3] = {i + 1 < nx, j + 1 < ny, k + 1 < nz};
        const std::size_t stride[3] = {sx, sy, sz};
        for (int a = 0; a < 3; ++a)
          if (has[a] && crossed(n, stride[a])) {
            if (points) points[id] = edge_point(i, j, k, a);
            ids.edge[a][m] = id++;
          }
      }
  }

  // Triangles of cell layer k (between node layers k and k + 1).
  void fill(int k, const LayerIds& lower, const LayerIds& upper, std::uint32_t first_centroid,
            Vec3* points, Triangle* triangles) const {
    std::uint32_t centroid = first_centroid;
    for (int j = 0; j + 1 < ny; ++j)
      for (int i = 0; i + 1 < nx; ++i) {
        const std::size_t base = grid.index(i, j, k);
        const unsigned c = config(base);
        if (c == 0 || c == 255) continue;
        const detail::McCase& mc = tables.cases[key(base, c)];
        std::uint32_t slot[14];
        for (int e = 0; e < 12; ++e) {
          const int c0 = tables.edge_corners[e][0], axis = e / 4;
          const std::size_t m = static_cast<std::size_t>(i + (c0 & 1)) +
                                sy * static_cast<std::size_t>(j + (c0 >> 1 & 1));
          slot[e] = ((c0 >> 2) ? upper : lower).edge[axis][m];
        }
        for (int cc = 0; cc < mc.centroid_count; ++cc) {
          Vec3 sum;
          int n = 0;
          for (int e = 0; e < 12; ++e)
            if (mc.centroid_edges[cc] >> e & 1) {
              const int c0 = tables.edge_corners[e][0];
              sum = sum + edge_point(i + (c0 & 1), j + (c0 >> 1 & 1), k + (c0 >> 2), e / 4);
              ++n;
            }
          points[centroid] = (1.0 / n) * sum;
          slot[12 + cc] = centroid++;
        }
        for (int t = 0; t < mc.triangle_count; ++t)
          *triangles++ = {slot[mc.triangles[t][0]], slot[mc.triangles[t][1]],
                          slot[mc.triangles[t][2]]};
      }
  }
};

}  // namespace

TriangleSoup marching_cubes(const Field& field, const McOptions& options) {
  const Grid& grid = field.grid;
  if (grid.dims[0] < 2 || grid.dims[1] < 2 || grid.dims[2] < 2)
    throw InputError("marching_cubes: the grid needs at least 2 nodes along each axis");
  if (field.values.size() != grid.node_count())
    throw InputError("marching_cubes: the field has " + std::to_string(field.values.size()) +
                     " values for " + std::to_string(grid.node_count()) + " grid nodes");

  const int nx = grid.dims[0], ny = grid.dims[1], nz = grid.dims[2];
  const std::size_t sy = static_cast<std::size_t>(nx), sz = sy * static_cast<std::size_t>(ny);
  const Extractor ex{grid, field.values.data(), options.iso, nx, ny, nz, 1, sy,
                     sz,   detail::mc_tables()};
  const std::size_t layers = static_cast<std::size_t>(nz);
  detail::ProgressCounter progress(options.progress, "marching cubes", 2 * layers);

  std::vector<LayerCounts> counts(layers);
  detail::parallel_for(layers, 1, [&](std::size_t b, std::size_t e) {
    for (std::size_t k = b; k < e; ++k) {
      counts[k] = ex.count(static_cast<int>(k));
      progress.add(1);
    }
  });

  // Layer k's vertices: its edge vertices, then the centroid vertices of cell layer k.
  std::vector<std::size_t> first_vertex(layers + 1, 0), first_triangle(layers + 1, 0);
  for (std::size_t k = 0; k < layers; ++k) {
    first_vertex[k + 1] = first_vertex[k] + counts[k].edge_vertices + counts[k].centroids;
    first_triangle[k + 1] = first_triangle[k] + counts[k].triangles;
  }
  if (first_vertex[layers] >= kNone)
    throw InputError("marching_cubes: more than 2^32 - 1 vertices; use a coarser grid");

  TriangleSoup soup;
  soup.points.resize(first_vertex[layers]);
  soup.triangles.resize(first_triangle[layers]);
  // Ranges of several layers, so that each task numbers the layer above its range only once.
  detail::parallel_for(layers, 8, [&](std::size_t b, std::size_t e) {
    LayerIds lower, upper;
    for (std::size_t k = b; k < e; ++k) {
      const int kk = static_cast<int>(k);
      if (k == b)
        ex.number(kk, static_cast<std::uint32_t>(first_vertex[k]), lower, soup.points.data());
      else
        std::swap(lower, upper);
      if (k + 1 < layers) {
        // The next layer's points are written by whichever task owns it.
        ex.number(kk + 1, static_cast<std::uint32_t>(first_vertex[k + 1]), upper,
                  k + 1 < e ? soup.points.data() : nullptr);
        ex.fill(kk, lower, upper,
                static_cast<std::uint32_t>(first_vertex[k] + counts[k].edge_vertices),
                soup.points.data(), soup.triangles.data() + first_triangle[k]);
      }
      progress.add(1);
    }
  });
  progress.finish();
  return soup;
}

}  // namespace tpmsfill
