// `tpmsfill decimate IN OUT --tolerance TOL`: fewer triangles within TOL of a valid mesh, still
// valid (tpmsfill::decimate). The input must already be valid (the check stage decides, and
// `tpmsfill repair` makes it so). This file only parses, checks the input, times and prints.
#include <unistd.h>

#include <chrono>
#include <cstdint>
#include <cstdio>
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <tpmsfill/check.hpp>
#include <tpmsfill/decimate.hpp>
#include <tpmsfill/error.hpp>
#include <tpmsfill/io.hpp>
#include <tpmsfill/units.hpp>

#include "cli/commands.hpp"
#include "cli/job_files.hpp"
#include "cli/terminal_progress.hpp"
#include "cli/thread_flags.hpp"
#include "cli/units_flag.hpp"
#include "cli/validators.hpp"

namespace tpmsfill::cli {
namespace {

struct DecimateArgs {
  std::string input, output, report;
  double tolerance = 0;
  std::uint64_t target = 0;
  bool json = false, quiet = false;
  std::string units = "mm";
  int threads = 0;
};

/// Refuses an input that is not what decimate() needs, with the check's own sentences.
void require_valid_input(const std::string& path, const TriangleSoup& soup) {
  const MeshCheck check = check_mesh(soup);
  if (check.valid()) return;
  std::string why;
  for (const std::string& p : check.problems()) why += (why.empty() ? "" : "; ") + p;
  throw InputError(path + " is not a valid closed 2-manifold (" + why +
                   "); decimation keeps validity, it does not create it: run `tpmsfill repair " +
                   path + " FIXED` first (`tpmsfill check` says where)");
}

int run_decimate(const DecimateArgs& args) {
  const auto threads = thread_limit(args.threads);
  // Fail on a bad output name, or one that would replace the input, before the work.
  const MeshFormat format = format_from_extension(args.output);
  if (format == MeshFormat::Auto) throw InputError(unknown_mesh_extension(args.output));
  std::vector<OutputFile> outputs{{"OUT", args.output}};
  if (!args.report.empty()) outputs.push_back({"--report", args.report});
  require_writable_outputs({args.input}, outputs);
  const ModelUnits units{.units = units_from_name(args.units)};

  std::unique_ptr<TerminalProgress> progress;
  if (progress_wanted(args.quiet)) progress = std::make_unique<TerminalProgress>();
  DecimateOptions options;
  options.tolerance = args.tolerance;
  options.target_triangles = args.target;
  // The file holds exactly the mesh that was validated (STL's floats, lib3mf's micrometres;
  // PLY is written as doubles, but rounded to float as before).
  options.rounding = format == MeshFormat::Ply ? CoordinateRounding::Float : rounding_for(format);
  options.progress = progress.get();

  const auto t0 = std::chrono::steady_clock::now();
  MeshFile file = read_mesh_file(args.input);
  file.soup = to_millimetres(std::move(file.soup), units);
  print_warnings(file.warnings);
  require_valid_input(args.input, file.soup);
  const DecimateResult result = decimate(file.soup, options);
  if (progress) progress->clear();
  const DecimateReport& report = result.report;

  // The mesh and the report are one outcome: both are written, or neither.
  StagedOutputs staged;
  write_mesh(staged.stage(args.output), result.mesh, write_options_for(args.output));
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  nlohmann::ordered_json j;
  j["input"] = args.input;
  j["output"] = args.output;
  j["units"] = args.units;
  j["wall_seconds"] = seconds;
  const auto fields = nlohmann::ordered_json::parse(to_json(report));  // outlives the loop
  for (const auto& [key, value] : fields.items()) j[key] = value;
  if (!args.report.empty()) write_file_atomically(staged.stage(args.report), j.dump(2) + "\n");
  staged.commit();

  if (args.json) {
    std::printf("%s\n", j.dump(2).c_str());
  } else if (!args.quiet) {
    std::printf("%s -> %s\n%s", args.input.c_str(), args.output.c_str(), to_text(report).c_str());
    std::printf("time         %.2f s\n", seconds);
    if (!args.report.empty()) std::printf("report       %s\n", args.report.c_str());
  }
  std::fflush(stdout);  // the report first, then what it warns about
  print_warnings(report.warnings);
  return kOk;
}

}  // namespace

Command add_decimate_command(CLI::App& app) {
  auto args = std::make_shared<DecimateArgs>();
  CLI::App* sub = app.add_subcommand(
      "decimate", "Fewer triangles within a tolerance of a valid mesh, still valid");
  sub->footer(
      "Collapses edges (CGAL surface mesh simplification, Lindstrom-Turk placement) while OUT "
      "and IN stay within --tolerance mm of each other both ways (a Hausdorff bound, proven at "
      "every collapse), no triangle turns over and no new triangle meets another. The result is "
      "validated like every output (closed, 2-manifold, outward, no degenerate faces, no "
      "self-intersections); should triangles intersect, those parts of IN are locked and the "
      "simplification runs again (up to 8 rounds); if none is valid, IN is written unchanged "
      "with a warning. IN must be valid already (`tpmsfill check`; `tpmsfill repair` makes it "
      "so). The report gives the triangles before and after, the measured distances both ways "
      "and the volume change. Lengths are millimetres.\n\n"
      "Examples:\n"
      "  tpmsfill decimate scaffold.stl scaffold-light.stl --tolerance 0.0125\n"
      "  tpmsfill decimate part.ply part-1m.ply --tolerance 0.05 --target 1000000 --report r.json\n"
      "  tpmsfill fill femur.stl scaffold.stl --cell 2 --voxel 0.05 --decimate 0.0125   (the same, "
      "in one job)\n\n"
      "Exit code 0: written (warnings say when the target was not reached or little was "
      "removed); 2: unreadable or invalid input, or bad arguments (nothing written).");
  sub->add_option("IN", args->input,
                  "Valid closed mesh: STL, OBJ, PLY or OFF (gzip allowed) or 3MF, mm")
      ->required();
  sub->add_option("OUT", args->output,
                  "Output mesh; the extension picks the format (.stl, .obj, .ply, .off, .3mf)")
      ->required();
  sub->add_option("--tolerance", args->tolerance,
                  "Largest distance from OUT to IN, mm (for a lattice: voxel/4 is a good start)")
      ->required()
      ->check(positive());
  sub->add_option("--target", args->target,
                  "Stop at this many triangles (default: as far as the tolerance allows)")
      ->check(between(1, 1e15, "at least 1"));
  add_units_flag(sub, args->units);
  sub->add_option("--report", args->report, "Write the JSON report here (fields: docs/cli.md)");
  sub->add_flag("--json", args->json,
                "Print the JSON report instead of text (fields: docs/cli.md)");
  add_threads_option(sub, args->threads);
  sub->add_flag("--quiet", args->quiet, "Print nothing but errors and warnings");
  return [args] { return run_decimate(*args); };
}

}  // namespace tpmsfill::cli
