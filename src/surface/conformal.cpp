// Stage "conformal": the field-space map of a slab design onto a surface (conformal.hpp).
#include "tpmsfill/conformal.hpp"

#include <CGAL/AABB_segment_primitive.h>
#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_tree.h>
#include <CGAL/AABB_triangle_primitive.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <map>
#include <memory>
#include <numbers>
#include <string>
#include <utility>

#include "core/parallel.hpp"
#include "lattice/review.hpp"
#include "mesh/cgal_types.hpp"
#include "surface/surface_normals.hpp"
#include "tpmsfill/error.hpp"
#include "tpmsfill/grid.hpp"
#include "tpmsfill/mesh/validate.hpp"

namespace tpmsfill {
namespace {

using K = detail::Kernel;
using Triangles = std::vector<K::Triangle_3>;
using Primitive = CGAL::AABB_triangle_primitive<K, Triangles::const_iterator>;
using Tree = CGAL::AABB_tree<CGAL::AABB_traits<K, Primitive>>;
using Segments = std::vector<K::Segment_3>;
using RimTree = CGAL::AABB_tree<
    CGAL::AABB_traits<K, CGAL::AABB_segment_primitive<K, Segments::const_iterator>>>;

bool positive(double x) {
  return std::isfinite(x) && x > 0;
}

// Barycentric coordinates of q (on the triangle or near it) in abc, clamped to the triangle.
std::array<double, 3> barycentric(Vec3 q, Vec3 a, Vec3 b, Vec3 c) {
  const Vec3 v0 = b - a, v1 = c - a, v2 = q - a;
  const double d00 = dot(v0, v0), d01 = dot(v0, v1), d11 = dot(v1, v1), d20 = dot(v2, v0),
               d21 = dot(v2, v1), den = d00 * d11 - d01 * d01;
  if (!(den > 0)) return {1.0 / 3, 1.0 / 3, 1.0 / 3};
  double v = (d11 * d20 - d01 * d21) / den, w = (d00 * d21 - d01 * d20) / den;
  v = std::clamp(v, 0.0, 1.0), w = std::clamp(w, 0.0, 1.0);
  if (v + w > 1) v /= v + w, w = 1 - v;
  return {1 - v - w, v, w};
}

struct SurfacePoint {
  double u = 0, v = 0;  ///< parameter at the closest point
  double h = 0;         ///< signed height on the layer's side, mm
  double lateral = 0;   ///< < 0 over the surface (minus the distance to its boundary), mm
};

// Closest point, parameter and height of any point: what the field and the measures share.
class SurfaceMap {
 public:
  SurfaceMap(const SurfaceParameterization& layout, std::array<double, 2> lengths, SurfaceSide side)
      : layout_(layout), lengths_(lengths), sign_(side == SurfaceSide::Out ? 1 : -1) {
    const TriangleSoup& m = layout.mesh;
    for (const Triangle& t : m.triangles)
      triangles_.emplace_back(detail::to_cgal(m.points[t[0]]), detail::to_cgal(m.points[t[1]]),
                              detail::to_cgal(m.points[t[2]]));
    tree_.insert(triangles_.begin(), triangles_.end());
    tree_.build();
    tree_.accelerate_distance_queries();
    // Angle-weighted normals per position, so the seam's two copies of a point agree.
    normals_ = detail::angle_weighted_normals(m);
    auto pos = [&](std::uint32_t i) {
      const Vec3 p = m.points[i];
      return std::array<double, 3>{p.x, p.y, p.z};
    };
    // The surface's own boundary: edges without a twin, less the seam's (whose twin is the
    // reversed edge between the same positions, on the seam's other side).
    std::map<std::array<double, 6>, int> open;
    std::map<std::uint64_t, bool> directed;
    for (const Triangle& t : m.triangles)
      for (int c = 0; c < 3; ++c) directed[(std::uint64_t(t[c]) << 32) | t[(c + 1) % 3]] = true;
    auto twin = [&](std::uint32_t a, std::uint32_t b) {
      return directed.count((std::uint64_t(b) << 32) | a) > 0;
    };
    for (const Triangle& t : m.triangles)
      for (int c = 0; c < 3; ++c)
        if (!twin(t[c], t[(c + 1) % 3])) {
          const auto a = pos(t[c]), b = pos(t[(c + 1) % 3]);
          ++open[{a[0], a[1], a[2], b[0], b[1], b[2]}];
        }
    boundary_edge_.resize(m.triangles.size());
    on_boundary_.assign(m.points.size(), false);
    for (std::size_t i = 0; i < m.triangles.size(); ++i)
      for (int c = 0; c < 3; ++c) {
        const std::uint32_t a = m.triangles[i][c], b = m.triangles[i][(c + 1) % 3];
        const auto pa = pos(a), pb = pos(b);
        const bool seam = open.count({pb[0], pb[1], pb[2], pa[0], pa[1], pa[2]}) > 0;
        if (!twin(a, b) && !seam) {
          boundary_edge_[i][c] = on_boundary_[a] = on_boundary_[b] = true;
          rim_.emplace_back(detail::to_cgal(m.points[a]), detail::to_cgal(m.points[b]));
        }
      }
    // A free layout's boundary is no square: the distance to the rim is measured on the surface
    // (to its boundary edges), not in the plane.
    if (layout.method == LayoutMethod::Free && !rim_.empty()) {
      rim_tree_.insert(rim_.begin(), rim_.end());
      rim_tree_.build();
      rim_tree_.accelerate_distance_queries();
    }
  }

  // The smallest radius of curvature bending towards the layer, from each edge's two vertex
  // normals: turning by Δn over the step Δx gives R ≈ |Δx|² / (Δn·Δx) (exact on a sphere,
  // whose angle-weighted normals are radial). Infinite where nothing bends that way.
  std::pair<double, Vec3> focal_distance() const {
    const TriangleSoup& m = layout_.mesh;
    double best = std::numeric_limits<double>::infinity();
    Vec3 where{};
    for (const Triangle& t : m.triangles)
      for (int c = 0; c < 3; ++c) {
        const std::uint32_t a = t[c], b = t[(c + 1) % 3];
        const Vec3 dx = m.points[b] - m.points[a];
        const double bend = -sign_ * dot(normals_[b] - normals_[a], dx);
        if (bend <= 0) continue;
        if (const double r = dot(dx, dx) / bend; r < best)
          best = r, where = 0.5 * (m.points[a] + m.points[b]);
      }
    // Bends at rounding level (flat parts) give radii that mean "none".
    const Box3 box = bounding_box(m);
    if (best > 1e6 * norm(box.max - box.min)) best = std::numeric_limits<double>::infinity();
    return {best, where};
  }

  const Triangles& triangles() const { return triangles_; }

  // The layer's volume by Steiner's formula for a polyhedral surface offset along its normals
  // up to H: A·H + M·H² + K·H³/3, with M = ½ Σ |e|·θ_e over inner edges (signed dihedral
  // angles, positive where the surface turns away from the layer) and K = Σ angle defects of
  // inner points. Exact for a sphere's or a cylinder's polyhedral offset while H stays below
  // the focal distance; the seam's edges and points count once, as on the uncut surface.
  double layer_volume(double H) const {
    const TriangleSoup& m = layout_.mesh;
    using Pos = std::array<double, 3>;
    auto pos = [&](std::uint32_t i) { return Pos{m.points[i].x, m.points[i].y, m.points[i].z}; };
    std::map<std::pair<Pos, Pos>, std::uint32_t> edge;
    std::map<Pos, double> angles;
    std::map<Pos, bool> boundary;
    double area = 0, mean = 0;
    for (std::uint32_t t = 0; t < m.triangles.size(); ++t) {
      const Triangle& x = m.triangles[t];
      area += 0.5 * norm(cross(m.points[x[1]] - m.points[x[0]], m.points[x[2]] - m.points[x[0]]));
      for (int c = 0; c < 3; ++c) {
        edge[{pos(x[c]), pos(x[(c + 1) % 3])}] = t;
        const Vec3 a = m.points[x[(c + 1) % 3]] - m.points[x[c]],
                   b = m.points[x[(c + 2) % 3]] - m.points[x[c]];
        angles[pos(x[c])] += std::atan2(norm(cross(a, b)), dot(a, b));
        boundary[pos(x[c])] = boundary[pos(x[c])] || on_boundary_[x[c]];
      }
    }
    auto normal = [&](std::uint32_t t) {
      const Triangle& x = m.triangles[t];
      return detail::unit_or_zero(
          cross(m.points[x[1]] - m.points[x[0]], m.points[x[2]] - m.points[x[0]]));
    };
    auto centroid = [&](std::uint32_t t) {
      const Triangle& x = m.triangles[t];
      return (1.0 / 3) * (m.points[x[0]] + m.points[x[1]] + m.points[x[2]]);
    };
    for (const auto& [e, t] : edge) {
      if (!(e.first < e.second)) continue;
      const auto other = edge.find({e.second, e.first});
      if (other == edge.end()) continue;
      const Vec3 n1 = normal(t), n2 = normal(other->second);
      const double turn = std::atan2(norm(cross(n1, n2)), dot(n1, n2));
      const double convex = sign_ * dot(n2 - n1, centroid(other->second) - centroid(t));
      const Vec3 d{e.second[0] - e.first[0], e.second[1] - e.first[1], e.second[2] - e.first[2]};
      mean += 0.5 * norm(d) * (convex >= 0 ? turn : -turn);
    }
    double gauss = 0;
    for (const auto& [p, a] : angles)
      if (!boundary[p]) gauss += 2 * std::numbers::pi - a;
    return area * H + mean * H * H + gauss * H * H * H / 3;
  }

  SurfaceMap(const SurfaceMap&) = delete;  // the tree points into triangles_
  SurfaceMap& operator=(const SurfaceMap&) = delete;

  SurfacePoint at(Vec3 p) const {
    const auto [cp, it] = tree_.closest_point_and_primitive(detail::to_cgal(p));
    const std::size_t t = static_cast<std::size_t>(it - triangles_.begin());
    const Triangle& tri = layout_.mesh.triangles[t];
    const auto& pts = layout_.mesh.points;
    const Vec3 q{cp.x(), cp.y(), cp.z()};
    const std::array<double, 3> b = barycentric(q, pts[tri[0]], pts[tri[1]], pts[tri[2]]);
    constexpr double eps = 1e-9;
    const Vec3 face =
        detail::unit_or_zero(cross(pts[tri[1]] - pts[tri[0]], pts[tri[2]] - pts[tri[0]]));
    Vec3 n = face;
    bool beyond = false;
    if (std::min({b[0], b[1], b[2]}) <= eps) {  // on an edge or a corner: the vertices' normal
      n = detail::unit_or_zero(b[0] * normals_[tri[0]] + b[1] * normals_[tri[1]] +
                               b[2] * normals_[tri[2]]);
      for (int c = 0; c < 3; ++c)
        beyond = beyond || (b[(c + 2) % 3] <= eps && boundary_edge_[t][c]) ||
                 (b[c] >= 1 - eps && on_boundary_[tri[c]]);
    }
    const Vec3 d = p - q;
    SurfacePoint s;
    const auto uv = uv_at(layout_, t, b);
    s.u = uv[0], s.v = uv[1];
    if (beyond) {
      // Past the boundary: height along the rim triangle's normal (as inside it, so h stays
      // continuous across the rim), lateral distance from the rim's normal line.
      const double along = dot(d, face);
      s.h = sign_ * along;
      s.lateral = norm(d - along * face);
    } else {
      // Over the surface h is the distance itself, signed by the side (the normal at q, the
      // vertices' where q is on an edge): continuous, and h = H is the true offset surface.
      s.h = sign_ * (dot(d, n) < 0 ? -norm(d) : norm(d));
      if (layout_.method == LayoutMethod::Free) {
        s.lateral = rim_.empty() ? -std::numeric_limits<double>::infinity()
                                 : -std::sqrt(rim_tree_.squared_distance(detail::to_cgal(q)));
      } else {
        double inside = std::min(s.v, 1 - s.v) * lengths_[1];
        if (!layout_.periodic_u) inside = std::min(inside, std::min(s.u, 1 - s.u) * lengths_[0]);
        s.lateral = -inside;
      }
    }
    return s;
  }

 private:
  const SurfaceParameterization& layout_;
  std::array<double, 2> lengths_;
  double sign_;
  Triangles triangles_;
  Tree tree_;
  std::vector<Vec3> normals_;
  std::vector<std::array<bool, 3>> boundary_edge_;
  std::vector<bool> on_boundary_;
  Segments rim_;  // the surface's boundary edges (a tube's seam is none)
  RimTree rim_tree_;
};

// The slab design sampled on a grid of half the voxel, read back trilinearly.
class SlabSamples {
 public:
  SlabSamples(const FieldSource& design, std::array<double, 3> size, double spacing) {
    const Grid g = make_grid(Box3{{0, 0, 0}, {size[0], size[1], size[2]}},
                             {.voxel_size = spacing, .padding = 2});
    if (g.node_count() > std::size_t(1) << 28)
      throw ResourceError("the slab design would need " + std::to_string(g.node_count()) +
                          " samples at half the voxel; use a coarser voxel");
    field_ = sample_field(design, g);
  }

  float at(double x, double y, double z) const {
    const Grid& g = field_.grid;
    const double c[3] = {(x - g.origin.x) / g.spacing, (y - g.origin.y) / g.spacing,
                         (z - g.origin.z) / g.spacing};
    int i[3];
    double f[3];
    for (int a = 0; a < 3; ++a) {
      const double cl = std::clamp(c[a], 0.0, double(g.dims[a] - 1) - 1e-9);
      i[a] = static_cast<int>(cl), f[a] = cl - i[a];
    }
    double r = 0;
    for (int corner = 0; corner < 8; ++corner) {
      const int dx = corner & 1, dy = (corner >> 1) & 1, dz = corner >> 2;
      const double w = (dx ? f[0] : 1 - f[0]) * (dy ? f[1] : 1 - f[1]) * (dz ? f[2] : 1 - f[2]);
      r += w * field_.values[g.index(i[0] + dx, i[1] + dy, i[2] + dz)];
    }
    return static_cast<float>(r);
  }

 private:
  Field field_;
};

// Coarse cells of a grid (4 voxels a side) that may hold nodes near the layer: those whose
// centre's height and lateral distance (one closest-point search a cell, 64 times fewer than
// the nodes) come within the cell's half diagonal of the layer grown by `margin`. The rest are
// outside the layer by more than the margin. Conservative: h and lateral are 1-Lipschitz
// across a cell whose centre lies within the focal distance; the lateral one is given twice that
// (past it the layer folds, which the job warns of).
class NearMask {
 public:
  NearMask(const SurfaceMap& map, const Grid& grid, double height, double margin) {
    for (int a = 0; a < 3; ++a) n_[a] = (grid.dims[a] + kCell - 1) / kCell;
    marked_.assign(std::size_t(n_[0]) * n_[1] * n_[2], 0);
    const double half = 0.5 * std::sqrt(3.0) * kCell * grid.spacing + margin;
    detail::parallel_for(marked_.size(), 64, [&](std::size_t first, std::size_t last) {
      for (std::size_t c = first; c < last; ++c) {
        const int x = int(c % n_[0]), y = int(c / n_[0] % n_[1]), z = int(c / n_[0] / n_[1]);
        const Vec3 centre = grid.node(0, 0, 0) +
                            (kCell * grid.spacing) * Vec3{x + 0.5, y + 0.5, z + 0.5} -
                            grid.spacing * Vec3{0.5, 0.5, 0.5};
        const SurfacePoint s = map.at(centre);
        // The lateral distance comes through (u, v) over the surface, which distortion can
        // stretch: twice the margin there.
        marked_[c] = s.h > -half && s.h < height + half && s.lateral < 2 * half;
      }
    });
  }
  bool near(int i, int j, int k) const {
    return marked_[i / kCell + std::size_t(n_[0]) * (j / kCell + std::size_t(n_[1]) * (k / kCell))];
  }

 private:
  static constexpr int kCell = 4;
  int n_[3] = {};
  std::vector<std::uint8_t> marked_;
};

struct SurfaceLayer {
  SurfaceLayer(const SurfaceParameterization& layout, std::array<double, 2> lengths,
               const ConformalOptions& options, LatticeDesign design)
      : map(layout, lengths, options.side),
        options(options),
        lengths(lengths),
        design(std::move(design)) {}
  SurfaceMap map;
  ConformalOptions options;
  std::array<double, 2> lengths;
  LatticeDesign design;  // resolved against the slab box
};

// The slab design's sampling step: half the voxel, or a sixteenth of its smallest cell where
// that is coarser. Trilinear reading of a TPMS field (≈ T/2π · f) errs by about s²/8 · 2π/T,
// 0.3 % of T at s = T/16: a few per cent of a voxel, and a fine voxel in a large slab does not
// need billions of samples.
double slab_spacing(const LatticeDesign& d, double voxel) {
  double cell = std::min({d.cell.x, d.cell.y, d.cell.z});
  for (const Blend& b : d.blends)
    cell = std::min({cell, b.tpms.cell.x, b.tpms.cell.y, b.tpms.cell.z});
  return std::max(0.5 * voxel, cell / 16);
}

Box3 slab_box(const std::array<double, 2>& lengths, const ConformalOptions& o) {
  return Box3{{0, 0, 0}, {lengths[0], lengths[1], o.height / o.normal_scale}};
}

}  // namespace

void require_valid(const ConformalOptions& o) {
  if (!positive(o.height)) throw InputError("the layer's height must be positive (mm)");
  if (!positive(o.normal_scale)) throw InputError("the normal scale must be positive");
  for (const auto& l : {o.length_u, o.length_v})
    if (l && !positive(*l)) throw InputError("the slab's lengths must be positive (mm)");
  if (!(o.skin_surface >= 0) || !(o.skin_top >= 0) || !std::isfinite(o.skin_surface) ||
      !std::isfinite(o.skin_top))
    throw InputError("skins must be zero or positive (mm)");
  if (o.skin_surface + o.skin_top >= o.height)
    throw InputError("the skins (" + std::to_string(o.skin_surface + o.skin_top) +
                     " mm together) leave no room in a layer " + std::to_string(o.height) +
                     " mm high");
}

std::array<double, 2> slab_lengths(const SurfaceParameterization& layout,
                                   const LatticeDesign& design, const ConformalOptions& o) {
  double lu = o.length_u.value_or(layout.length_u);
  const double lv = o.length_v.value_or(layout.length_v);
  if (layout.periodic_u) {
    const double cell = design.cell.x;
    lu = cell * std::max(1.0, std::round(lu / cell));
  }
  return {lu, lv};
}

namespace {

// The layer: its surface map (an AABB tree) built once, for the field and for the measures.
std::shared_ptr<const SurfaceLayer> make_layer(const SurfaceParameterization& layout,
                                               const LatticeDesign& design,
                                               const ConformalOptions& options) {
  require_valid(options);
  require_valid(design);
  const std::array<double, 2> lengths = slab_lengths(layout, design, options);
  return std::make_shared<const SurfaceLayer>(layout, lengths, options,
                                              resolve_design(design, slab_box(lengths, options)));
}

FieldSource source_of(std::shared_ptr<const SurfaceLayer> layer) {
  return {.on_grid = [layer](const Grid& grid) -> RowFunction {
    const Vec3 size = slab_box(layer->lengths, layer->options).max;
    auto slab = std::make_shared<const SlabSamples>(design_source(layer->design),
                                                    std::array<double, 3>{size.x, size.y, size.z},
                                                    slab_spacing(layer->design, grid.spacing));
    // Nodes in coarse blocks that lie more than two voxels outside the layer (NearMask) skip
    // the closest-point search and read "two voxels outside".
    const double reach = layer->options.height + 2 * grid.spacing;
    auto near =
        std::make_shared<const NearMask>(layer->map, grid, layer->options.height, 2 * grid.spacing);
    return [layer, slab, near, grid, reach](std::size_t first, std::size_t count, float* values,
                                            const std::uint8_t* need) {
      const ConformalOptions& o = layer->options;
      for_each_needed_node(grid, first, count, need, [&](int i, int j, int k, std::size_t n) {
        if (!near->near(i, j, k)) {
          values[n] = static_cast<float>(reach - o.height);
          return;
        }
        const SurfacePoint s = layer->map.at(grid.node(i, j, k));
        const double outside = std::max({-s.h, s.h - o.height, s.lateral});
        double lattice =
            slab->at(s.u * layer->lengths[0], s.v * layer->lengths[1], s.h / o.normal_scale);
        if (o.skin_surface > 0) lattice = std::min(lattice, s.h - o.skin_surface);
        if (o.skin_top > 0) lattice = std::min(lattice, o.height - o.skin_top - s.h);
        values[n] = static_cast<float>(std::max(outside, lattice));
      });
    };
  }};
}

}  // namespace

FieldSource conformal_source(const SurfaceParameterization& layout, const LatticeDesign& design,
                             const ConformalOptions& options) {
  return source_of(make_layer(layout, design, options));
}

namespace {

// What both maps' fills share: the job's grid, budget, checks and progress.
FillOptions fill_options(const ConformalJobOptions& options) {
  FillOptions f;
  f.grid = options.grid;
  f.keep_islands = options.keep_islands;
  f.check_self_intersections = options.check_self_intersections;
  f.memory_budget = options.memory_budget;
  f.rounding = options.rounding;
  f.progress = options.progress;
  return f;
}

// The field-space map: the layer's own field (it bounds the layer) meshed over the surface's
// box grown by the layer.
FillResult fill_through_field(std::shared_ptr<const SurfaceLayer> layer,
                              const SurfaceParameterization& layout,
                              const ConformalJobOptions& options) {
  FillOptions f = fill_options(options);
  f.design.cell = options.design.cell;  // for the report; the field is the layer's
  f.design.custom = source_of(std::move(layer));
  Box3 box = bounding_box(layout.mesh);
  const double grow = options.layer.height + options.grid.voxel_size;
  box.min = box.min - Vec3{grow, grow, grow}, box.max = box.max + Vec3{grow, grow, grow};
  return fill_field(box, f);
}

// The seed's vertex map: the flat slab filled as a box part (the lattice cut to the slab's
// faces) with the design, carried over vertex by vertex, then validated again (it may fold,
// which the field map cannot).
FillResult fill_by_vertices(ConformalReport& r, const ConformalJobOptions& options,
                            std::array<double, 2> lengths, const Box3& slab) {
  FillOptions f = fill_options(options);
  f.design = options.design;
  const ConformalOptions& o = options.layer;
  if (o.skin_surface > 0 || o.skin_top > 0) {
    // Skins in the slab: its design (blends and all, resolved over the slab) united with solid
    // layers where h = s·z lies under skin_surface or over H − skin_top, as the field map has.
    const FieldSource lattice = design_source(resolve_design(options.design, slab));
    f.design = LatticeDesign{};
    f.design.cell = options.design.cell;  // for the report; the field is the slab's
    f.design.custom = {.on_grid = [lattice, o](const Grid& grid) -> RowFunction {
      const RowFunction rows = bind_source(lattice, grid);
      return [rows, grid, o](std::size_t first, std::size_t count, float* values,
                             const std::uint8_t* need) {
        rows(first, count, values, need);
        for_each_needed_node(grid, first, count, need, [&](int i, int j, int k, std::size_t n) {
          const double h = grid.node(i, j, k).z * o.normal_scale;
          double v = values[n];
          if (o.skin_surface > 0) v = std::min(v, h - o.skin_surface);
          if (o.skin_top > 0) v = std::min(v, o.height - o.skin_top - h);
          values[n] = static_cast<float>(v);
        });
      };
    }};
  }
  // The flat slab is carried over before it is written: rounded after the map, not before.
  f.rounding = CoordinateRounding::None;
  FillResult filled = fill_box(slab, f);
  const auto t0 = std::chrono::steady_clock::now();
  filled.mesh = map_slab_vertices(filled.mesh, r.layout, lengths, options.layer, options.vertex_map,
                                  &r.vertex_map);
  round_coordinates(options.rounding, filled.mesh);  // what the file will hold is validated
  ValidateOptions check;
  check.self_intersections = options.check_self_intersections;
  filled.report.validation = validate_mesh(filled.mesh, check);
  filled.report.stages.push_back(
      {"vertex map", std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count(),
       peak_memory_mb()});
  if (!filled.report.validation.valid()) {
    std::string why;
    for (const std::string& p : filled.report.validation.problems())
      why += (why.empty() ? "" : "; ") + p;
    throw ValidationError("the vertex map folds the layer (" + why +
                          "): it is thicker than the surface bends, or the surface's triangles "
                          "are coarse; the field map (the default) stays valid");
  }
  return filled;
}

std::string mm(double x) {
  char s[32];
  std::snprintf(s, sizeof s, "%.3g mm", x);
  return s;
}

}  // namespace

ConformalResult conformal_fill(const TriangleSoup& surface, const ConformalJobOptions& options) {
  require_valid(options.layer);
  require_valid(options.design);
  ConformalResult result;
  result.layer = options.layer;
  ConformalReport& r = result.report;
  ParameterizeOptions po = options.layout;
  po.progress = options.progress;
  // The vertex map lifts the slab box: it needs the layout to fill the square.
  if (options.map == SlabMap::Vertex) {
    if (po.method == LayoutMethod::Free)
      throw InputError("the vertex map needs the square layout (--layout square or auto)");
    po.method = LayoutMethod::Square;
  }
  auto t0 = std::chrono::steady_clock::now();
  const auto seconds = [&] {
    const auto t = std::chrono::steady_clock::now();
    return std::chrono::duration<double>(t - std::exchange(t0, t)).count();
  };
  r.layout = parameterize_surface(surface, po);
  const StageTime layout_time{"parameterize", seconds(), peak_memory_mb()};
  const ConformalOptions& o = options.layer;
  const std::array<double, 2> lengths = slab_lengths(r.layout, options.design, o);
  r.length_u = lengths[0], r.length_v = lengths[1];
  const Box3 slab = slab_box(lengths, o);
  // The slab design is reviewed as a part of its own (the slab box), before any work.
  std::vector<std::string> warnings =
      review_design(resolve_design(options.design, slab), slab, {.voxel = options.grid.voxel_size});
  const double factor = r.layout.length_u * r.layout.length_v / (lengths[0] * lengths[1]);
  const auto cell = [&](double s) { return options.design.cell.x * std::sqrt(s * factor); };
  const Spread& a = r.layout.area_scale;
  r.cell_size = {cell(a.min), cell(a.p5), cell(a.p50), cell(a.p95), cell(a.max)};
  const double asked = options.design.cell.x;
  if (!options.allow_distortion && (r.cell_size.p5 < 0.5 * asked || r.cell_size.p95 > 2 * asked)) {
    std::string other;
    if (r.layout.other_area_scale)
      other = std::string("; the ") + (r.layout.method == LayoutMethod::Free ? "square" : "free") +
              " layout gives " + mm(cell(r.layout.other_area_scale->p5)) + " to " +
              mm(cell(r.layout.other_area_scale->p95));
    throw InputError(
        "the surface cannot be laid out flat with cells near the size asked: cells of " +
        mm(asked) + " would measure " + mm(r.cell_size.p5) + " to " + mm(r.cell_size.p95) +
        " on it (p5 to p95, " + std::string(layout_method_name(r.layout.method)) + " layout" +
        other +
        "), beyond half to twice; cut it into flatter pieces, or pass "
        "--allow-distortion to write it so");
  }

  r.map = options.map;
  const std::shared_ptr<const SurfaceLayer> layer = make_layer(r.layout, options.design, o);
  FillResult filled = options.map == SlabMap::Field ? fill_through_field(layer, r.layout, options)
                                                    : fill_by_vertices(r, options, lengths, slab);
  result.mesh = std::move(filled.mesh);
  result.fill = std::move(filled.report);
  result.fill.design = tpms_label(options.design);
  for (const Blend& b : options.design.blends) result.fill.design += " + " + tpms_label(b.tpms);

  result.fill.stages.insert(result.fill.stages.begin(), layout_time);
  seconds();  // the fill timed its own stages
  // The output's heights, through the same map.
  const SurfaceMap& map = layer->map;
  std::tie(r.focal_distance, r.focal_at) = map.focal_distance();
  // The fill ran over a box: its input and model are the surface and the layer.
  result.fill.input_triangles = surface.triangles.size();
  result.fill.input_bbox = bounding_box(surface);
  result.fill.model_volume = map.layer_volume(o.height);
  const auto& points = result.mesh.points;
  std::vector<double> h(points.size());
  detail::parallel_for(points.size(), 4096, [&](std::size_t b, std::size_t e) {
    for (std::size_t i = b; i < e; ++i) h[i] = map.at(points[i]).h;
  });
  double worst = -1;
  for (std::size_t i = 0; i < h.size(); ++i) {
    r.height_min = i ? std::min(r.height_min, h[i]) : h[i];
    r.height_max = i ? std::max(r.height_max, h[i]) : h[i];
    if (const double out = std::max(-h[i], h[i] - o.height); out > worst)
      worst = out, r.farthest_at = points[i];
  }

  const double voxel = options.grid.voxel_size;
  if (r.cell_size.p95 > 2 * r.cell_size.p5)
    warnings.push_back("the layout stretches the surface unevenly: cells asked " + mm(asked) +
                       " measure " + mm(r.cell_size.p5) + " to " + mm(r.cell_size.p95) +
                       " on the surface (p5 to p95); a shallower surface, or corners where it "
                       "turns, lay it out more evenly");
  if (r.layout.flips > 0)
    warnings.push_back(std::to_string(r.layout.flips) +
                       " triangles of the surface fold over in its layout; the lattice is torn "
                       "there");
  if (r.focal_distance < o.height)
    warnings.push_back("the layer (" + mm(o.height) +
                       " high) is thicker than the surface's "
                       "smallest radius of curvature on its side (" +
                       mm(r.focal_distance) + " near " + mm(r.focal_at.x) + ", " +
                       mm(r.focal_at.y) + ", " + mm(r.focal_at.z) +
                       "): the layer folds over itself there");
  if (r.height_max > o.height + voxel || r.height_min < -voxel)
    warnings.push_back("the output reaches " + mm(r.height_min) + " to " + mm(r.height_max) +
                       " from the surface, more than a voxel outside 0 to " + mm(o.height) +
                       " (farthest at " + mm(r.farthest_at.x) + ", " + mm(r.farthest_at.y) + ", " +
                       mm(r.farthest_at.z) + ")");
  if (result.mesh.triangles.empty())
    warnings.push_back("the layer came out empty: no lattice lies within it");
  for (std::string& w : warnings) result.fill.warnings.push_back(std::move(w));
  result.fill.stages.push_back({"heights", seconds(), peak_memory_mb()});
  return result;
}

std::string_view surface_side_name(SurfaceSide side) {
  return side == SurfaceSide::Out ? "out" : "in";
}

std::string_view slab_map_name(SlabMap map) {
  return map == SlabMap::Field ? "field" : "vertex";
}

SlabMap slab_map_from_name(std::string_view name) {
  if (name == "field") return SlabMap::Field;
  if (name == "vertex") return SlabMap::Vertex;
  throw InputError("unknown map '" + std::string(name) + "' (use field or vertex)");
}

SurfaceSide surface_side_from_name(std::string_view name) {
  if (name == "out") return SurfaceSide::Out;
  if (name == "in") return SurfaceSide::In;
  throw InputError("unknown side '" + std::string(name) + "' (use out or in)");
}

}  // namespace tpmsfill
