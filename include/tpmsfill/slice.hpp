/// @file slice.hpp
/// @brief Stage "slice": printer layers straight from the field fill() meshes, without a mesh
/// (the direct slicing of Li & Fu 2021, applied to fill()'s field).
///
/// For each layer the field φ of fill() (model clipping, design, grading, blends, skin) is
/// sampled on the horizontal plane through the layer's centre, at fill()'s nodes in x and y,
/// and its zero level is traced by marching squares with marching cubes' rules: the same
/// asymptotic decider on ambiguous squares, the same edge parameters clamped into the edge,
/// one vertex per crossed edge shared by the two squares beside it (no welding). The plane's
/// φ at a node is the value fill() would give a node there: a slab of node planes around it
/// is classified and banded, so the model's exact distance reaches it wherever fill()'s would.
///
/// Contours are closed and oriented with the solid on their left: outer boundaries run
/// counter-clockwise seen from above (+z), holes clockwise. They never cross or touch (checked
/// with exact predicates for every layer; a defect throws ValidationError).
///
/// Memory: a few layers are worked on at once (up to 8, one per core), each a slab of planes;
/// the model and its tree; never the grid or a mesh. Layers go to the caller's sink one at a
/// time, in order.
#pragma once

#include <array>
#include <cstdint>
#include <functional>
#include <vector>

#include "tpmsfill/fill.hpp"
#include "tpmsfill/progress.hpp"
#include "tpmsfill/report.hpp"
#include "tpmsfill/types.hpp"

namespace tpmsfill {

// Vec2, Contour, signed_area, MaterialSection and Layer, the plain data of a printer layer,
// are in types.hpp.

/// What a slice will make and cost, forecast before any work (SliceOptions::preflight), for
/// the whole stack (a share split among processes forecasts the same). Contour points are the
/// output's area (fill's forecast: the lattice's area per volume over the model's volume, half
/// the model's surface) over layer × voxel: each layer cuts the surface in lines of π/4 of its
/// area per mm of height, and marching squares puts 4/π points per voxel along a line.
struct SliceForecast {
  std::uint64_t layers = 0;
  std::uint64_t samples = 0;  ///< plane nodes × layers
  double points = 0;          ///< contour points expected (within about 30 %)
  double seconds_low = 0, seconds_high = 0;
};

struct SliceOptions {
  double layer = 0.05;  ///< layer thickness L, mm (> 0)
  /// Height of the first layer's bottom, mm; unset: the model's lowest point. Layers are
  /// stacked from there until one's bottom reaches the model's top.
  std::optional<double> start = {};
  /// Only layers [first_layer, end_layer) of the stack (end 0: to the top): one process's
  /// share when a slice is split among several (MPI). The report then covers those layers.
  std::uint64_t first_layer = 0, end_layer = 0;
  /// The auto inside rule's decision across every share (as FillPartOptions::any_unbalanced).
  std::function<bool(bool)> any_unbalanced = {};
  /// Stages "review", "spatial", ..., then "slice" per layer; unset: the FillOptions' progress.
  Progress* progress = nullptr;
  /// The contours' points as the layer file will hold them (layer_rounding): each placed
  /// strictly inside its grid edge as rounded, so the contours checked are the ones written
  /// and stay simple and disjoint wherever the part sits. A grid finer than four of the
  /// format's steps where the part reaches is refused before any work.
  CoordinateRounding rounding = CoordinateRounding::None;
  /// Called once the design is reviewed and the memory budget checked, before any work, with
  /// the forecast: to show it, or to refuse the job (whatever it throws ends the job).
  std::function<void(const SliceForecast&)> preflight = {};
};

/// One layer's figures, kept for every layer (the report's index).
struct LayerSummary {
  double z = 0;              ///< mm
  double area = 0;           ///< mm²
  std::uint32_t outer = 0;   ///< counter-clockwise contours
  std::uint32_t holes = 0;   ///< clockwise contours
  std::uint64_t points = 0;  ///< contour points
};

struct SliceReport {
  /// The job as fill() reports it: input, units, design, grading, skin, grid (its x and y
  /// nodes are the planes' nodes), inside rule, clean, the model's volume (each layer's section
  /// measured along the rays, as fill measures it, times the layer), stage times and warnings.
  /// samples counts the nodes sampled: plane nodes × layers.
  JobReport job;
  /// The options as the job ran them, the design resolved (as FillResult::resolved):
  /// recipe_json(resolved) reproduces the job.
  FillOptions resolved;
  double layer = 0;  ///< thickness, mm
  std::vector<LayerSummary> layers;
  std::uint64_t contours = 0, holes = 0, points = 0;
  /// Σ area × layer, mm³: the lattice's volume as printed.
  double volume = 0;
  /// 1 − volume / the model's volume (0 without a model volume).
  double porosity() const { return job.model_volume > 0 ? 1.0 - volume / job.model_volume : 0.0; }
  /// Pairs of contour segments tested for crossing or touching with exact predicates.
  std::uint64_t segment_pairs_checked = 0;
  std::uint64_t plane_nodes = 0;  ///< nodes per plane
  int slab_planes = 0;            ///< planes classified per layer
};

/// Receives each layer, in order, from the thread that called slice().
using LayerSink = std::function<void(const Layer& layer)>;

/// Slices the lattice fill(model, options) would mesh into layers of options.layer.
/// FillOptions' mesh-only settings (keep_islands, measure, check_self_intersections,
/// rounding, slab_planes) do not apply: islands are kept (a layer cannot tell them).
/// @throws InputError      as fill() (bad options, no volume, a design refused on review);
///                         a layer thickness that is not positive; a start above the model
/// @throws ResourceError   one slab of planes exceeds the memory budget
/// @throws ValidationError a layer's contours cross or touch (a bug; nothing more is sunk)
/// @throws Cancelled       options.progress cancelled the job
/// @throws whatever the sink throws
SliceReport slice(const TriangleSoup& model, const FillOptions& fill_options,
                  const SliceOptions& options, const LayerSink& sink);

/// @throws InputError  a layer thickness that is not positive, or a start that is not finite
void require_valid(const SliceOptions& options);

/// Layers slice() makes for a model with this box (mm): from the start (or the box's bottom)
/// until one's bottom reaches its top, at least one.
/// @throws InputError  a layer thickness that is not positive, or a start that is not finite
std::uint64_t layer_count(const Box3& model, const SliceOptions& options);

/// Contours of φ < 0 on one plane (grid.dims[2] == 1) by marching squares, oriented as above.
/// Nodes on the plane's border must be positive (outside) for every contour to close. Points
/// are as a file with `rounding` holds them (SliceOptions::rounding).
/// @throws InputError  the field is not one plane, a border node is not positive, or the grid
///                     is finer than `rounding` holds where it reaches
std::vector<Contour> trace_contours(const Field& plane,
                                    CoordinateRounding rounding = CoordinateRounding::None);

/// Exact check of a plane's contours: no two segments cross, touch or overlap except
/// consecutive ones at their shared point, and no contour turns back on itself.
/// @return the number of offending segment pairs (0: the contours are simple and disjoint);
///         `pairs_checked` (if not null) gets the pairs tested
std::uint64_t count_contour_defects(const std::vector<Contour>& contours, double spacing,
                                    std::uint64_t* pairs_checked = nullptr);

/// The JSON object `tpmsfill slice --report` writes (and the folder formats' index.json).
std::string to_json(const SliceReport& report);
/// The human summary `tpmsfill slice` prints.
std::string to_text(const SliceReport& report);

}  // namespace tpmsfill
