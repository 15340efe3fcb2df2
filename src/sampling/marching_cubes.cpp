// Marching cubes in two passes over layers of nodes along z, so that the output order does not
// depend on the thread count: count (edge vertices, triangles and centroid vertices per layer)
// → exclusive scan → fill by index. Memory beyond the output is a few rows of vertex ids per
// task: each task rolls two layers of edge-vertex ids instead of one id per grid edge.
#include "tpmsfill/sampling/marching_cubes.hpp"

#include <algorithm>
#include <atomic>
#include <bit>
#include <cstdint>
#include <limits>
#include <string>

#include "core/grid_border.hpp"
#include "core/grid_buffer.hpp"
#include "core/index_limits.hpp"
#include "core/parallel.hpp"
#include "core/stage_progress.hpp"
#include "sampling/mc_tables.hpp"
#include "sampling/rounded_grid.hpp"
#include "tpmsfill/error.hpp"

namespace tpmsfill {
namespace {

/// Vertex ids of the +x, +y, +z edges of every node (i + nx·j) of one node layer, and the
/// layer's row states (Extractor::row_states) that fill() skips rows by.
struct LayerIds {
  std::vector<std::uint32_t> edge[3];
  std::vector<std::uint8_t> rows;
};

struct LayerCounts {
  std::size_t edge_vertices = 0, centroids = 0, triangles = 0;
};

// What marching_cubes_proved() checks as it extracts: each vertex as stored strictly inside
// its edge (a centroid inside its cube) of the grid as held, and held as the file holds it.
struct ProofLog {
  std::atomic<bool> vertex_off{false};
};

// kSlab: `values` holds a slab of node layers, from node `first_node` on; otherwise the whole
// field (a compile-time choice, so the whole-field path indexes as directly as it always did).
template <bool kSlab>
struct Extractor {
  const Grid& grid;
  const float* values;
  float iso;
  int nx, ny, nz;
  std::size_t sx, sy, sz;  // index strides
  const detail::McTables& tables;
  const detail::RoundedGrid& held;  // the nodes and edges as the file holds them
  std::size_t first_node = 0;
  // Point id p is written to points[p - id_base]: a slab's caller may have consumed (and
  // dropped) the points below id_base.
  std::uint32_t id_base = 0;

  float v(std::size_t n) const { return values[kSlab ? n - first_node : n]; }  // n: grid node
  bool inside(std::size_t n) const { return v(n) < iso; }  // == iso counts as outside

  // Calls f(i, config) for the cells (i, j, k), i = 0 .. nx - 2, where bit c of config is set
  // when corner c is inside. The x = 1 face of a cell is the x = 0 face of the next, so each
  // node is read once per row.
  template <class F>
  void for_cells_in_row(int j, int k, const F& f) const {
    const float* r = values + (grid.index(0, j, k) - (kSlab ? first_node : 0));
    auto column = [&](int i) {
      return static_cast<unsigned>(r[i] < iso) | static_cast<unsigned>(r[i + sy] < iso) << 2 |
             static_cast<unsigned>(r[i + sz] < iso) << 4 |
             static_cast<unsigned>(r[i + sy + sz] < iso) << 6;
    };
    unsigned left = column(0);
    for (int i = 0; i + 1 < nx; ++i) {
      const unsigned right = column(i + 1);
      f(i, left | right << 1);
      left = right;
    }
  }

  // Per node row j of layer k: kOut when every node is outside, kIn when every node is inside,
  // kMixed otherwise. A cell row whose four node rows are all out (or all in) has no surface,
  // and a node row whose row, next row and row above agree owns no crossed edge: most rows of
  // a grid around a model are outside it, and these checks let the passes skip them.
  enum RowState : std::uint8_t { kOut, kIn, kMixed };
  std::vector<std::uint8_t> row_states(int k) const {
    std::vector<std::uint8_t> state(static_cast<std::size_t>(ny));
    for (int j = 0; j < ny; ++j) {
      const float* r = values + (grid.index(0, j, k) - (kSlab ? first_node : 0));
      std::uint32_t in = 0;  // a count, not a branch: the loop vectorises
      for (int i = 0; i < nx; ++i) in += r[i] < iso ? 1u : 0u;
      state[static_cast<std::size_t>(j)] =
          in == 0 ? kOut : (in == static_cast<std::uint32_t>(nx) ? kIn : kMixed);
    }
    return state;
  }
  static bool same_side(std::uint8_t a, std::uint8_t b) { return a == b && a != kMixed; }
  // Cell row (j, k) of a layer whose node rows have states `lower` and `upper` (layer k + 1).
  static bool no_surface(const std::vector<std::uint8_t>& lower,
                         const std::vector<std::uint8_t>& upper, int j) {
    const auto a = static_cast<std::size_t>(j);
    return same_side(lower[a], lower[a + 1]) && same_side(lower[a], upper[a]) &&
           same_side(lower[a], upper[a + 1]);
  }

  std::size_t corner_index(std::size_t base, int corner) const {
    return base + (corner & 1) * sx + (corner >> 1 & 1) * sy + (corner >> 2) * sz;
  }

  // Table key: configuration plus the asymptotic decider (detail::mc_case_key).
  unsigned key(std::size_t base, unsigned config) const {
    return detail::mc_case_key(tables, config, [&](int corner) {
      return v(corner_index(base, corner)) - iso;  // in float, as always
    });
  }

  bool crossed(std::size_t n, std::size_t stride) const { return inside(n) != inside(n + stride); }

  Vec3 edge_point(int i, int j, int k, int axis) const {
    const int at[3] = {i, j, k};
    const std::size_t n = grid.index(i, j, k);
    const std::size_t stride = axis == 0 ? sx : (axis == 1 ? sy : sz);
    const double v0 = v(n), v1 = v(n + stride);
    // Clamped off the nodes (detail::edge_crossing); where the output is rounded as its file
    // holds it (McOptions::rounding), RoundedGrid keeps the rounded vertex inside its edge.
    const double t = detail::edge_crossing(v0, v1, static_cast<double>(iso));
    double p[3];
    for (int a = 0; a < 3; ++a) p[a] = held.node(a, at[a]);
    const double c0 = grid.coordinate(axis, at[axis]), c1 = grid.coordinate(axis, at[axis] + 1);
    p[axis] = held.inside_edge(axis, at[axis], c0 + t * (c1 - c0));
    return {p[0], p[1], p[2]};
  }

  // The centroid of the cube's piece (its edge points' mean), rounded strictly inside the cube.
  Vec3 centroid(int i, int j, int k, unsigned edges) const {
    Vec3 sum;
    int n = 0;
    for (unsigned m = edges; m; m &= m - 1, ++n) {
      const int e = std::countr_zero(m), c0 = tables.edge_corners[e][0];
      sum = sum + edge_point(i + (c0 & 1), j + (c0 >> 1 & 1), k + (c0 >> 2), e / 4);
    }
    const Vec3 c = (1.0 / n) * sum;
    return {held.inside_edge(0, i, c.x), held.inside_edge(1, j, c.y), held.inside_edge(2, k, c.z)};
  }

  // Crossed edges owned by node (i, j, k), the slow general way (grid borders only).
  int node_edges(int i, int j, int k) const {
    const std::size_t n = grid.index(i, j, k);
    return (i + 1 < nx && crossed(n, sx)) + (j + 1 < ny && crossed(n, sy)) +
           (k + 1 < nz && crossed(n, sz));
  }

  LayerCounts count(int k) const {
    LayerCounts r;
    if (k + 1 == nz) {
      for (int j = 0; j < ny; ++j)
        for (int i = 0; i < nx; ++i) r.edge_vertices += node_edges(i, j, k);
      return r;
    }
    const std::vector<std::uint8_t> lower = row_states(k), upper = row_states(k + 1);
    for (int j = 0; j + 1 < ny; ++j) {
      if (no_surface(lower, upper, j)) continue;  // node_edges(nx - 1, j, k) is 0 too
      for_cells_in_row(j, k, [&](int i, unsigned c) {
        if (c == 0 || c == 255) return;
        // Cube edges 0, 4 and 8 leave corner 0: the +x, +y, +z edges that node (i, j, k) owns.
        r.edge_vertices += (c ^ c >> 1) % 2 + (c ^ c >> 2) % 2 + (c ^ c >> 4) % 2;
        const detail::McCase& mc = tables.cases[key(grid.index(i, j, k), c)];
        r.triangles += mc.triangle_count;
        r.centroids += mc.centroid_count;
      });
      r.edge_vertices += node_edges(nx - 1, j, k);
    }
    for (int i = 0; i < nx; ++i) r.edge_vertices += node_edges(i, ny - 1, k);
    return r;
  }

  // The proof's assumption of a vertex: strictly inside its edge along `axis` (or, axis -1,
  // inside its cube) of the grid as held, as the file holds it. (An edge vertex's other two
  // coordinates are the held nodes', assigned.)
  void check_vertex(const Vec3& p, int i, int j, int k, int axis, ProofLog& log) const {
    const int at[3] = {i, j, k};
    bool inside = true;
    for (int a = axis < 0 ? 0 : axis; a <= (axis < 0 ? 2 : axis); ++a) {
      const double x = p[a];
      inside &= detail::held(held.rounding(), x) == x && held.node(a, at[a]) < x &&
                x < held.node(a, at[a] + 1);
    }
    if (!inside) log.vertex_off.store(true, std::memory_order_relaxed);
  }

  // Numbers the crossed edges of node layer k from `first` on, in index order (x, y, z edge of
  // each node); writes their points when `points` is given (the layer's owner does), checked
  // when `log` is.
  void number(int k, std::uint32_t first, LayerIds& ids, Vec3* points,
              ProofLog* log = nullptr) const {
    // Only crossed edges' ids are ever read (fill looks up the crossed edges of its cells), so
    // the others keep whatever an earlier layer left there.
    const std::size_t layer = static_cast<std::size_t>(nx) * static_cast<std::size_t>(ny);
    for (auto& e : ids.edge) e.resize(layer);
    ids.rows = row_states(k);
    const std::vector<std::uint8_t>& here = ids.rows;
    const std::vector<std::uint8_t> above = k + 1 < nz ? row_states(k + 1) : here;
    std::uint32_t id = first;
    for (int j = 0; j < ny; ++j) {
      const std::size_t row = grid.index(0, j, k), m0 = sy * static_cast<std::size_t>(j);
      const bool has_y = j + 1 < ny, has_z = k + 1 < nz;
      const auto at = static_cast<std::size_t>(j);
      if (same_side(here[at], above[at]) && (!has_y || same_side(here[at], here[at + 1])))
        continue;  // no crossed +x, +y or +z edge in this row
      for (int i = 0; i < nx; ++i) {
        const bool in = v(row + i) < iso;
        const bool cross[3] = {i + 1 < nx && (v(row + i + 1) < iso) != in,
                               has_y && (v(row + i + sy) < iso) != in,
                               has_z && (v(row + i + sz) < iso) != in};
        for (int a = 0; a < 3; ++a)
          if (cross[a]) {
            if (points) {
              points[id - id_base] = edge_point(i, j, k, a);
              if (log) check_vertex(points[id - id_base], i, j, k, a, *log);
            }
            ids.edge[a][m0 + i] = id++;
          }
      }
    }
  }

  // Triangles of cell layer k (between node layers k and k + 1); with a log, the centroids
  // are checked.
  void fill(int k, const LayerIds& lower, const LayerIds& upper, std::uint32_t first_centroid,
            Vec3* points, Triangle* triangles, ProofLog* log = nullptr) const {
    // Where cube edge e's vertex id lives: layer, axis and offset from the cell's id index.
    const std::uint32_t* base_ids[12];
    std::size_t offset[12];
    for (int e = 0; e < 12; ++e) {
      const int c0 = tables.edge_corners[e][0];
      base_ids[e] = ((c0 >> 2) ? upper : lower).edge[e / 4].data();
      offset[e] = static_cast<std::size_t>(c0 & 1) + sy * static_cast<std::size_t>(c0 >> 1 & 1);
    }
    std::uint32_t centroid = first_centroid;
    for (int j = 0; j + 1 < ny; ++j) {
      if (no_surface(lower.rows, upper.rows, j)) continue;
      const std::size_t m0 = sy * static_cast<std::size_t>(j);
      for_cells_in_row(j, k, [&](int i, unsigned c) {
        if (c == 0 || c == 255) return;
        const detail::McCase& mc = tables.cases[key(grid.index(i, j, k), c)];
        std::uint32_t slot[14];
        for (unsigned m = tables.crossed_edges[c]; m; m &= m - 1) {
          const int e = std::countr_zero(m);
          slot[e] = base_ids[e][m0 + static_cast<std::size_t>(i) + offset[e]];
        }
        for (int cc = 0; cc < mc.centroid_count; ++cc) {
          points[centroid - id_base] = this->centroid(i, j, k, mc.centroid_edges[cc]);
          if (log) check_vertex(points[centroid - id_base], i, j, k, -1, *log);
          slot[12 + cc] = centroid++;
        }
        for (int t = 0; t < mc.triangle_count; ++t)
          *triangles++ = {slot[mc.triangles[t][0]], slot[mc.triangles[t][1]],
                          slot[mc.triangles[t][2]]};
      });
    }
  }
};

// Where each layer's points and triangles start: first_vertex[k] is node layer kb + k's first
// point id, first_triangle[k] cell layer kb + k's first triangle (index into the soup); the
// last entries are the ends.
struct LayerStarts {
  std::vector<std::size_t> first_vertex, first_triangle;
};

// Both passes over node layers [kb, ke), appended to `soup`, which holds the points of the
// layers below kb from id `id_base` on (its point count plus id_base is layer kb's first id)
// and any triangles. with_layers(b, e, f) calls f(extractor) with an extractor that reads node
// layers b .. e + 1 (those that exist), writing points from id_base on: all that counting the
// layers [b, e) and numbering them and the next one need (a node's +z edge reaches the layer
// above).
template <class WithLayers>
LayerStarts extract(const Grid& grid, std::size_t kb, std::size_t ke, std::size_t count_grain,
                    detail::ProgressCounter& progress, const WithLayers& with_layers,
                    TriangleSoup& soup, std::uint32_t id_base = 0, ProofLog* log = nullptr) {
  const std::size_t layers = static_cast<std::size_t>(grid.dims[2]);
  const std::size_t n = ke - kb;
  std::vector<LayerCounts> counts(n);
  detail::parallel_for(n, count_grain, [&](std::size_t b, std::size_t e) {
    with_layers(kb + b, kb + e, [&](const auto& ex) {
      for (std::size_t k = b; k < e; ++k) {
        counts[k] = ex.count(static_cast<int>(kb + k));
        progress.add(1);
      }
    });
  });

  // Layer k's vertices: its edge vertices, then the centroid vertices of cell layer k.
  std::vector<std::size_t> first_vertex(n + 1, id_base + soup.points.size()),
      first_triangle(n + 1, soup.triangles.size());
  for (std::size_t k = 0; k < n; ++k) {
    first_vertex[k + 1] = first_vertex[k] + counts[k].edge_vertices + counts[k].centroids;
    first_triangle[k + 1] = first_triangle[k] + counts[k].triangles;
  }
  if (!detail::fits_32bit_ids(first_vertex[n]))
    throw InputError("marching_cubes: more than 2^32 - 1 vertices; use a coarser grid");

  detail::resize_on_huge_pages(soup.points, first_vertex[n] - id_base);
  detail::resize_on_huge_pages(soup.triangles, first_triangle[n]);
  // Ranges of several layers, so that each task numbers the layer above its range only once.
  detail::parallel_for(n, 8, [&](std::size_t b, std::size_t e) {
    with_layers(kb + b, kb + e, [&](const auto& ex) {
      LayerIds lower, upper;
      for (std::size_t k = b; k < e; ++k) {
        const int kk = static_cast<int>(kb + k);
        if (k == b)
          ex.number(kk, static_cast<std::uint32_t>(first_vertex[k]), lower, soup.points.data(),
                    log);
        else
          std::swap(lower, upper);
        if (kb + k + 1 < layers) {
          // The next layer's points are written by whichever task (or slab) owns it; its ids
          // start where this range's end, whoever owns it.
          ex.number(kk + 1, static_cast<std::uint32_t>(first_vertex[k + 1]), upper,
                    k + 1 < e ? soup.points.data() : nullptr, log);
          ex.fill(kk, lower, upper,
                  static_cast<std::uint32_t>(first_vertex[k] + counts[k].edge_vertices),
                  soup.points.data(), soup.triangles.data() + first_triangle[k], log);
        }
        progress.add(1);
      }
    });
  });
  return {std::move(first_vertex), std::move(first_triangle)};
}

void require_cells(const Grid& grid) {
  if (grid.dims[0] < 2 || grid.dims[1] < 2 || grid.dims[2] < 2)
    throw InputError("marching_cubes: the grid needs at least 2 nodes along each axis");
}

// An extractor over `values`, which start at grid node `first_node` (0: the whole field).
template <bool kSlab>
Extractor<kSlab> extractor(const Grid& grid, const float* values, float iso,
                           const detail::RoundedGrid& held, std::size_t first_node = 0,
                           std::uint32_t id_base = 0,
                           const detail::McTables& tables = detail::mc_tables()) {
  const std::size_t sy = static_cast<std::size_t>(grid.dims[0]);
  const std::size_t sz = sy * static_cast<std::size_t>(grid.dims[1]);
  return {grid, values, iso,    grid.dims[0], grid.dims[1], grid.dims[2], 1,
          sy,   sz,     tables, held,         first_node,   id_base};
}

// The whole field's mesh, by `tables`; checked as it goes when `log` is given.
TriangleSoup extract_field(const Field& field, const McOptions& options,
                           const detail::RoundedGrid& held, const detail::McTables& tables,
                           ProofLog* log) {
  const Grid& grid = field.grid;
  require_cells(grid);
  if (field.values.size() != grid.node_count())
    throw InputError("marching_cubes: the field has " + std::to_string(field.values.size()) +
                     " values for " + std::to_string(grid.node_count()) + " grid nodes");
  const auto ex = extractor<false>(grid, field.values.data(), options.iso, held, 0, 0, tables);
  detail::ProgressCounter progress(options.progress, "marching cubes", 2 * grid.dims[2]);
  TriangleSoup soup;
  extract(
      grid, 0, grid.dims[2], 1, progress,
      [&](std::size_t, std::size_t, const auto& work) { work(ex); }, soup, 0, log);
  progress.finish();
  return soup;
}

// Why the construction cannot be relied on for any field on `held`'s grid: the table breaks
// one of the proof's rules, or the grid as held does not increase strictly. Empty when neither.
std::string unproved_grid(const Grid& g, const detail::RoundedGrid& held,
                          const detail::McTables& tables) {
  // The real table is checked once per process; a table a test hands in, on every call.
  static const std::vector<std::string> own_violations = mc_table_violations(detail::mc_tables());
  const std::vector<std::string> violations =
      &tables == &detail::mc_tables() ? own_violations : mc_table_violations(tables);
  if (!violations.empty())
    return "the marching-cubes table breaks a rule its proof needs (" + violations[0] + ")";
  for (int a = 0; a < 3; ++a)
    for (int i = 0; i + 1 < g.dims[a]; ++i)
      if (!(held.node(a, i) < held.node(a, i + 1)))
        return "the grid's nodes as the file holds them do not increase strictly";
  return {};
}

// The first assumption the proof lacks, in one order whether the field came whole or in slabs:
// the table and grid (`grid_reason`, unproved_grid()), a border node inside, a vertex off.
std::string unproved_reason(const std::string& grid_reason, bool border_inside, bool vertex_off) {
  if (!grid_reason.empty()) return grid_reason;
  if (border_inside) return "a node on the grid's border is inside, so the surface is open there";
  if (vertex_off)
    return "a vertex is not strictly inside its grid edge or cube as the file holds it";
  return {};
}

}  // namespace

TriangleSoup marching_cubes(const Field& field, const McOptions& options) {
  const detail::RoundedGrid held(field.grid, options.rounding);
  return extract_field(field, options, held, detail::mc_tables(), nullptr);
}

namespace detail {

ProvedMesh marching_cubes_proved(const Field& field, const McOptions& options,
                                 const McTables& tables) {
  const RoundedGrid held(field.grid, options.rounding);
  ProofLog log;
  ProvedMesh out;
  out.mesh = extract_field(field, options, held, tables, &log);
  bool border_inside = false;
  for_each_border_node(field.grid,
                       [&](std::size_t n) { border_inside |= field.values[n] < options.iso; });
  out.unproved = unproved_reason(unproved_grid(field.grid, held, tables), border_inside,
                                 log.vertex_off.load());
  if (!out.unproved.empty()) return out;
  // No pair is left open (marching_cubes.hpp says why).
  out.proof = ConstructionProof{out.mesh.triangles.size(), out.mesh.points.size()};
  return out;
}

}  // namespace detail

ProvedMesh marching_cubes_proved(const Field& field, const McOptions& options) {
  return detail::marching_cubes_proved(field, options, detail::mc_tables());
}

TriangleSoup marching_cubes(const FieldSource& source, const Grid& grid, const McOptions& options) {
  require_cells(grid);
  const RowFunction rows = bind_source(source, grid);
  const std::size_t ny = static_cast<std::size_t>(grid.dims[1]);
  const std::size_t layer = static_cast<std::size_t>(grid.dims[0]) * ny;
  const std::size_t layers = static_cast<std::size_t>(grid.dims[2]);
  const detail::RoundedGrid held(grid, options.rounding);
  // Each task evaluates the node layers it reads, two more than it owns.
  detail::ProgressCounter progress(options.progress, "marching cubes", 2 * layers);
  TriangleSoup soup;
  extract(
      grid, 0, layers, 8, progress,
      [&](std::size_t b, std::size_t e, const auto& work) {
        const std::size_t end = std::min(e + 2, layers);
        std::vector<float> slab((end - b) * layer);
        rows(b * ny, (end - b) * ny, slab.data(), nullptr);
        work(extractor<true>(grid, slab.data(), options.iso, held, b * layer));
      },
      soup);
  progress.finish();
  return soup;
}

SlabMarchingCubes::SlabMarchingCubes(const Grid& grid, const McOptions& options, int first_plane)
    : grid_(grid),
      options_(options),
      held_(std::make_shared<const detail::RoundedGrid>(grid, options.rounding)),
      first_(first_plane),
      next_(first_plane) {
  require_cells(grid);
  if (grid.z_offset != 0) throw InputError("SlabMarchingCubes: give the whole grid");
  if (first_plane < 0 || first_plane >= grid.dims[2])
    throw InputError("SlabMarchingCubes: the first plane is not in the grid");
  first_point_.push_back(0);
  first_triangle_.push_back(0);
  unproved_grid_ = unproved_grid(grid_, *held_, detail::mc_tables());
}

std::string SlabMarchingCubes::unproved() const {
  return unproved_reason(unproved_grid_, border_inside_, vertex_off_);
}

std::uint64_t SlabMarchingCubes::first_point(int k) const {
  if (k < first_ || k > next_) throw InputError("SlabMarchingCubes: that layer is not made yet");
  return first_point_[static_cast<std::size_t>(k - first_)];
}

std::uint64_t SlabMarchingCubes::first_triangle(int k) const {
  if (k < first_ || k > next_) throw InputError("SlabMarchingCubes: that layer is not made yet");
  return first_triangle_[static_cast<std::size_t>(k - first_)];
}

void SlabMarchingCubes::drop_points(TriangleSoup& mesh, std::uint64_t below) {
  if (below < dropped_ || below > dropped_ + mesh.points.size())
    throw InputError("SlabMarchingCubes: those points are not held");
  mesh.points.erase(mesh.points.begin(),
                    mesh.points.begin() + static_cast<std::ptrdiff_t>(below - dropped_));
  dropped_ = below;
}

void SlabMarchingCubes::add(const Field& planes, int owned, TriangleSoup& mesh) {
  const Grid& g = planes.grid;
  const int nz = grid_.dims[2];
  const int last = std::min(next_ + owned + 1, nz - 1);  // the highest plane read
  if (owned < 1 || next_ + owned > nz || g.z_offset != next_ || g.dims[2] != last - next_ + 1 ||
      g.dims[0] != grid_.dims[0] || g.dims[1] != grid_.dims[1] || g.spacing != grid_.spacing ||
      !(g.origin == grid_.origin) || planes.values.size() != g.node_count())
    throw InputError("SlabMarchingCubes: the slab is not the grid's next planes (" +
                     std::to_string(next_) + " on, with the one or two above)");
  const std::size_t layer = static_cast<std::size_t>(grid_.dims[0]) * grid_.dims[1];
  const auto base = static_cast<std::uint32_t>(dropped_);
  const auto ex = extractor<true>(grid_, planes.values.data(), options_.iso, *held_,
                                  static_cast<std::size_t>(next_) * layer, base);
  detail::ProgressCounter progress(nullptr, "marching cubes", 1);
  const std::size_t triangles_before = mesh.triangles.size();
  ProofLog log;
  const LayerStarts starts = extract(
      grid_, next_, next_ + owned, 1, progress,
      [&](std::size_t, std::size_t, const auto& work) { work(ex); }, mesh, base, &log);
  // The proof's checks on the owned planes (each plane is owned by one slab).
  vertex_off_ = vertex_off_ || log.vertex_off.load();
  for (int k = next_; k < next_ + owned; ++k)
    detail::for_each_border_node_of_plane(grid_, k, [&](std::size_t n) {
      border_inside_ = border_inside_ ||
                       planes.values[n - static_cast<std::size_t>(next_) * layer] < options_.iso;
    });
  // Triangle starts count every triangle made, whatever the caller has taken from `mesh`.
  const std::uint64_t made = first_triangle_.back();
  for (int k = 1; k <= owned; ++k) {
    first_point_.push_back(starts.first_vertex[static_cast<std::size_t>(k)]);
    first_triangle_.push_back(made + starts.first_triangle[static_cast<std::size_t>(k)] -
                              triangles_before);
  }
  next_ += owned;
}

}  // namespace tpmsfill
