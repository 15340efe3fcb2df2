/// @file job_settings.hpp
/// @brief What every job that samples fill()'s field (fill, slice) settles first, in one
/// place so their fields cannot drift apart: the settings in the report, the design resolved
/// against the model's box, the band's width and the field source the model clips.
#pragma once

#include <utility>

#include "tpmsfill/field.hpp"
#include "tpmsfill/fill.hpp"
#include "tpmsfill/lattice/compose.hpp"
#include "tpmsfill/lattice/design.hpp"
#include "tpmsfill/report.hpp"
#include "tpmsfill/sampling/classify.hpp"
#include "tpmsfill/sampling/spatial.hpp"
#include "tpmsfill/types.hpp"

namespace tpmsfill::detail {

/// Memory estimates' shared terms: per input triangle the soup (three points, STL-style), the
/// tree's copy and nodes; and a fixed allowance for the process and its libraries (20 MB
/// resident after a fill of a cube, plus the small jobs' scatter over 22 meshes, §27).
inline constexpr double kBytesPerInputTriangle = 260.0;
inline constexpr double kFixedBytes = 28.0 * 1024 * 1024;

/// A size in memory refusals, in --memory's binary units: "6.1 GiB", "150 MiB", bytes below
/// 1 MiB (a budget of "1" is "1 byte", not "1e-09 GB"). (fill.cpp)
std::string memory_text(double bytes);

/// The options' settings into `report` (units, input, design, grading, cell, level, skin,
/// porosities) and the design resolved against the model's box (resolve_design), returned.
/// @param model  in millimetres
LatticeDesign describe_job(const TriangleSoup& model, const FillOptions& options,
                           FillReport& report);

/// The band's half-width in voxels: the options' own, widened so distances reach the skin.
int band_width(const FillOptions& options, double spacing);

/// The compose options fill() uses for `options` (skin, windows), reporting to `progress`.
ComposeOptions compose_options(const FillOptions& options, Progress* progress);

/// The deepest depth (mm) any depth ramp of `design` reads (0: none): the distance below the
/// surface beyond which every ramp is constant.
double depth_reach(const LatticeDesign& design);

/// What the classification found, into the report (fill, either path, and slice).
/// @throws InputError  no node is inside
void record_classification(const FillOptions& options, const Occupancy::PlaneCounts& counts,
                           bool any_inside, FillReport& report);

/// With a skin, `design` (resolved) re-solved so that the part, skin included, has the porosity
/// asked: the lattice's porosity is p / (1 - s), s the skin's share of the model's volume (a
/// coarse sample through `tree`, the index of the inside rule); a warning with both numbers
/// when even the most porous lattice cannot reach it. Before the design is evaluated; the
/// report's level, thickness and unclipped porosity follow. Nothing without a skin or with a
/// design that has no one porosity (fill.cpp). Returns what it solved, for a split job's parts.
std::optional<FillPart::SolvedPorosity> solve_porosity_with_skin(const FillOptions& options,
                                                                 const MeshIndex& tree,
                                                                 LatticeDesign& design,
                                                                 FillReport& report);

/// What solve_porosity_with_skin() solved, into `design` and `report` (a split job's join).
void apply_solved_porosity(const FillPart::SolvedPorosity& solved, LatticeDesign& design,
                           FillReport& report);

/// A warning with the numbers when the part's porosity `got` is more than 5 points from the
/// one asked: a structure's porosity is solved over its whole unit cube, of which the model may
/// cover mostly void or mostly solid; a TPMS's over its cell, which a part a few cells across
/// cuts. Designs without one porosity (graded, blended, custom) are not judged.
void warn_porosity(const LatticeDesign& design, double got, FillReport& report);

/// The output's surface area (mm²) fill's forecast expects of `model` (in mm): the lattice's
/// area per volume over the model's volume plus half the model's surface (fill.cpp).
double expected_output_area(const TriangleSoup& model, const FillOptions& options);

/// A forecast's wall time: `on_two`, seconds on the 2 cores its model was measured on, scaled
/// by the cores TBB may use, as a range from half to twice that (a machine's speed and a
/// model's shape move it by up to about 2x either way).
std::pair<double, double> seconds_range(double on_two);

/// Warnings for measured walls and pores below FillOptions::min_wall and min_pore (with the
/// share of samples, the worst sizes and where they are); nothing without measures.
void warn_printability(const FillOptions& options, double voxel, FillReport& report);

}  // namespace tpmsfill::detail
