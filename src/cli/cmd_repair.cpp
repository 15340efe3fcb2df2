// `tpmsfill repair IN OUT`: make a mesh a closed, outward 2-manifold without
// self-intersections (tpmsfill::repair_mesh) and write it only if it is one. This file only
// parses, times and prints.
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <tpmsfill/error.hpp>
#include <tpmsfill/io.hpp>
#include <tpmsfill/repair.hpp>
#include <tpmsfill/units.hpp>

#include "cli/commands.hpp"
#include "cli/job_files.hpp"
#include "cli/terminal_progress.hpp"
#include "cli/thread_flags.hpp"
#include "cli/units_flag.hpp"
#include "cli/validators.hpp"

namespace tpmsfill::cli {
namespace {

struct RepairArgs {
  std::string input, output;
  bool json = false, no_wrap = false, no_volume = false, no_fill_holes = false, quiet = false;
  bool accept_deviation = false;
  double alpha = 0, offset = 0, tolerance = 0, voxel = 0;
  double min_component = RepairOptions{}.min_component_fraction;
  std::string units = "mm";
  int threads = 0;
};

int run_repair(const RepairArgs& args) {
  const auto threads = thread_limit(args.threads);
  // Fail on a bad output name before the work, not after it.
  const MeshFormat format = format_from_extension(args.output);
  if (format == MeshFormat::Auto) throw InputError(unknown_mesh_extension(args.output));
  require_writable_outputs({args.input}, {{"OUT", args.output}});
  const ModelUnits units{.units = units_from_name(args.units)};

  RepairOptions options;
  options.wrap = !args.no_wrap;
  options.volume = !args.no_volume;
  options.voxel = args.voxel;
  options.fill_holes = !args.no_fill_holes;
  options.alpha = args.alpha;
  options.offset = args.offset;
  options.min_component_fraction = args.min_component;
  options.tolerance = args.tolerance;
  // STL stores floats: check what will be written.
  options.rounding = rounding_for(format);
  std::unique_ptr<TerminalProgress> progress;
  if (progress_wanted(args.quiet)) progress = std::make_unique<TerminalProgress>();
  options.progress = progress.get();

  const auto t0 = std::chrono::steady_clock::now();
  MeshFile file = read_mesh_file(args.input);
  file.soup = to_millimetres(std::move(file.soup), units);
  print_warnings(file.warnings);
  const RepairResult result = repair_mesh(file.soup, options);
  if (progress) progress->clear();
  const RepairReport& report = result.report;
  // A valid result past the tolerance is not the part that came in: written only if accepted.
  const bool valid = report.valid() && (report.within_tolerance || args.accept_deviation);
  if (valid) write_mesh(args.output, result.mesh);
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();

  if (args.json) {
    nlohmann::ordered_json j;
    j["input"] = args.input;
    j["output"] = args.output;
    j["written"] = valid;
    j["units"] = args.units;
    j["seconds"] = seconds;
    const auto fields = nlohmann::ordered_json::parse(to_json(report));
    for (const auto& [key, value] : fields.items()) j[key] = value;
    std::printf("%s\n", j.dump(2).c_str());
  } else if (!args.quiet) {
    std::printf("%s -> %s\n%s", args.input.c_str(), args.output.c_str(),
                to_text(result.report).c_str());
    std::printf("time     %.2f s\n", seconds);
  }
  std::fflush(stdout);  // the report first, then what it warns about
  print_warnings(report.warnings);
  if (report.valid() && !valid) {
    std::fflush(stdout);
    const RepairDeviation& d = report.deviation;
    const std::string what =
        report.route == "repair" ? "mesh" : "mesh (route: " + report.route + ")";
    std::fprintf(stderr,
                 "tpmsfill: error: the repaired %s lies up to %.3g mm from the input (95 %% within "
                 "%.3g mm, volume %+.1f %%), beyond the tolerance of %.3g mm; nothing was written "
                 "(--accept-deviation writes it anyway, --tolerance sets the limit)\n",
                 what.c_str(), d.worst(), std::max(d.to_input.p95, d.from_input.p95),
                 100 * d.volume_change, report.tolerance);
    return kNotValid;
  }
  if (!report.valid()) {
    std::fflush(stdout);
    std::fprintf(stderr,
                 "tpmsfill: error: %s could not be made a valid closed 2-manifold%s; nothing "
                 "was written\n",
                 args.input.c_str(),
                 args.no_wrap || args.no_volume
                     ? " with the routes allowed (try again without --no-wrap or --no-volume)"
                     : "");
    return kNotValid;
  }
  return kOk;
}

}  // namespace

Command add_repair_command(CLI::App& app) {
  auto args = std::make_shared<RepairArgs>();
  CLI::App* sub = app.add_subcommand(
      "repair", "Make a mesh a closed, outward 2-manifold without self-intersections");
  sub->footer(
      "Merges duplicate points, drops degenerate and duplicate triangles, orients the faces, "
      "stitches borders, splits non-manifold edges and vertices, removes small components, "
      "fills holes, resolves self-intersections and orients every shell outward (CGAL Polygon "
      "Mesh Processing, exact predicates). If the result is still not valid, or lies beyond "
      "--tolerance from the input, other routes run, cheapest first, until one is within: the "
      "alpha wrap (CGAL 3D Alpha Wrapping; always valid, but it lies --offset outside the input "
      "and does not enter cavities narrower than about --alpha), the volumetric route (the "
      "solid the winding number encloses, remade by marching cubes at --voxel and decimated "
      "within the tolerance left), then wraps with a half and a quarter of the alpha. The "
      "valid result nearest the input is kept; the report names its route and every route "
      "tried. OUT is written only when `tpmsfill check` would accept it and it lies within "
      "--tolerance. Lengths are millimetres.\n\n"
      "Example: tpmsfill repair scan.stl scan-fixed.stl\n\n"
      "Exit code 0: repaired and written; 1: could not be made valid (nothing written); 2: "
      "unreadable input or bad arguments.");
  sub->add_option("IN", args->input,
                  "Mesh to repair: STL, OBJ, PLY, OFF (gzip allowed), 3MF or a scene (glTF, FBX, "
                  "COLLADA, ...), mm")
      ->required();
  sub->add_option("OUT", args->output,
                  "Output mesh; the extension picks the format (.stl, .obj, .ply, .off, .3mf)")
      ->required();
  add_units_flag(sub, args->units);
  sub->add_flag("--json", args->json,
                "Print the JSON report instead of text (fields: docs/cli.md)");
  sub->add_flag("--no-wrap", args->no_wrap,
                "Never fall back to alpha wrapping; fail (exit 1) instead");
  sub->add_flag("--no-volume", args->no_volume,
                "Never remake the surface from the volume it encloses (the volumetric route)");
  sub->add_option("--alpha", args->alpha,
                  "Alpha of the wrap in mm, the only one tried (default: bounding-box diagonal "
                  "/ 100, then / 200 and / 400 if nothing else is within the tolerance)")
      ->check(positive());
  sub->add_option("--voxel", args->voxel,
                  "Voxel of the volumetric route in mm (default: half the tolerance)")
      ->check(positive());
  sub->add_option("--offset", args->offset, "Offset of the wrap in mm (default: alpha / 30)")
      ->check(positive());
  sub->add_option("--tolerance", args->tolerance,
                  "Largest deviation from the input a repair may have, mm (default 1 % of the "
                  "bounding-box diagonal); past it the other routes are tried and the nearest "
                  "result is kept")
      ->check(positive());
  sub->add_flag("--accept-deviation", args->accept_deviation,
                "Write the result even when it deviates from the input beyond --tolerance");
  sub->add_flag("--no-fill-holes", args->no_fill_holes,
                "Do not fill holes (an open mesh then needs the wrap; no volumetric route)");
  sub->add_option("--min-component", args->min_component,
                  "Remove components whose area is below this fraction of the largest one's "
                  "(default 0.001; 0 keeps all)")
      ->check(between(0, 0.999999, "at least 0 and below 1"));
  add_threads_option(sub, args->threads);
  sub->add_flag("--quiet", args->quiet, "Print nothing but errors and warnings");
  return [args] { return run_repair(*args); };
}

}  // namespace tpmsfill::cli
