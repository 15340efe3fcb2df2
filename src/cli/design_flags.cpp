#include "cli/design_flags.hpp"

#include <cmath>
#include <exception>
#include <tpmsfill/error.hpp>

namespace tpmsfill::cli {
namespace {

Vec3 three(const std::vector<double>& v) {
  return {v[0], v[1], v[2]};
}

struct Level {
  double value;
  LevelUnit unit;
};

// "0.3" in mm, "0.3c" the seeds' raw C.
Level parse_level(const std::string& flag, const std::string& text) {
  const bool raw = !text.empty() && (text.back() == 'c' || text.back() == 'C');
  const std::string number = raw ? text.substr(0, text.size() - 1) : text;
  std::size_t used = 0;
  double v = 0;
  try {
    v = std::stod(number, &used);
  } catch (const std::exception&) {
    used = 0;
  }
  if (number.empty() || used != number.size() || !std::isfinite(v))
    throw InputError(flag + " " + text + ": not a number of mm (0.3) or a raw level C on f (0.3c)");
  return {v, raw ? LevelUnit::Raw : LevelUnit::Millimetre};
}

}  // namespace

void add_tpms_options(CLI::App* sub, TpmsArgs& args) {
  sub->add_option("--lattice", args.lattice,
                  "primitive, gyroid, diamond, iwp, neovius, frd, lidinoid, splitp or fourier "
                  "(default gyroid)");
  sub->add_option(
         "--term", args.terms,
         "A fourier lattice's term A H K L P: A cos(2 pi (H x/Tx + K y/Ty + L z/Tz) + P), "
         "whole periods H K L per cell, phase P in radians; repeat for each term, e.g. "
         "--lattice fourier --term 1 1 0 0 0 --term 1 0 1 0 0 --term 1 0 0 1 0 (Schwarz P)")
      ->expected(5)
      ->multi_option_policy(CLI::MultiOptionPolicy::TakeAll);
  sub->add_flag("--sheet", args.sheet, "Sheet (shell) lattice instead of a network");
  sub->add_option("--levels", args.levels,
                  "A sheet between two levels C1 C2 in mm (C1 <= f/|grad f| <= C2): walls of "
                  "thickness C2 - C1 off the minimal surface, e.g. --levels 0 0.4; or raw, on f "
                  "as the seeds write C: --levels -0.3c 0.3c")
      ->expected(2);
  sub->add_option("--cell", args.cell, "Cell size in mm: one value, or three for x y z (default 2)")
      ->expected(1, 3);
  sub->add_option("--porosity", args.porosity,
                  "Void fraction to reach, e.g. 0.7: solves the network level or the sheet "
                  "thickness over a sampled unit cell (any type)");
  sub->add_option("--level", args.level,
                  "Network level in mm: 0 is the minimal surface, positive thins the struts "
                  "(default 0); with a c, the seeds' raw C on f (solid where f + C < 0), e.g. "
                  "--level 0.3c");
  sub->add_option("--thickness", args.thickness,
                  "Sheet wall thickness in mm (default 0.3); with a c, raw on f (|f| < T/2), e.g. "
                  "--thickness 0.6c");
  sub->add_option("--rotate", args.rotate,
                  "Rotate the lattice by RX RY RZ degrees (about x, then y, then z)")
      ->expected(3);
  sub->add_option("--origin", args.origin, "Shift the lattice's phase origin to X Y Z (mm)")
      ->expected(3);
}

void apply_tpms_flags(const TpmsArgs& args, TpmsOptions& tpms) {
  if (args.lattice) tpms.type = tpms_type_from_name(*args.lattice);
  if (!args.terms.empty()) {
    if (tpms.type != TpmsType::Fourier) throw InputError("--term needs --lattice fourier");
    tpms.terms.clear();
    for (std::size_t i = 0; i + 5 <= args.terms.size(); i += 5) {
      const double* t = &args.terms[i];
      for (int a = 1; a <= 3; ++a)
        if (t[a] != std::round(t[a]) || std::fabs(t[a]) > kMaxFourierWave)
          throw InputError("--term " + std::to_string(i / 5 + 1) +
                           ": H K L are whole periods per cell (at most " +
                           std::to_string(kMaxFourierWave) + "), not " + std::to_string(t[a]));
      tpms.terms.push_back(
          {t[0], {static_cast<int>(t[1]), static_cast<int>(t[2]), static_cast<int>(t[3])}, t[4]});
    }
  } else if (args.lattice && tpms.type != TpmsType::Fourier) {
    tpms.terms.clear();
  } else if (tpms.type == TpmsType::Fourier && tpms.terms.empty()) {
    throw InputError("--lattice fourier needs its terms: --term A H K L P, once per term");
  }
  // One unit for the levels and thickness given: mm, or raw C where each ends in c.
  std::optional<LevelUnit> unit;
  auto level = [&](const std::string& flag, const std::string& text) {
    const Level l = parse_level(flag, text);
    if (unit && *unit != l.unit)
      throw InputError(flag + " " + text +
                       ": mixes mm and raw C; give every level and thickness in one unit");
    unit = l.unit;
    return l.value;
  };
  if (args.sheet || !args.levels.empty()) tpms.style = TpmsStyle::Sheet;
  if (!args.levels.empty()) {  // walls between two levels: a sheet off the minimal surface
    if (args.level || args.thickness || args.porosity)
      throw InputError(
          "--levels sets the sheet's walls; it takes no --level, --thickness or "
          "--porosity");
    const double c1 = level("--levels", args.levels[0]), c2 = level("--levels", args.levels[1]);
    if (!(c2 > c1))
      throw InputError("--levels C1 C2 needs C1 < C2, not " + args.levels[0] + " and " +
                       args.levels[1]);
    tpms.thickness = c2 - c1;
    tpms.level = -0.5 * (c1 + c2);
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
  if (args.level) tpms.level = level("--level", *args.level), tpms.porosity.reset();
  if (args.thickness) tpms.thickness = level("--thickness", *args.thickness), tpms.porosity.reset();
  if (args.porosity) tpms.porosity = *args.porosity, tpms.unit = LevelUnit::Millimetre;
  if (unit) tpms.unit = *unit;
  if (!args.rotate.empty()) tpms.rotation = rotation_from_euler(three(args.rotate));
  if (!args.origin.empty()) tpms.origin = three(args.origin);
}

}  // namespace tpmsfill::cli
