// `tpmsfill fill IN OUT`: read a mesh, fill it with a TPMS lattice (tpmsfill::fill), write the
// validated lattice and, when asked, the report. This file only parses, times I/O and prints.
#include <tbb/global_control.h>
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <tpmsfill/error.hpp>
#include <tpmsfill/fill.hpp>
#include <tpmsfill/io.hpp>
#include <tpmsfill/itdf.hpp>
#include <tpmsfill/recipe.hpp>
#include <vector>

#include "cli/commands.hpp"
#include "cli/design_flags.hpp"
#include "cli/job_files.hpp"
#include "cli/ramp_along.hpp"
#include "cli/terminal_progress.hpp"
#include "cli/validators.hpp"

namespace tpmsfill::cli {
namespace {

struct FillArgs {
  std::string input, output, report, recipe, field;
  std::optional<std::string> inside;
  TpmsArgs tpms;
  std::vector<double> grade_range;
  std::optional<double> voxel, skin;
  std::vector<std::string> grade;
  std::string grade_along = "z";
  std::optional<std::string> units;
  std::optional<double> scale;
  std::optional<int> band;
  bool skin_windows = false, measure = false;
  bool full_field = false, keep_islands = false, no_self_intersections = false, quiet = false;
  std::string memory;
  int threads = 0;
};

// "8G", "512M", "1.5GB", "1000000" → bytes.
std::uint64_t parse_bytes(const std::string& text) {
  std::size_t used = 0;
  double value = 0;
  try {
    value = std::stod(text, &used);
  } catch (const std::exception&) {
    throw InputError("--memory: '" + text + "' is not a size such as 8G or 512M");
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
    throw InputError("--memory: '" + text + "' is not a size such as 8G or 512M");
  return static_cast<std::uint64_t>(value * scale);
}

// --field: seed 003's structure replaces the TPMS; --cell tiles it with that cell.
void apply_field(FillArgs& args, FillOptions& options) {
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
  d.structure = read_itdf(args.field).structure;
  d.structure_file = args.field;
  if (std::vector<double>& cell = args.tpms.cell; !cell.empty()) {
    d.structure->size = cell.size() == 1 ? std::array<double, 3>{cell[0], cell[0], cell[0]}
                                         : std::array<double, 3>{cell[0], cell[1], cell[2]};
    d.structure->placement = Placement::Tile;
    cell.clear();
  }
}

// Flags on top of the recipe (or the defaults): what is given on the command line wins.
void apply_flags(FillArgs& args, FillOptions& options) {
  TpmsOptions& tpms = options.design;
  if (!args.field.empty()) apply_field(args, options);
  if (args.units) options.units.units = units_from_name(*args.units);
  if (args.scale) options.units.scale = *args.scale;
  if (args.voxel) options.grid.voxel_size = *args.voxel;
  apply_tpms_flags(args.tpms, tpms);
  if (args.grade.size() % 3 != 0)
    throw InputError("--grade takes three values each time: WHAT FROM TO");
  if (!args.grade.empty()) {
    Ramp ramp = ramp_along(args.grade_along);
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
  } else if (!args.grade_range.empty() || args.grade_along != "z") {
    throw InputError("--grade-along and --grade-range describe a --grade: give one");
  }
  if (args.skin) options.skin = *args.skin;
  if (args.skin_windows) options.skin_windows = true;
  if (options.skin_windows && !(options.skin > 0))
    throw InputError("--skin-windows opens a skin: give --skin too");
  if (args.band) options.band.width = *args.band;
  if (args.inside) options.inside = inside_from_name(*args.inside);
  if (args.full_field) options.full_field = true;
  if (args.keep_islands) options.keep_islands = true;
  if (args.measure) options.measure = true;
  if (args.no_self_intersections) options.check_self_intersections = false;
  if (!args.memory.empty()) options.memory_budget = parse_bytes(args.memory);
  require_valid(options.design);
}

double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

int run_fill(FillArgs args) {
  std::optional<tbb::global_control> threads;
  if (args.threads > 0)
    threads.emplace(tbb::global_control::max_allowed_parallelism,
                    static_cast<std::size_t>(args.threads));

  FillOptions options = args.recipe.empty() ? FillOptions{} : read_recipe_file(args.recipe);
  apply_flags(args, options);
  // Fail on a bad output name, or one that would replace an input, before the work.
  if (format_from_extension(args.output) == MeshFormat::Auto)
    throw InputError(args.output + ": unknown extension (use .stl, .obj, .ply or .off)");
  std::vector<OutputFile> outputs{{"OUT", args.output}};
  if (!args.report.empty()) outputs.push_back({"--report", args.report});
  std::vector<std::filesystem::path> inputs{args.input};
  if (!args.field.empty()) inputs.emplace_back(args.field);
  if (!args.recipe.empty()) inputs.emplace_back(args.recipe);
  require_writable_outputs(inputs, outputs);

  std::unique_ptr<TerminalProgress> progress;
  if (!args.quiet && isatty(STDERR_FILENO)) progress = std::make_unique<TerminalProgress>();
  options.progress = progress.get();

  auto t0 = std::chrono::steady_clock::now();
  MeshFile file = read_mesh_file(args.input);
  const StageTime read{"read", seconds_since(t0), peak_memory_mb()};
  for (const std::string& w : file.warnings)
    std::fprintf(stderr, "tpmsfill: warning: %s\n", w.c_str());

  FillResult result = fill(file.soup, options);
  if (progress) progress->clear();

  // The mesh and the report are one outcome: both are written, or neither.
  t0 = std::chrono::steady_clock::now();
  StagedOutputs staged;
  write_mesh(staged.stage(args.output), result.mesh,
             {.format = format_from_extension(args.output)});
  FillReport& report = result.report;
  report.recipe = recipe_json(result.resolved);
  report.input_path = args.input;
  report.input_sha256 = sha256_of_file(args.input);
  report.command_line = command_line();
  report.version = TPMSFILL_VERSION;
  report.stages.insert(report.stages.begin(), read);
  report.stages.push_back({"write", seconds_since(t0), peak_memory_mb()});
  if (!args.report.empty()) write_file_atomically(staged.stage(args.report), to_json(report));
  staged.commit();

  if (!args.quiet) {
    std::printf("%s -> %s\n%s", args.input.c_str(), args.output.c_str(), to_text(report).c_str());
    if (!args.report.empty()) std::printf("report       %s\n", args.report.c_str());
  }
  for (const std::string& w : report.warnings)
    std::fprintf(stderr, "tpmsfill: warning: %s\n", w.c_str());
  return kOk;
}

}  // namespace

Command add_fill_command(CLI::App& app) {
  auto args = std::make_shared<FillArgs>();
  CLI::App* sub =
      app.add_subcommand("fill", "Fill a mesh with a TPMS lattice clipped to its surface");
  sub->footer(
      "The lattice is the zero level of max(model distance, TPMS field), meshed by marching "
      "cubes on a grid of --voxel mm, and validated before it is written: closed, 2-manifold, "
      "outward, no degenerate faces, no self-intersections. If validation fails nothing is "
      "written. Lengths are millimetres (--units converts IN; OUT is in mm). Network lattices "
      "are solid where f/|grad f| + level < 0; sheet lattices are walls of --thickness around "
      "the minimal surface.\n\n"
      "Before any work the design is reviewed against the model: what cannot come out as asked "
      "(a model smaller than a cell, a voxel over half a cell, a level that leaves no solid, a "
      "ramp or blend that misses the model, OUT or --report replacing IN) is refused with the "
      "value that fits; what may not (thin struts, few cells, islands that were features, "
      "sealed voids) is written with a warning (docs/cli.md lists them).\n\n"
      "Examples:\n"
      "  tpmsfill fill femur.stl scaffold.stl --lattice gyroid --cell 2 --voxel 0.1\n"
      "  tpmsfill fill part.obj shell.stl --lattice diamond --sheet --thickness 0.4 --report "
      "r.json\n"
      "  tpmsfill fill femur.stl implant.stl --porosity 0.7 --grade porosity 0.5 0.8 "
      "--grade-along depth --skin 0.4\n"
      "  tpmsfill fill part.stl graded.stl --lattice iwp --grade cell 2 4 --grade-along x\n"
      "  tpmsfill fill part.stl hybrid.stl --recipe hybrid.json   (docs/recipes.md)\n"
      "  tpmsfill fill bracket-in-metres.stl lattice.stl --units m --cell 4\n\n"
      "Exit code 0: written; 1: the lattice failed validation (nothing written); 2: unreadable "
      "input, bad arguments or over the memory budget.");
  sub->add_option("IN", args->input,
                  "Mesh: STL, OBJ, PLY or OFF (gzip allowed), mm; holes, flipped faces and "
                  "overlapping shells are fine")
      ->required();
  sub->add_option("OUT", args->output,
                  "Output mesh; the extension picks the format (.stl, .obj, .ply, .off)")
      ->required();
  sub->add_option("--recipe", args->recipe,
                  "JSON recipe with every setting below and more (blends of several lattices, "
                  "explicit ramps; docs/recipes.md); flags given as well override it")
      ->check(existing_file());
  sub->add_option("--field", args->field,
                  "A porous structure (ITDF, from `tpmsfill field fit`) in place of the TPMS: "
                  "stretched over the model's box, or tiled with --cell as its cell; --porosity "
                  "shifts its thresholds")
      ->check(existing_file());
  add_tpms_options(sub, args->tpms);
  sub->add_option("--grade", args->grade,
                  "Vary porosity, level, thickness or cell between two values, e.g. --grade "
                  "porosity 0.8 0.5 (repeatable; where: --grade-along)")
      ->expected(3)
      ->multi_option_policy(CLI::MultiOptionPolicy::TakeAll);
  sub->add_option("--grade-along", args->grade_along,
                  "x, y, z (across the model), radial (from its centre), radial-x/-y/-z (from an "
                  "axis through its centre) or depth (below its surface, denser near the skin "
                  "with --grade porosity 0.5 0.8); default z");
  sub->add_option("--grade-range", args->grade_range,
                  "Ramp positions A B in mm where the first and second values apply (default: "
                  "the model's extent; depth: 0 to a quarter of its smallest side)")
      ->expected(2);
  sub->add_option("--skin", args->skin,
                  "Unite a solid shell this thick (mm) inside the model's surface, so no strut "
                  "dangles at the boundary (closed: it seals the void in)");
  sub->add_flag("--skin-windows", args->skin_windows,
                "Open the skin at every pore that meets it, so powder or resin can drain");
  sub->add_option("--voxel", args->voxel, "Grid spacing in mm (default 0.1)");
  sub->add_option("--inside", args->inside,
                  "What counts as inside: winding (the generalized winding number >= 1/2 of the "
                  "cleaned mesh, holes closed the way a person would close them), parity (odd "
                  "ray crossings, the method paper's rule, for closed meshes only) or auto "
                  "(default: the winding number, cleaning the mesh only if some grid row finds "
                  "it open or inside out)");
  sub->add_option("--units", args->units,
                  "Unit the input was modelled in: mm, cm, m, in or um (default mm); it is "
                  "converted to millimetres, the unit of every other length and of OUT");
  sub->add_option("--scale", args->scale,
                  "Multiply the input's coordinates (after --units) by this, e.g. 2 to fill the "
                  "part at twice its size (default 1)")
      ->check(positive());
  sub->add_option("--band", args->band,
                  "Half-width of the exact-distance band in voxels (default 1, the paper's)")
      ->check(between(1, 64, "1 to 64"));
  sub->add_flag("--full-field", args->full_field,
                "Compute the model distance at every node, not just the band (the paper's "
                "reference; slow)");
  sub->add_flag("--keep-islands", args->keep_islands,
                "Keep lattice pieces that float free of the main body (removed by default)");
  sub->add_flag("--measure", args->measure,
                "Measure pore size, wall thickness and void labyrinths into the report (costs "
                "about as much as the fill itself on small jobs)");
  sub->add_flag("--no-self-intersections", args->no_self_intersections,
                "Skip the self-intersection search when validating");
  sub->add_option("--memory", args->memory,
                  "Memory budget, e.g. 8G or 512M (default: half of physical memory); larger "
                  "jobs are refused with the voxel size that fits");
  sub->add_option("--report", args->report, "Write the JSON report here (fields: docs/cli.md)");
  sub->add_option("--threads", args->threads, "Worker threads (default: all cores)")
      ->check(between(1, 1024, "1 to 1024"));
  sub->add_flag("--quiet", args->quiet, "Print nothing but errors and warnings");
  return [args] { return run_fill(*args); };
}

}  // namespace tpmsfill::cli
