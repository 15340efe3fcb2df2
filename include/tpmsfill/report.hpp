/// @file report.hpp
/// @brief Stage "report": what a job on a lattice's field did (JobReport) and what fill() made
/// of it (FillReport), as data, JSON and a human summary.
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "tpmsfill/io.hpp"
#include "tpmsfill/lattice/measure.hpp"
#include "tpmsfill/mesh/clean.hpp"
#include "tpmsfill/mesh/validate.hpp"
#include "tpmsfill/types.hpp"

namespace tpmsfill {

/// Wall time of one stage and the process's peak resident memory when it ended.
struct StageTime {
  std::string name;
  double seconds = 0;
  double peak_memory_mb = 0;  ///< high-water mark of the whole process so far (getrusage)
};

/// A lattice piece removed as an island (FillOptions::keep_islands unset).
struct RemovedIsland {
  double volume = 0;  ///< mm^3
  Box3 bbox;          ///< mm
};

/// What every job on a lattice's field reports, whatever it extracts from the field (fill's
/// mesh, slice's layers): provenance, input, settings, grid, inside/outside, memory, stage
/// times and warnings.
struct JobReport {
  // --- provenance: set by the caller (the CLI), as the recipe is; empty: null in to_json ---
  std::string input_path;    ///< the file read
  std::string input_sha256;  ///< of its bytes as stored (hex)
  std::string command_line;  ///< the full command, shell-quoted
  std::string version;       ///< the tool's version
  // --- input and settings ---------------------------------------------------------------
  std::string units = "mm";  ///< what the input's coordinates were read as (units.hpp)
  double scale = 1;          ///< the further scale applied to them
  double mm_per_unit = 1;    ///< the two together: millimetres per input coordinate
  std::uint64_t input_triangles = 0;
  Box3 input_bbox;                        ///< mm (after units and scale)
  std::string design;                     ///< "gyroid network", "diamond sheet", ...
  std::string grading;                    ///< "porosity 0.5→0.8 along depth", ... ("" none)
  Vec3 rotation_degrees;                  ///< the lattice's rotation as Euler angles
  Vec3 cell;                              ///< mm
  double level = 0;                       ///< mm (network), or raw C where level_unit says so
  double thickness = 0;                   ///< mm (sheet), or raw C where level_unit says so
  std::string level_unit = "mm";          ///< "mm", or "c": the seeds' raw C on f
  double skin = 0;                        ///< mm (0: none)
  std::optional<double> porosity_target;  ///< what --porosity asked (level/thickness solved)
  bool sheet = false;                     ///< the base lattice is a sheet
  double min_wall = 0, min_pore = 0;      ///< printability limits, mm (0: none; FillOptions)
  /// The recipe that reproduces the job, JSON (recipe_json(FillResult::resolved), recipe.hpp),
  /// for the caller to set: fill() does not write recipes. Empty: null in to_json.
  std::string recipe;
  // --- grid and field -------------------------------------------------------------------
  Grid grid;
  std::uint64_t samples = 0;           ///< grid nodes
  std::uint64_t band_nodes = 0;        ///< nodes with an exact distance
  std::uint64_t distance_queries = 0;  ///< closest-point queries made
  std::uint64_t rows = 0;              ///< grid rows classified, one ray each
  std::uint64_t crossings = 0;         ///< ray/triangle crossings counted
  std::uint64_t odd_rows = 0;          ///< rows with an odd crossing count (input not closed)
  // --- inside/outside (classify.hpp) -----------------------------------------------------
  std::string inside_rule;         ///< "parity" or "winding"
  CleanReport clean;               ///< what the clean stage found and did (winding rule only)
  std::uint64_t overlap_rows = 0;  ///< rows where shells overlap (winding rule)
  std::uint64_t parity_disagreements = 0;  ///< nodes where winding and parity differ
  std::uint64_t cap_evaluations = 0;       ///< nodes that needed the hole caps' winding number
  /// The clean stage ran (winding; auto when the input needed it).
  bool cleaned() const { return clean.input_triangles > 0; }
  std::uint64_t estimated_memory_bytes = 0;
  /// Processes the field and its extraction were split among (fill_parts; MPI ranks)
  int ranks = 1;
  double model_volume = 0;  ///< mm^3, enclosed by the input (measured along the rays)
  /// Of the infinite lattice (one cell, sampled); NaN (JSON null) when a grading varies the
  /// porosity, level or thickness through the part.
  double unclipped_porosity = 0;
  std::vector<StageTime> stages;      ///< in pipeline order
  std::vector<std::string> warnings;  ///< one sentence each

  double total_seconds() const;
};

/// What fill() reports: the job, and the mesh it made (the written mesh's figures are its
/// validation's).
struct FillReport : JobReport {
  bool full_field = false;  ///< distances at every node (--full-field)
  /// 0: the whole grid was held at once; else node planes per slab (FillOptions::slab_planes)
  int slab_planes = 0;
  std::uint64_t islands_removed = 0;  ///< floating pieces dropped (not with --keep-islands)
  double islands_volume = 0;          ///< their volume, mm^3
  /// The largest removed islands, largest first (at most 10).
  std::vector<RemovedIsland> largest_islands;
  std::optional<LatticeMeasures> measures;  ///< pores, walls, labyrinths (FillOptions::measure)
  std::uint64_t cavities = 0;  ///< closed voids in the output (negative-volume surfaces)
  double cavities_volume = 0;  ///< their volume, mm^3
  MeshValidity validation;     ///< of the written mesh

  std::uint64_t vertices() const { return validation.vertices; }
  std::uint64_t triangles() const { return validation.triangles; }
  std::uint64_t components() const { return validation.components; }
  double lattice_volume() const { return validation.volume.value_or(0); }  ///< mm^3
  double surface_area() const { return validation.area; }                  ///< mm^2
  /// 1 − lattice_volume / model_volume (0 without a model volume).
  double porosity() const { return model_volume > 0 ? 1.0 - lattice_volume() / model_volume : 0.0; }
  /// Surface area per solid volume, mm⁻¹ (scaffold designers' specific surface area).
  double specific_surface() const {
    return lattice_volume() > 0 ? surface_area() / lattice_volume() : 0.0;
  }
  /// Surface area per model volume, mm⁻¹ (surface density of the filled part).
  double surface_density() const { return model_volume > 0 ? surface_area() / model_volume : 0.0; }
};

/// The JSON object of `tpmsfill fill --report` (2-space indent; field list in docs/cli.md).
std::string to_json(const FillReport& report);
/// The human summary `tpmsfill fill` prints: a few aligned lines, one stage table.
std::string to_text(const FillReport& report);

/// What a 3MF of the lattice carries (MeshMetadata, io.hpp): `given`, with a description of the
/// lattice (design, cell, porosity, size, what validation proved) when it has none, and the
/// report (to_json) attached as "Metadata/tpmsfill-report.json".
MeshMetadata lattice_metadata(const FillReport& report, MeshMetadata given = {});

/// Peak resident memory of this process so far, MB.
double peak_memory_mb();

}  // namespace tpmsfill
