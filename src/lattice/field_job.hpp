/// @file field_job.hpp
/// @brief The field job: what every job that samples a lattice's field over a model (fill,
/// slice) settles before its extractor runs (marching cubes, marching squares), in one place so
/// that their fields cannot drift apart: the options checked, the model in millimetres, the
/// settings in the report and the design resolved against the model's box; the stage clock;
/// the band's width and the compose options; the classification's record; the porosity solved
/// with a skin; the estimates' shared terms. The field is sampled whole (fill.cpp) or plane by
/// plane (field_planes.hpp).
#pragma once

#include <chrono>
#include <optional>
#include <string>
#include <type_traits>
#include <utility>

#include "core/job_progress.hpp"
#include "tpmsfill/field.hpp"
#include "tpmsfill/fill.hpp"
#include "tpmsfill/lattice/compose.hpp"
#include "tpmsfill/lattice/design.hpp"
#include "tpmsfill/report.hpp"
#include "tpmsfill/sampling/classify.hpp"
#include "tpmsfill/sampling/spatial.hpp"
#include "tpmsfill/types.hpp"

namespace tpmsfill::detail {

/// What a job on the field starts from: the input, in millimetres, and the design resolved.
struct FieldJob {
  const TriangleSoup* input = nullptr;
  std::optional<TriangleSoup> in_mm;  ///< the input's copy, only when it is in another unit
  LatticeDesign design;               ///< resolved against the model's box (resolve_design)

  /// The model in millimetres.
  const TriangleSoup& model() const { return in_mm ? *in_mm : *input; }
};

/// Checks the options' units, design and skin, reads the model in millimetres, and puts the
/// settings into `report` (units, input, design, grading, cell, level, skin, porosities,
/// printability limits), with the design resolved against the model's box.
/// @throws InputError  the units, the design or the skin are not valid
FieldJob start_field_job(const TriangleSoup& input, const FillOptions& options, JobReport& report);

/// start_field_job() for a design meshed over `bounds` (mm) with no model (fill_field): the
/// model is empty, the report's input box is `bounds`.
/// @throws InputError  as above; units other than mm, a skin or a depth ramp (they need a
///                     model)
FieldJob start_field_job(const Box3& bounds, const FillOptions& options, JobReport& report);

/// Times each stage into the report and announces its start and end to the job's progress
/// (which checks for cancelling at both, also for stages that report nothing themselves).
class StageClock {
 public:
  StageClock(JobReport& report, JobProgress& progress) : report_(report), progress_(progress) {}
  template <class F>
  auto operator()(const char* name, F&& work) {
    progress_.begin_stage(name);
    const auto t0 = std::chrono::steady_clock::now();
    if constexpr (std::is_void_v<decltype(work())>) {
      work();
      record(name, t0);
      progress_.end_stage();
    } else {
      auto result = work();
      record(name, t0);
      progress_.end_stage();
      return result;
    }
  }

 private:
  void record(const char* name, std::chrono::steady_clock::time_point t0) {
    const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    report_.stages.push_back({name, s, peak_memory_mb()});
  }
  JobReport& report_;
  JobProgress& progress_;
};

/// The band's half-width in voxels: the options' own, widened so distances reach the skin.
int band_width(const FillOptions& options, double spacing);

/// The compose options of `options` (skin, windows), reporting to `progress`.
ComposeOptions compose_options(const FillOptions& options, Progress* progress);

/// The deepest depth (mm) any depth ramp of `design` reads (0: none): the distance below the
/// surface beyond which every ramp is constant.
double depth_reach(const LatticeDesign& design);

/// What the classification found, into the report (fill, either path, and slice).
/// @throws InputError  no node is inside
void record_classification(const FillOptions& options, const Occupancy::PlaneCounts& counts,
                           bool any_inside, JobReport& report);

/// With a skin, `design` (resolved) re-solved so that the part, skin included, has the porosity
/// asked: the lattice's porosity is p / (1 - s), s the skin's share of the model's volume (a
/// coarse sample through `tree`, the index of the inside rule); a warning with both numbers
/// when even the most porous lattice cannot reach it. Before the design is evaluated; the
/// report's level, thickness and unclipped porosity follow. Nothing without a skin or with a
/// design that has no one porosity. Returns what it solved, for a split job's parts.
std::optional<FillPart::SolvedPorosity> solve_porosity_with_skin(const FillOptions& options,
                                                                 const MeshIndex& tree,
                                                                 LatticeDesign& design,
                                                                 JobReport& report);

/// What solve_porosity_with_skin() solved, into `design` and `report` (a split job's join).
void apply_solved_porosity(const FillPart::SolvedPorosity& solved, LatticeDesign& design,
                           JobReport& report);

/// A warning with the numbers when the part's porosity `got` is more than 5 points from the
/// one asked: a structure's porosity is solved over its whole unit cube, of which the model may
/// cover mostly void or mostly solid; a TPMS's over its cell, which a part a few cells across
/// cuts. Designs without one porosity (graded, blended, custom) are not judged.
void warn_porosity(const LatticeDesign& design, double got, JobReport& report);

// --- the estimates' shared terms (memory plans and forecasts) -----------------------------

/// Per input triangle the soup (three points, STL-style), the tree's copy and nodes; and a
/// fixed allowance for the process and its libraries (20 MB resident after a fill of a cube,
/// plus the small jobs' scatter over 22 meshes, docs/benchmarks.md §27).
inline constexpr double kBytesPerInputTriangle = 260.0;
inline constexpr double kFixedBytes = 28.0 * 1024 * 1024;

/// What the estimates know of the model (mm): its box, triangles, and the volume and area its
/// lattice's surface scales with.
struct ModelSize {
  Box3 bounds;
  std::uint64_t triangles = 0;
  double volume = 0;  ///< enclosed, as far as the soup tells; at most the box's
  double area = 0;    ///< of its surface (a scan's overlapping shells count twice: more is safe)
};

/// The size of `model` (in mm).
ModelSize model_size(const TriangleSoup& model);

/// How an output estimate reads: the count to expect (the preflight), or a bound on it (memory).
enum class Count { Expected, Bound };

/// The output's surface area (mm²): the lattice's area per volume over the model's volume plus
/// the model's surface where cut cells meet it (half of it expected, all of it as the bound).
double output_area(const ModelSize& model, const FillOptions& options, Count count);

/// A size in memory refusals, in --memory's binary units: "6.1 GiB", "150 MiB", bytes below
/// 1 MiB (a budget of "1" is "1 byte", not "1e-09 GB").
std::string memory_text(double bytes);

/// A forecast's wall time: `on_two`, seconds on the 2 cores its model was measured on, scaled
/// by the cores TBB may use, as a range from half to twice that (a machine's speed and a
/// model's shape move it by up to about 2x either way).
std::pair<double, double> seconds_range(double on_two);

}  // namespace tpmsfill::detail
