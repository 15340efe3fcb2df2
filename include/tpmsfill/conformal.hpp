/// @file conformal.hpp
/// @brief Stage "conformal": a lattice layer of height H that follows a freeform surface
/// (e.g. the multi-morphology microchannels of Yang et al. 2023): a planar slab design, laid
/// onto the surface through its parameterization (parameterize.hpp), then filled, meshed and
/// validated like any lattice.
///
/// The layer is what lies between heights h = 0 and h = H over the surface. The slab reaches
/// it through the field (conformal_source: disks and tubes, the default) or vertex by vertex
/// (map_slab_vertices: disks only). The field map is one-to-one while H stays below the
/// surface's focal distance (its smallest radius of curvature on the layer's side; the vertex
/// map while s·z does): the job estimates that radius and warns with it when H exceeds it.
/// Cells on the surface measure T·√σ_A (the parameterization's area scale); the report gives
/// their spread. The method: docs/method.md, section "Mapping a slab design onto a surface".
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "tpmsfill/field.hpp"
#include "tpmsfill/fill.hpp"
#include "tpmsfill/lattice/design.hpp"
#include "tpmsfill/progress.hpp"
#include "tpmsfill/surface/parameterize.hpp"
#include "tpmsfill/types.hpp"

namespace tpmsfill {

/// Which side of the surface the layer grows to: along its normals (the side its triangles
/// face, counter-clockwise seen from there) or against them.
enum class SurfaceSide { Out, In };

struct ConformalOptions {
  double height = 0;  ///< H, the layer's height above the surface, mm (> 0)
  SurfaceSide side = SurfaceSide::Out;
  /// s: the slab design's z is h / s, so s > 1 stretches the design's cells across the layer
  /// (the normal-offset scale of Yang et al. 2023).
  double normal_scale = 1;
  /// The slab's size along u and v, mm. Unset: the surface's mean lengths along u and v
  /// (SurfaceParameterization::length_u/v), so cells keep their nominal size on average. For a
  /// tube, Lu is rounded to a whole number of the design's cells along x so the lattice closes
  /// across the seam.
  std::optional<double> length_u = {}, length_v = {};
  double skin_surface = 0;  ///< a solid skin this thick on the surface (h < skin), mm
  double skin_top = 0;      ///< a solid skin this thick under the top (h > H − skin), mm
};

struct VertexMapOptions {
  /// Split edges whose mapped midpoint is farther than this from their mapped chord, mm
  /// (0: a fiftieth of the layer's height).
  double chord_tolerance = 0;
  int max_passes = 12;  ///< rounds of splitting at most
};

struct VertexMapReport {
  std::uint64_t split_edges = 0;  ///< edges split to follow the surface
  std::uint64_t clamped = 0;      ///< vertices outside the unit square, moved onto its edge
  double chord_error = 0;         ///< the largest left after splitting, mm
};

/// Maps `slab` vertex by vertex onto the surface: (x, y, z) goes to the surface point at
/// (u, v) = (x/Lu, y/Lv), offset by s·z along the interpolated vertex normal, and edges whose
/// mapped midpoint strays from their mapped chord by more than options.chord_tolerance are
/// split (docs/method.md, section "Mapping a slab design onto a surface").
/// @param[in] slab     a mesh in slab coordinates (e.g. fill() of the slab box with the design)
/// @param[in] layout   a disk's layout on the square (periodic_u false, method Square)
/// @param[in] lengths  Lu, Lv, mm (slab_lengths())
/// @param[in] layer    height, side and normal scale (skins are not used)
/// @throws InputError  a tube's layout or a free one (LayoutMethod::Free), lengths not positive
TriangleSoup map_slab_vertices(const TriangleSoup& slab, const SurfaceParameterization& layout,
                               std::array<double, 2> lengths, const ConformalOptions& layer,
                               const VertexMapOptions& options = {},
                               VertexMapReport* report = nullptr);

/// @throws InputError  height, normal_scale, lengths or skins not positive and finite (skins:
///                     not negative; together under H)
void require_valid(const ConformalOptions& options);

/// The slab sizes options and parameterization give (Lu rounded for a tube: see
/// ConformalOptions::length_u), mm.
std::array<double, 2> slab_lengths(const SurfaceParameterization& layout,
                                   const LatticeDesign& design, const ConformalOptions& options);

/// The layer as a field source (field.hpp), mm:
///
///   φ = max(φ_slab, min(φ_design, skins)),   φ_slab = max(−h, h − H, lateral)
///
/// with h a point's signed height over the surface (along the normal at its closest point, on
/// `side`), φ_design the slab design at (u·Lu, v·Lv, h/s), lateral minus the distance to the
/// surface's boundary over the surface (a tube's seam is no boundary) and the distance from
/// the boundary's normal line past it, and skins solid where h < skin_surface or
/// h > H − skin_top. `design` is resolved against the slab box (resolve_design). `layout` must
/// outlive the source.
/// @throws InputError  invalid options or design
FieldSource conformal_source(const SurfaceParameterization& layout, const LatticeDesign& design,
                             const ConformalOptions& options);

/// How the slab reaches the surface: through the field (conformal_source: the default) or the
/// vertex map of Yang et al. 2023 (map_slab_vertices: disks on the square layout; skins are made
/// in the slab before it is lifted; the mapped mesh is
/// validated and refused with its intersecting pairs where it folds).
enum class SlabMap { Field, Vertex };

struct ConformalJobOptions {
  ConformalOptions layer;
  SlabMap map = SlabMap::Field;
  VertexMapOptions vertex_map;  ///< SlabMap::Vertex
  LatticeDesign design;         ///< in slab coordinates (x along u, y along v, z up the layer)
  ParameterizeOptions layout;   ///< the vertex map takes the square layout (Auto: the square)
  /// Write the layer even where the layout gives cells under half or over twice the size asked
  /// (p5 or p95 on the surface); otherwise such a job is refused before the fill.
  bool allow_distortion = false;
  GridOptions grid;  ///< voxel size (mm) and padding of the fill's grid
  bool keep_islands = false;
  bool check_self_intersections = true;
  std::uint64_t memory_budget = 0;  ///< as FillOptions
  /// As FillOptions::rounding: the output rounded as its file will hold it before it is
  /// validated (both maps; rounding_for(format), io.hpp).
  CoordinateRounding rounding = CoordinateRounding::Float;
  Progress* progress = nullptr;
};

struct ConformalReport {
  SurfaceParameterization layout;     ///< the parameterization, with its distortion
  double length_u = 0, length_v = 0;  ///< the slab's size used, mm
  /// Cell size on the surface along the design's x (T·√σ_A over the triangles, area-weighted).
  Spread cell_size;
  /// The surface's smallest radius of curvature on the layer's side (edge dihedral angles),
  /// mm (infinity: flat or curving away), and where.
  double focal_distance = 0;
  Vec3 focal_at = {};
  /// Signed heights of the output's vertices above the surface (h), mm: the layer's measured
  /// extent (0 and H up to the marching cubes' vertex error, a fraction of a voxel).
  double height_min = 0, height_max = 0;
  Vec3 farthest_at = {};  ///< the output vertex farthest outside 0..H
  SlabMap map = SlabMap::Field;
  VertexMapReport vertex_map;  ///< SlabMap::Vertex: edges split, vertices clamped, chord error
};

struct ConformalResult {
  TriangleSoup mesh;  ///< closed, 2-manifold, outward, no self-intersections (validated)
  FillReport fill;    ///< the fill's report (warnings include the layer's)
  ConformalReport report;
  ConformalOptions layer;  ///< the layer as it ran
};

/// Lays `surface` out (parameterize_surface), maps the slab design onto it and meshes the
/// layer's own field over its box with fill_field() (the vertex map: fill() of the flat slab,
/// carried over), then measures the output's heights.
/// @throws as parameterize_surface, require_valid, fill_field(), fill()
ConformalResult conformal_fill(const TriangleSoup& surface, const ConformalJobOptions& options);

/// The fill's report (report.hpp's to_json) with a "conformal" object: the layer's settings,
/// the layout (loops, seam, corners, flips, distortion spreads), cell sizes, focal distance
/// and measured heights.
std::string to_json(const ConformalResult& result);
/// The fill's summary followed by the layer's lines.
std::string to_text(const ConformalResult& result);

std::string_view surface_side_name(SurfaceSide side);  ///< "out", "in"
/// @throws InputError  neither "out" nor "in"
SurfaceSide surface_side_from_name(std::string_view name);
std::string_view slab_map_name(SlabMap map);  ///< "field", "vertex"
/// @throws InputError  neither "field" nor "vertex"
SlabMap slab_map_from_name(std::string_view name);

}  // namespace tpmsfill
