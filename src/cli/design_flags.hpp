// The flags that describe one TPMS (type, style, cell, level or thickness or porosity,
// rotation, origin), shared by the commands that make lattices: fill and conformal.
#pragma once

#include <CLI/CLI.hpp>
#include <optional>
#include <string>
#include <tpmsfill/lattice/tpms.hpp>
#include <vector>

namespace tpmsfill::cli {

struct TpmsArgs {
  std::optional<std::string> lattice;
  bool sheet = false;
  std::vector<double> cell, rotate, origin;
  /// Each "0.3" (mm) or "0.3c" (the seeds' raw C on f).
  std::vector<std::string> levels;
  std::optional<std::string> level, thickness;
  std::optional<double> porosity;
  /// --term A H K L P, flattened: five numbers a term.
  std::vector<double> terms;

  bool any() const {
    return lattice || sheet || !cell.empty() || !rotate.empty() || !origin.empty() ||
           !levels.empty() || level || thickness || porosity || !terms.empty();
  }
};

/// Registers --lattice, --term, --sheet, --levels, --cell, --porosity, --level, --thickness,
/// --rotate and --origin on `sub`.
void add_tpms_options(CLI::App* sub, TpmsArgs& args);

/// What the flags give, on top of `tpms` (a recipe's or the defaults): given flags win.
/// @throws InputError  contradicting flags (--level with --sheet, --levels with --thickness...)
void apply_tpms_flags(const TpmsArgs& args, TpmsOptions& tpms);

}  // namespace tpmsfill::cli
