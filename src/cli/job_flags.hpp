// The flags that describe fill()'s field and its job: the recipe, a porous structure or a
// TPMS, grading, skin, grid, inside rule, units and memory. fill and slice take the same ones,
// so a slice is the slice of the fill the same flags would make.
#pragma once

#include <CLI/CLI.hpp>
#include <cstdint>
#include <optional>
#include <string>
#include <tpmsfill/fill.hpp>
#include <vector>

#include "cli/design_flags.hpp"

namespace tpmsfill::cli {

struct JobArgs {
  std::string recipe, field;
  std::optional<std::string> inside, units;
  TpmsArgs tpms;
  std::vector<double> grade_range;
  std::optional<double> voxel, skin, scale;
  std::vector<std::string> grade;
  std::string grade_along = "z";
  std::string grade_by;  // a .tsm model's material or a volume file: the ramp's coordinate
  std::optional<int> band;
  bool skin_windows = false;
  std::string memory;
};

/// Registers --recipe, --field, the TPMS flags, --grade, --grade-along, --grade-by, --grade-range,
/// --skin,
/// --skin-windows, --voxel, --inside, --units, --scale, --band and --memory on `sub`.
void add_job_options(CLI::App* sub, JobArgs& args);

/// The recipe (or the defaults) with the flags on top: what is given on the command line wins.
/// @throws InputError  contradicting or malformed flags; a recipe or structure file refused
FillOptions job_options(JobArgs& args);

/// "8G", "512M", "1.5GB", "1000000" → bytes.
/// @throws InputError  not such a size
std::uint64_t parse_bytes(const std::string& text, const std::string& flag = "--memory");

}  // namespace tpmsfill::cli
