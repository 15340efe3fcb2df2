/// @file fill.hpp
/// @brief The whole pipeline: a TPMS lattice clipped to a closed mesh, validated.
///
///   grid → spatial → classify → voxel band → band distances → compose (with the design's
///   field source) → marching cubes → islands → validate
///
/// Each stage is public (its own header) for callers who compose their own pipeline; fill()
/// is the sequence with the report filled in. Inside is, by default, the generalized winding
/// number w ≥ ½ of the cleaned input (clean.hpp, classify.hpp), so scans with holes, flipped
/// faces, overlapping shells and self-intersections get the lattice a person expects.
#pragma once

#include <cmath>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <optional>
#include <string_view>
#include <vector>

#include "tpmsfill/grid.hpp"
#include "tpmsfill/io.hpp"
#include "tpmsfill/lattice/design.hpp"
#include "tpmsfill/mesh/clean.hpp"
#include "tpmsfill/progress.hpp"
#include "tpmsfill/report.hpp"
#include "tpmsfill/sampling/classify.hpp"
#include "tpmsfill/sampling/voxel.hpp"
#include "tpmsfill/types.hpp"
#include "tpmsfill/units.hpp"

namespace tpmsfill {

/// What a fill will make and cost, known before any work (forecast_fill, FillOptions::preflight).
/// The time is a model of the job's own stages (per grid sample: classification, band, compose
/// and marching cubes; per output triangle: islands, validation and the write; per input
/// triangle: reading and the tree), fitted to the femur and tube jobs of docs/benchmarks.md §4
/// on 2 cores and scaled by the cores the job may use; a range, since a machine's speed and a
/// model's shape move it by up to about 2× either way.
struct FillForecast {
  std::uint64_t samples = 0;       ///< grid nodes
  double triangles = 0;            ///< output triangles expected (within about 30 %)
  std::uint64_t memory_bytes = 0;  ///< the peak planned (streamed by slabs when over the budget)
  double seconds_low = 0;          ///< wall time, the quick end of the range
  double seconds_high = 0;         ///< the slow end
  double seconds() const { return std::sqrt(seconds_low * seconds_high); }  ///< the middle
};

struct FillOptions {
  /// The unit the model's coordinates are in (and a further scale): fill() works, and its
  /// output and report are, in millimetres. A model that this makes smaller than one cell is
  /// refused with the likely unit named (review_design).
  ModelUnits units = {};
  GridOptions grid;  ///< voxel size (mm) and padding
  /// Type, network/sheet, cell size, level, thickness or porosity, rotation, origin; grading,
  /// blends or a custom field source (design.hpp). Porosities are solved and ramps without
  /// positions span the model (resolve_design); FillResult::resolved holds what was resolved.
  LatticeDesign design;
  /// A solid shell this thick (mm) inside the model's surface, united with the lattice (0:
  /// none). The band is widened so that its distances reach that deep.
  double skin = 0;
  /// Open the skin where the lattice's pores meet it (compose.hpp), so the void can drain;
  /// by default the skin is closed (holes-free).
  bool skin_windows = false;
  BandOptions band;  ///< band half-width in voxels
  /// What counts as inside. Winding: clean the input (clean_soup), cap its holes and classify
  /// by the generalized winding number. Parity: classify the input as it is by the parity of
  /// crossings (the method paper's rule, for closed meshes whose shells do not overlap).
  /// Unset (auto): the winding number by signed crossings on the input as it is; if any row
  /// finds it open or inside out there (Occupancy::unbalanced_rows), clean and cap as Winding
  /// does. Auto and Winding give the same inside; auto skips cleaning what needs none.
  std::optional<InsideRule> inside;
  /// Compute the model's distance at every node instead of the band only (the paper's
  /// reference, for comparing distance-query counts; same surface, much slower).
  bool full_field = false;
  /// Keep lattice pieces that do not touch the main body of their part of the model
  /// (by default they are removed: they cannot be printed).
  bool keep_islands = false;
  /// Search the output for self-intersections before accepting it (exact predicates).
  bool check_self_intersections = true;
  /// How the output is validated. Proof: where marching cubes' construction proves the
  /// output valid (marching_cubes_proved on the whole grid, or SlabMarchingCubes slab by slab
  /// in one process), its proof is checked and nothing is searched; other jobs (split among
  /// processes) are searched. Full:
  /// every output searched as a mesh from anywhere would be (the oracle; slower). Both give
  /// the same verdict; FillReport::validation.validated_by says which way was taken.
  enum class Validation { Proof, Full };
  Validation validation = Validation::Proof;
  /// Measure pore and wall sizes and the void's connectivity into the report (measure.hpp).
  /// Off by default: two distance transforms of the grid and one labelling cost about as much
  /// as the rest of the pipeline on small jobs (docs/benchmarks.md).
  bool measure = false;
  /// Printability: the thinnest wall (or strut) and the narrowest pore the process can make,
  /// mm (0: no limit). Measured walls and pores below them are warned about, with the share of
  /// samples, the worst sizes and where they are (LatticeMeasures' SizeDistribution::smallest,
  /// below_limit). Needs `measure`.
  double min_wall = 0, min_pore = 0;
  /// Round the output's coordinates as the file will hold them before validating, so that the
  /// file holds exactly the mesh that was validated (rounding_for(format): Float for STL,
  /// ThreeMf for 3MF). fill_to_file() uses the output's rounding when that is ThreeMf.
  CoordinateRounding rounding = CoordinateRounding::Float;
  /// What the job must fit in, bytes (0: half of physical memory). A job whose grid does not
  /// fit goes slab by slab (slab_planes): the same mesh, bit for bit, in the memory of a slab
  /// and the output; one that does not fit even so is refused with a voxel size that would.
  std::uint64_t memory_budget = 0;
  /// Node planes per slab: 0 chooses (the whole grid when it fits the budget, else the thickest
  /// slabs that do); > 0 forces slabs this thick whatever the budget. --measure needs the whole
  /// grid.
  int slab_planes = 0;
  Progress* progress = nullptr;
  /// Called once the options, the design's review and the memory plan have passed, before any
  /// work, with the job's forecast: to show it, or to refuse the job (whatever it throws ends
  /// the job, nothing written). The command line refuses outputs over 2 GB or jobs over an
  /// hour unless told --yes.
  std::function<void(const FillForecast&)> preflight = {};
};

/// "proof" or "full" (FillOptions::Validation).
/// @throws InputError  any other name
FillOptions::Validation validation_from_name(std::string_view name);
const char* validation_name(FillOptions::Validation validation);

struct FillResult {
  TriangleSoup mesh;  ///< closed, 2-manifold, outward, no self-intersections (validated)
  FillReport report;
  /// The options as the job ran them: the design resolved (porosities solved into levels or
  /// thicknesses, ramp positions fixed from the model's box). recipe_json(resolved) is the
  /// recipe that reproduces the job exactly (recipe.hpp); the CLI puts it into the report.
  FillOptions resolved;
};

/// Fills `model` with the lattice.
/// @param[in] model  any triangle soup in options.units (holes, flips, overlaps and duplicates
///                   allowed)
/// @throws InputError       bad options, a model without a usable triangle, one that encloses
///                          no volume, or a design that cannot come out as asked on it
///                          (review_design: a model smaller than a cell, a voxel over half a
///                          cell, a level that leaves no solid, ...); doubtful designs are
///                          warned about in report.warnings instead
/// @throws ResourceError    the job exceeds the memory budget (message names a voxel size
///                          that fits)
/// @throws ValidationError  the output failed validation (nothing to write; a bug)
/// @throws Cancelled        options.progress cancelled the job
FillResult fill(const TriangleSoup& model, const FillOptions& options);

/// Fills a box part, such as a test coupon or a flat slab: fill() of the box's surface (its
/// twelve triangles), so the lattice is cut to the box's faces exactly as to any model's.
/// @param[in] box  in options.units; @pre not empty
/// @throws as fill()
FillResult fill_box(const Box3& box, const FillOptions& options);

/// The design's own field meshed over the grid of `bounds` (make_grid(bounds, options.grid)),
/// with no model to clip it: for a design that bounds its solid itself, such as a lattice
/// layer's field (FillOptions::design.custom, conformal.hpp). The grid's outermost nodes are
/// taken as outside, so the mesh is closed where the solid reaches them. Islands are judged
/// over the whole grid as one part; the mesh is validated as fill()'s. The report has no
/// input (no triangles, no rays; its box is `bounds`) and no model volume.
/// @param[in] bounds  mm (options.units must be mm)
/// @throws InputError       as fill(); units other than mm, a skin or a depth ramp (they
///                          follow a model's surface)
/// @throws ResourceError    the whole grid does not fit the memory budget (no slabs without a
///                          model)
/// @throws ValidationError, Cancelled  as fill()
FillResult fill_field(const Box3& bounds, const FillOptions& options);

/// fill(), with the mesh written to `path` instead of returned (result.mesh stays empty): the
/// same bytes as write_mesh(path, fill(model, options).mesh, write), and as atomic. A job whose
/// grid and mesh fit options.memory_budget runs as fill() does and is written at the end;
/// a larger one (or one given FillOptions::slab_planes) goes slab by slab and streams: the
/// mesh is never held whole, only a slab's share of it. Its triangles spill to a temporary
/// file beside `path` (removed however the job ends; the folder needs room for about 30 bytes
/// per triangle beside the output), islands are judged once the last slab is done, and the
/// mesh is validated and written a few cell layers at a time. Nothing is left at `path` unless
/// the mesh is valid.
/// @throws InputError       as fill(); a `path` whose extension names no format (before any
///                          work)
/// @throws IoError          `path`'s folder cannot be written, or the disk is full
/// @throws ResourceError, ValidationError, Cancelled  as fill()
FillResult fill_to_file(const TriangleSoup& model, const FillOptions& options,
                        const std::filesystem::path& path, const WriteOptions& write = {});

/// One process's share of a fill split along z across processes (tpmsfill under mpirun): the
/// field, marching cubes and the masks islands need for node planes [first_plane, end_plane)
/// of the job's grid (fill_grid). Plain data, for the caller to send to the process that
/// finishes the job with fill_parts().
struct FillPart {
  int first_plane = 0, end_plane = 0;
  /// The points of its node layers, numbered from 0, and its cell layers' triangles; those of
  /// its last cell layer may refer to the next part's first points (ids from points.size() on,
  /// in that part's numbering shifted by points.size()).
  TriangleSoup mesh;
  /// Where its node layers' points and its cell layers' triangles start in `mesh`, for planes
  /// first_plane .. end_plane (the last entries: the totals): what streaming it needs
  /// (SlabMarchingCubes::first_point, first_triangle).
  std::vector<std::uint64_t> layer_points, layer_triangles;
  Regions inside_runs, solid_runs;             ///< its planes' rows (append_runs)
  std::vector<Occupancy::PlaneCounts> counts;  ///< per plane
  std::vector<std::uint64_t> band_nodes;       ///< per plane
  CleanReport clean;                           ///< when the input was cleaned (winding rule)
  double seconds = 0;                          ///< the part's wall time
  /// With a skin sharing --porosity: the lattice's level or thickness solved for the whole part
  /// (every part solves the same), the lattice's own porosity and the solve's warnings, which
  /// the joined report and its recipe state.
  struct SolvedPorosity {
    double level = 0, thickness = 0, lattice_porosity = 0;
    std::vector<std::string> warnings;
  };
  std::optional<SolvedPorosity> solved_porosity;
};

struct FillPartOptions {
  int first_plane = 0, end_plane = 0;  ///< a range of fill_grid()'s node planes
  /// The auto inside rule's decision across every part: given whether this part's planes find
  /// the input open or inside out, whether any part's do (an MPI all-reduce). Unset: this
  /// part decides alone (parts may then clean differently: give it for a split job).
  std::function<bool(bool)> any_unbalanced = {};
};

/// The grid fill() samples for `model`, to split among processes.
/// @throws InputError  as fill()'s options checks
Grid fill_grid(const TriangleSoup& model, const FillOptions& options);

/// One part of a split fill (see FillPart). Every process reads the same model and options.
/// @throws InputError  as fill(); a range that is not within the grid
FillPart fill_part(const TriangleSoup& model, const FillOptions& options,
                   const FillPartOptions& part);

/// The job finished from its parts, in plane order, covering the grid: islands, validation and
/// the report, with the same mesh, bit for bit, as fill(model, options).
/// @throws InputError       the parts do not cover the grid in order; as fill()
/// @throws ValidationError  as fill()
FillResult fill_parts(const TriangleSoup& model, const FillOptions& options,
                      std::vector<FillPart> parts);

/// fill_parts(), written to `path` as fill_to_file() writes fill()'s mesh (the same bytes):
/// `count` parts are taken from `next_part` one at a time, in plane order. When the job is over
/// options.memory_budget (or slab_planes is set) each part's mesh is spilled as it arrives and
/// the output is streamed, so the process finishing the job holds one part, never the whole
/// mesh; otherwise the parts are joined and written as fill_parts() joins them.
/// @throws as fill_parts() and fill_to_file(); whatever next_part throws
FillResult fill_parts_to_file(const TriangleSoup& model, const FillOptions& options, int count,
                              const std::function<FillPart()>& next_part,
                              const std::filesystem::path& path, const WriteOptions& write = {});

/// The forecast of fill_to_file(model, options, ...) on the cores TBB may use, without
/// allocating anything (beyond a copy in millimetres when the units are not): what
/// FillOptions::preflight is given, for callers that want it before calling fill.
/// @throws InputError  bad units
FillForecast forecast_fill(const TriangleSoup& model, const FillOptions& options);

/// Bytes fill() is estimated to need at most for `model` (in options.units), without
/// allocating anything (beyond a copy in millimetres when the units are not): the whole grid's
/// fields, tree and output when they fit options.memory_budget, else those of the thickest slabs
/// that do.
std::uint64_t estimate_fill_memory(const TriangleSoup& model, const FillOptions& options);

/// Half of the physical memory (the default budget), bytes.
std::uint64_t default_memory_budget();

}  // namespace tpmsfill
