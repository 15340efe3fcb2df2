// `tpmsfill fill IN OUT`: read a mesh, fill it with a TPMS lattice (tpmsfill::fill), write the
// validated lattice and, when asked, the report. This file only parses, times I/O and prints.
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <functional>
#include <limits>
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <tpmsfill/decimate.hpp>
#include <tpmsfill/error.hpp>
#include <tpmsfill/fill.hpp>
#include <tpmsfill/io.hpp>
#include <tpmsfill/io/volume.hpp>
#include <tpmsfill/recipe.hpp>
#include <tpmsfill/render.hpp>
#include <tpmsfill/scan/itdf.hpp>
#include <vector>

#include "cli/commands.hpp"
#include "cli/job_files.hpp"
#include "cli/job_flags.hpp"
#include "cli/memory_policy.hpp"
#include "cli/picture_flags.hpp"
#include "cli/preflight.hpp"
#include "cli/ranks.hpp"
#include "cli/split_jobs.hpp"
#include "cli/terminal_progress.hpp"
#include "cli/thread_flags.hpp"
#include "cli/validators.hpp"

namespace tpmsfill::cli {
namespace {

struct FillArgs {
  std::string input, output, report, preview, field_out;
  JobArgs job;
  bool measure = false, full_field = false, keep_islands = false, no_self_intersections = false;
  std::optional<std::string> validate;
  bool quiet = false, yes = false;
  int threads = 0;
  double min_wall = 0, min_pore = 0;
  double decimate = 0;  ///< --decimate TOL, mm (0: off)
};

// Bytes a mesh of `triangles` takes in `format`, about two points a triangle for the indexed
// formats: binary STL exactly, the text formats and PLY within about 20 %, 3MF roughly.
double mesh_file_bytes(MeshFormat format, double triangles) {
  switch (format) {
    case MeshFormat::Auto:
    case MeshFormat::StlBinary:
      return 84 + 50 * triangles;
    case MeshFormat::StlAscii:
      return 230 * triangles;
    case MeshFormat::Obj:
      return 52 * triangles;
    case MeshFormat::Off:
      return 50 * triangles;
    case MeshFormat::Ply:
      return 25 * triangles;
    case MeshFormat::ThreeMf:
      return 20 * triangles;  // deflated XML
    case MeshFormat::Scene:   // never written
      break;
  }
  return 50 * triangles;
}

// fill's preflight (FillOptions::preflight): once the design has passed its review and the
// memory plan is made, before any work (cli/preflight.hpp).
std::function<void(const FillForecast&)> preflight(const FillArgs& args,
                                                   TerminalProgress* progress) {
  return [&args, progress](const FillForecast& f) {
    const MeshFormat format = format_from_extension(args.output);
    Preflight p{.samples = f.samples,
                .made = "about " + count_text(f.triangles) + " triangles",
                .made_json = {{"triangles", std::round(f.triangles)}},
                .bytes = mesh_file_bytes(format, f.triangles),
                .format = std::string(format_name(format)),
                .seconds_low = f.seconds_low,
                .seconds_high = f.seconds_high,
                .memory_bytes = f.memory_bytes,
                .smaller =
                    "a larger --voxel or --cell (the triangles fall with the square of "
                    "the voxel), or --decimate"};
    run_preflight(p, args.yes, progress);
  };
}

double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

// The lattice as written: the result's own, or read back where it was streamed to disk.
const TriangleSoup& written_mesh(const FillArgs& args, const FillResult& result,
                                 const std::filesystem::path& mesh_path, TriangleSoup& read_back) {
  if (!result.mesh.triangles.empty()) return result.mesh;
  if (read_back.triangles.empty()) {
    ReadOptions read;
    read.format = format_from_extension(args.output);
    read.max_bytes = std::numeric_limits<std::uint64_t>::max();  // it is our own output
    read_back = read_mesh_file(mesh_path, read).soup;
  }
  return read_back;
}

// --preview: the lattice cut open at the middle of its box (the half nearer the camera taken
// away), seen from the default three-quarter view.
void write_preview(const TriangleSoup& mesh, const std::filesystem::path& to) {
  RenderOptions options;
  options.clip.axis = 1;
  options.clip.position = bounding_box(mesh).centre().y;
  write_file_atomically(to, encode_png(render_mesh(mesh, options)));
}

// --decimate: fill() writes its validated lattice to a scratch file beside OUT (never
// committed, so removed however the job ends), which is read back, decimated (and validated
// again inside decimate()) and written to OUT's staged name. Going through a file keeps fill's
// own paths unchanged: a job that streams by slabs never holds its mesh, and the MPI ranks
// hand rank 0 a file either way; only the decimation needs the whole mesh in memory.
struct Decimation {
  DecimateReport report;
  StageTime stage;
};

Decimation decimate_file(const std::filesystem::path& raw, const std::filesystem::path& out,
                         const std::string& target_name, const WriteOptions& write,
                         const FillOptions& fill_options, double tolerance) {
  const auto t0 = std::chrono::steady_clock::now();
  DecimateOptions options;
  options.tolerance = tolerance;
  // OUT's rounding (the scratch holds fill's, float by default, as doubles).
  options.rounding = rounding_for(format_from_extension(target_name));
  if (options.rounding == CoordinateRounding::None) options.rounding = fill_options.rounding;
  options.self_intersections = fill_options.check_self_intersections;
  options.progress = fill_options.progress;
  ReadOptions read;
  read.format = MeshFormat::Ply;
  read.max_bytes = std::numeric_limits<std::uint64_t>::max();  // our own scratch
  DecimateResult result = decimate(read_mesh(raw, read), options);
  write_mesh(out, result.mesh, write);
  return {std::move(result.report), {"decimate", seconds_since(t0), peak_memory_mb()}};
}

int run_fill(FillArgs args) {
  const auto threads = thread_limit(args.threads);

  FillOptions options = job_options(args.job);
  if (args.full_field) options.full_field = true;
  if (args.keep_islands) options.keep_islands = true;
  if (args.measure) options.measure = true;
  if (args.min_wall > 0) options.min_wall = args.min_wall;
  if (args.min_pore > 0) options.min_pore = args.min_pore;
  // Printability is checked against the measures (from the flags or a recipe's keys).
  if (options.min_wall > 0 || options.min_pore > 0) options.measure = true;
  if (args.no_self_intersections) options.check_self_intersections = false;
  if (args.validate) options.validation = validation_from_name(*args.validate);
  // Fail on a bad output name, or one that would replace an input, before the work.
  if (format_from_extension(args.output) == MeshFormat::Auto)
    throw InputError(unknown_mesh_extension(args.output));
  // Validate what OUT will hold: floats for STL, lib3mf's micrometres for 3MF, doubles for the
  // others (so a part far from the origin can be filled finely into PLY, OBJ or OFF).
  options.rounding = rounding_for(format_from_extension(args.output));
  std::vector<OutputFile> outputs{{"OUT", args.output}};
  if (!args.report.empty()) outputs.push_back({"--report", args.report});
  if (!args.preview.empty()) {
    require_png_name("--preview", args.preview);
    outputs.push_back({"--preview", args.preview});
  }
  if (!args.field_out.empty()) {
    if (volume_format_from_extension(args.field_out) != VolumeFormat::Vdb)
      throw InputError("--field-out " + args.field_out +
                       ": the field is written as an OpenVDB level set, named .vdb");
    if (!vdb_available())
      throw InputError(
          "--field-out: this build of tpmsfill has no OpenVDB (install "
          "libopenvdb-dev and build again)");
    outputs.push_back({"--field-out", args.field_out});
  }
  std::vector<std::filesystem::path> inputs{args.input};
  for (const std::string& f : {args.job.field, args.job.recipe})
    if (!f.empty()) inputs.emplace_back(f);
  require_writable_outputs(inputs, outputs);

  std::unique_ptr<TerminalProgress> progress;
  if (rank() == 0 && progress_wanted(args.quiet)) progress = std::make_unique<TerminalProgress>();
  options.progress = progress.get();

  auto t0 = std::chrono::steady_clock::now();
  MeshFile file = read_mesh_file(args.input);
  const StageTime read{"read", seconds_since(t0), peak_memory_mb()};
  release_freed_memory();
  print_warnings(file.warnings);
  options.preflight = preflight(args, progress.get());

  // The mesh and the report are one outcome: both are written, or neither. The mesh is
  // written as it is made (streamed when the job goes in slabs), to a staged name.
  StagedOutputs staged, scratch;
  const std::filesystem::path mesh_path = staged.stage(args.output);
  const std::filesystem::path fill_path =
      args.decimate > 0 ? scratch.stage(args.output + ".undecimated") : mesh_path;
  // Under mpirun each rank fills its share of the grid; rank 0 finishes and writes.
  // A 3MF carries the recipe as given (it reproduces the job) beside the report fill adds.
  WriteOptions write = write_options_for(args.output);
  write.metadata.attachments.emplace_back("Metadata/tpmsfill-recipe.json", recipe_json(options));
  // The scratch a decimation reads back is binary PLY whatever OUT is: doubles, read back
  // exactly, without OUT's text, deflating or lib3mf on the way (OUT's rounding is applied by
  // decimate() to its input).
  const WriteOptions scratch_write{
      .format = MeshFormat::Ply, .compression = Compression::None, .metadata = {}};
  std::optional<FillResult> on_ranks =
      fill_on_ranks(file.soup, options, fill_path, args.decimate > 0 ? scratch_write : write);
  if (!on_ranks) return kOk;
  FillResult& result = *on_ranks;
  std::optional<Decimation> decimation;
  if (args.decimate > 0)
    decimation = decimate_file(fill_path, mesh_path, args.output, write, options, args.decimate);
  if (progress) progress->clear();

  FillReport& report = result.report;
  report.recipe = recipe_json(result.resolved);
  record_provenance(report, args.input);
  report.stages.insert(report.stages.begin(), read);
  std::string json = to_json(report);
  if (decimation) {
    // The report's own figures are the lattice's as filled; "decimation" is OUT's.
    report.stages.push_back(decimation->stage);
    for (const std::string& w : decimation->report.warnings) report.warnings.push_back(w);
    nlohmann::ordered_json j = nlohmann::ordered_json::parse(to_json(report));
    j["decimation"] = nlohmann::ordered_json::parse(to_json(decimation->report));
    json = j.dump(2) + "\n";
  }
  if (!args.report.empty()) write_file_atomically(staged.stage(args.report), json);
  TriangleSoup read_back;
  if (!args.preview.empty())
    write_preview(written_mesh(args, result, mesh_path, read_back), staged.stage(args.preview));
  if (!args.field_out.empty())
    write_level_set(staged.stage(args.field_out), written_mesh(args, result, mesh_path, read_back),
                    {.voxel = result.resolved.grid.voxel_size, .half_width = 3});
  staged.commit();

  if (!args.quiet) {
    std::printf("%s -> %s\n%s", args.input.c_str(), args.output.c_str(), to_text(report).c_str());
    if (decimation) std::printf("decimated\n%s", to_text(decimation->report).c_str());
    if (!args.report.empty()) std::printf("report       %s\n", args.report.c_str());
    if (!args.preview.empty()) std::printf("preview      %s\n", args.preview.c_str());
    if (!args.field_out.empty()) std::printf("field        %s\n", args.field_out.c_str());
  }
  print_warnings(report.warnings);
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
      "  tpmsfill fill femur.stl bone.stl --grade porosity 0.5 0.8 --grade-by femur.tsm   "
      "(material fit)\n"
      "  tpmsfill fill part.stl hybrid.stl --recipe hybrid.json   (docs/recipes.md)\n"
      "  tpmsfill fill bracket-in-metres.stl lattice.stl --units m --cell 4\n"
      "  tpmsfill fill femur.stl scaffold.stl --cell 2 --preview scaffold.png\n"
      "  tpmsfill fill femur.stl light.stl --cell 2 --voxel 0.05 --decimate 0.0125\n\n"
      "Exit code 0: written; 1: the lattice failed validation (nothing written); 2: unreadable "
      "input, bad arguments or over the memory budget.");
  sub->add_option(
         "IN", args->input,
         "Mesh: STL, OBJ, PLY, OFF (gzip allowed), 3MF or a scene (glTF, FBX, COLLADA, ...), "
         "mm; holes, flipped faces and "
         "overlapping shells are fine")
      ->required();
  sub->add_option("OUT", args->output,
                  "Output mesh; the extension picks the format (.stl, .obj, .ply, .off, .3mf; "
                  "the first four also as .gz)")
      ->required();
  add_job_options(sub, args->job);
  sub->add_flag("--full-field", args->full_field,
                "Compute the model distance at every node, not just the band (the paper's "
                "reference; slow)");
  sub->add_flag("--keep-islands", args->keep_islands,
                "Keep lattice pieces that float free of the main body (removed by default)");
  sub->add_flag("--measure", args->measure,
                "Measure pore size, wall thickness and void labyrinths into the report (costs "
                "about as much as the fill itself on small jobs)");
  sub->add_option("--min-wall", args->min_wall,
                  "Thinnest wall or strut your process prints, mm: thinner measured walls are "
                  "warned about, with where (turns --measure on)")
      ->check(positive());
  sub->add_option("--min-pore", args->min_pore,
                  "Narrowest pore your process clears (powder, resin), mm: narrower measured "
                  "pores are warned about, with where (turns --measure on)")
      ->check(positive());
  sub->add_option("--decimate", args->decimate,
                  "Decimate the lattice within this tolerance, mm, before writing it (as "
                  "`tpmsfill decimate`; voxel/4 is a good start): fewer triangles, still valid")
      ->check(positive());
  sub->add_flag("--no-self-intersections", args->no_self_intersections,
                "Skip the self-intersection search when validating");
  sub->add_option(
      "--validate", args->validate,
      "How the lattice is proved valid: proof (default: from marching cubes' own "
      "structure, each of its assumptions checked, nothing searched; jobs split "
      "among processes are searched) or full (search the whole mesh as if it came from anywhere: "
      "slower, the same verdict). The report's validated_by says which ran");
  sub->add_option("--report", args->report, "Write the JSON report here (fields: docs/cli.md)");
  sub->add_option("--preview", args->preview,
                  "Also write a picture of the lattice here (PNG, 640 pixels): cut open at the "
                  "middle of its box, seen from the three-quarter view of `tpmsfill render`");
  sub->add_option("--field-out", args->field_out,
                  "Also write the lattice as an OpenVDB narrow-band level set here (.vdb): the "
                  "exact distance to the surface written (negative inside) within 3 voxels of "
                  "it, at the fill's voxel; for Houdini, Blender and OpenVDB's tools");
  add_threads_option(sub, args->threads);
  add_yes_flag(sub, args->yes);
  sub->add_flag("--quiet", args->quiet, "Print nothing but errors and warnings");
  return [args] { return run_fill(*args); };
}

}  // namespace tpmsfill::cli
