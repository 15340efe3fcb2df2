#include "cli/job_flags.hpp"

#include <cmath>
#include <filesystem>
#include <memory>
#include <tpmsfill/error.hpp>
#include <tpmsfill/recipe.hpp>
#include <tpmsfill/scan/itdf.hpp>
#include <tpmsfill/solid/material_volume.hpp>
#include <utility>

#include "cli/ramp_along.hpp"
#include "cli/units_flag.hpp"
#include "cli/validators.hpp"

namespace tpmsfill::cli {

// "8G", "512M", "1.5GB", "1000000" → bytes.
std::uint64_t parse_bytes(const std::string& text, const std::string& flag) {
  std::size_t used = 0;
  double value = 0;
  try {
    value = std::stod(text, &used);
  } catch (const std::exception&) {
    throw InputError(flag + ": '" + text + "' is not a size such as 8G or 512M");
  }
  std::string unit = text.substr(used);
  if (!unit.empty() && (unit.back() == 'B' || unit.back() == 'b')) unit.pop_back();
  const double scale = unit.empty()                 ? 1.0
                       : unit == "K" || unit == "k" ? 1024.0
                       : unit == "M" || unit == "m" ? 1024.0 * 1024
                       : unit == "G" || unit == "g" ? 1024.0 * 1024 * 1024
                       : unit == "T" || unit == "t" ? 1024.0 * 1024 * 1024 * 1024
                                                    : -1.0;
  if (scale < 0 || !(value > 0) || !std::isfinite(value))
    throw InputError(flag + ": '" + text + "' is not a size such as 8G or 512M");
  return static_cast<std::uint64_t>(value * scale);
}

namespace {

// --field: seed 003's structure replaces the TPMS; --cell tiles it with that cell.
void apply_field(JobArgs& args, FillOptions& options) {
  const TpmsArgs& t = args.tpms;
  for (const auto& [given, flag] : {std::pair{t.lattice.has_value(), "--lattice"},
                                    {t.sheet, "--sheet"},
                                    {!t.levels.empty(), "--levels"},
                                    {t.level.has_value(), "--level"},
                                    {t.thickness.has_value(), "--thickness"},
                                    {!args.grade.empty(), "--grade"},
                                    {!t.rotate.empty(), "--rotate"},
                                    {!t.origin.empty(), "--origin"}})
    if (given)
      throw InputError(std::string(flag) + " describes a TPMS; --field " + args.field +
                       " replaces it (its thresholds: tpmsfill field mesh --solid/--surface)");
  LatticeDesign& d = options.design;
  d.structure = read_structure(args.field).structure;
  d.structure_file = args.field;
  if (std::vector<double>& cell = args.tpms.cell; !cell.empty()) {
    d.structure->size = cell.size() == 1 ? std::array<double, 3>{cell[0], cell[0], cell[0]}
                                         : std::array<double, 3>{cell[0], cell[1], cell[2]};
    d.structure->placement = Placement::Tile;
    cell.clear();
  }
}

}  // namespace

FillOptions job_options(JobArgs& args) {
  FillOptions options = args.recipe.empty() ? FillOptions{} : read_recipe_file(args.recipe);
  TpmsOptions& tpms = options.design;
  if (!args.field.empty()) apply_field(args, options);
  if (args.units) options.units.units = units_from_name(*args.units);
  if (args.scale) options.units.scale = *args.scale;
  if (args.voxel) options.grid.voxel_size = *args.voxel;
  apply_tpms_flags(args.tpms, tpms);
  if (args.grade.size() % 3 != 0)
    throw InputError("--grade takes three values each time: WHAT FROM TO");
  if (!args.grade.empty()) {
    Ramp ramp;
    if (!args.grade_by.empty()) {
      if (args.grade_along != "z")
        throw InputError("--grade-by " + args.grade_by + " and --grade-along " + args.grade_along +
                         " both say where the grade goes: give one");
      ramp = {.shape = RampShape::Volume,
              .volume = std::make_shared<const ScalarVolume>(read_grading_volume(args.grade_by)),
              // Absolute, so that the report's recipe finds it from any folder.
              .volume_file = std::filesystem::absolute(args.grade_by).string()};
    } else {
      ramp = ramp_along(args.grade_along);
    }
    if (!args.grade_range.empty()) ramp.from = args.grade_range[0], ramp.to = args.grade_range[1];
    for (std::size_t g = 0; g + 2 < args.grade.size(); g += 3) {
      const Graded what = graded_from_name(args.grade[g]);
      Ramp r = ramp;
      try {
        r.start = std::stod(args.grade[g + 1]);
        r.end = std::stod(args.grade[g + 2]);
      } catch (const std::exception&) {
        throw InputError("--grade " + args.grade[g] + ": '" + args.grade[g + 1] + " " +
                         args.grade[g + 2] + "' are not two numbers");
      }
      std::erase_if(options.design.grading, [&](const Grading& e) { return e.what == what; });
      options.design.grading.push_back({what, r});
    }
  } else if (!args.grade_range.empty() || args.grade_along != "z" || !args.grade_by.empty()) {
    throw InputError("--grade-along, --grade-by and --grade-range describe a --grade: give one");
  }
  if (args.skin) options.skin = *args.skin;
  if (args.skin_windows) options.skin_windows = true;
  if (options.skin_windows && !(options.skin > 0))
    throw InputError("--skin-windows opens a skin: give --skin too");
  if (args.band) options.band.width = *args.band;
  if (args.inside) options.inside = inside_from_name(*args.inside);
  if (!args.memory.empty()) options.memory_budget = parse_bytes(args.memory);
  require_valid(options.design);
  return options;
}

void add_job_options(CLI::App* sub, JobArgs& args) {
  sub->add_option("--recipe", args.recipe,
                  "JSON recipe with every setting below and more (blends of several lattices, "
                  "explicit ramps; docs/recipes.md); flags given as well override it")
      ->check(existing_file());
  sub->add_option("--field", args.field,
                  "A porous structure (ITDF, from `tpmsfill field fit`, or a signed field such as "
                  "an OpenVDB level set, fitted on reading) in place of the TPMS: "
                  "stretched over the model's box, or tiled with --cell as its cell; --porosity "
                  "shifts its thresholds")
      ->check(existing_file());
  add_tpms_options(sub, args.tpms);
  sub->add_option("--grade", args.grade,
                  "Vary porosity, level, thickness or cell between two values, e.g. --grade "
                  "porosity 0.8 0.5 (repeatable; where: --grade-along)")
      ->expected(3)
      ->multi_option_policy(CLI::MultiOptionPolicy::TakeAll);
  sub->add_option("--grade-along", args.grade_along,
                  "x, y, z (across the model), radial (from its centre), radial-x/-y/-z (from an "
                  "axis through its centre) or depth (below its surface, denser near the skin "
                  "with --grade porosity 0.5 0.8); default z");
  sub->add_option("--grade-by", args.grade_by,
                  "Grade by the values of FILE at each point instead: a fitted model's material "
                  "(.tsm, from `tpmsfill material fit`) or a volume in mm (NRRD, MetaImage, INR: "
                  "a CT); --grade-range A B are then values (default: their range over the "
                  "model)")
      ->check(existing_file());
  sub->add_option("--grade-range", args.grade_range,
                  "Ramp positions A B in mm where the first and second values apply (default: "
                  "the model's extent; depth: 0 to a quarter of its smallest side)")
      ->expected(2);
  sub->add_option("--skin", args.skin,
                  "Unite a solid shell this thick (mm) inside the model's surface, so no strut "
                  "dangles at the boundary (closed: it seals the void in)");
  sub->add_flag("--skin-windows", args.skin_windows,
                "Open the skin at every pore that meets it, so powder or resin can drain");
  sub->add_option("--voxel", args.voxel, "Grid spacing in mm (default 0.1)");
  sub->add_option("--inside", args.inside,
                  "What counts as inside: winding (the generalized winding number >= 1/2 of the "
                  "cleaned mesh, holes closed the way a person would close them), parity (odd "
                  "ray crossings, the method paper's rule, for closed meshes only) or auto "
                  "(default: the winding number, cleaning the mesh only if some grid row finds "
                  "it open or inside out)");
  add_units_flag(sub, args.units);
  sub->add_option("--scale", args.scale,
                  "Multiply the input's coordinates (after --units) by this, e.g. 2 to fill the "
                  "part at twice its size (default 1)")
      ->check(positive());
  sub->add_option("--band", args.band,
                  "Half-width of the exact-distance band in voxels (default 1, the paper's)")
      ->check(between(1, 64, "1 to 64"));
  sub->add_option("--memory", args.memory,
                  "Memory to fit in, e.g. 8G or 512M (default: half of physical memory). fill "
                  "goes slab by slab when the whole grid does not fit (or needs over 512 MiB, "
                  "where slabs are faster), and then streams OUT "
                  "(validated and written a few layers at a time, through a temporary file of "
                  "about 30 bytes a triangle beside it): the same output; what fits in no way "
                  "is refused, saying what would");
}

}  // namespace tpmsfill::cli
