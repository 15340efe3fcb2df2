#include "cli/design_flags.hpp"

#include <tpmsfill/error.hpp>

namespace tpmsfill::cli {
namespace {

Vec3 three(const std::vector<double>& v) {
  return {v[0], v[1], v[2]};
}

}  // namespace

void add_tpms_options(CLI::App* sub, TpmsArgs& args) {
  sub->add_option("--lattice", args.lattice,
                  "primitive, gyroid, diamond, iwp, neovius, frd, lidinoid or splitp (default "
                  "gyroid)");
  sub->add_flag("--sheet", args.sheet, "Sheet (shell) lattice instead of a network");
  sub->add_option("--levels", args.levels,
                  "A sheet between two levels C1 C2 in mm (C1 <= f/|grad f| <= C2): walls of "
                  "thickness C2 - C1 off the minimal surface, e.g. --levels 0 0.4")
      ->expected(2);
  sub->add_option("--cell", args.cell, "Cell size in mm: one value, or three for x y z (default 2)")
      ->expected(1, 3);
  sub->add_option("--porosity", args.porosity,
                  "Void fraction to reach, e.g. 0.7: solves the network level or the sheet "
                  "thickness over a sampled unit cell (any type)");
  sub->add_option("--level", args.level,
                  "Network level in mm: 0 is the minimal surface, positive thins the struts "
                  "(default 0)");
  sub->add_option("--thickness", args.thickness, "Sheet wall thickness in mm (default 0.3)");
  sub->add_option("--rotate", args.rotate,
                  "Rotate the lattice by RX RY RZ degrees (about x, then y, then z)")
      ->expected(3);
  sub->add_option("--origin", args.origin, "Shift the lattice's phase origin to X Y Z (mm)")
      ->expected(3);
}

void apply_tpms_flags(const TpmsArgs& args, TpmsOptions& tpms) {
  if (args.lattice) tpms.type = tpms_type_from_name(*args.lattice);
  if (args.sheet || !args.levels.empty()) tpms.style = TpmsStyle::Sheet;
  if (!args.levels.empty()) {  // walls between two levels: a sheet off the minimal surface
    if (args.level || args.thickness || args.porosity)
      throw InputError(
          "--levels sets the sheet's walls; it takes no --level, --thickness or "
          "--porosity");
    if (!(args.levels[1] > args.levels[0]))
      throw InputError("--levels C1 C2 needs C1 < C2 (mm), not " + std::to_string(args.levels[0]) +
                       " and " + std::to_string(args.levels[1]));
    tpms.thickness = args.levels[1] - args.levels[0];
    tpms.level = -0.5 * (args.levels[0] + args.levels[1]);
    tpms.porosity.reset();
  }
  if (!args.cell.empty()) {
    if (args.cell.size() != 1 && args.cell.size() != 3)
      throw InputError("--cell takes one size or three (x y z), in mm");
    tpms.cell =
        args.cell.size() == 1 ? Vec3{args.cell[0], args.cell[0], args.cell[0]} : three(args.cell);
  }
  const bool sheet = tpms.style == TpmsStyle::Sheet;
  if (sheet && args.level)
    throw InputError("--level is for network lattices; use --thickness with --sheet");
  if (!sheet && args.thickness) throw InputError("--thickness needs --sheet");
  if (args.porosity && (args.level || args.thickness))
    throw InputError("--porosity sets the " + std::string(sheet ? "thickness" : "level") +
                     "; give one or the other");
  if (args.level) tpms.level = *args.level, tpms.porosity.reset();
  if (args.thickness) tpms.thickness = *args.thickness, tpms.porosity.reset();
  if (args.porosity) tpms.porosity = *args.porosity;
  if (!args.rotate.empty()) tpms.rotation = rotation_from_euler(three(args.rotate));
  if (!args.origin.empty()) tpms.origin = three(args.origin);
}

}  // namespace tpmsfill::cli
