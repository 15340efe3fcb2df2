// `tpmsfill slice IN OUT --layer L`: printer layers straight from fill's field
// (tpmsfill::slice), written as they come (tpmsfill::LayerFileWriter). This file only parses,
// stages the outputs and prints.
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <iterator>
#include <memory>
#include <optional>
#include <string>
#include <tpmsfill/error.hpp>
#include <tpmsfill/io.hpp>
#include <tpmsfill/layer_files.hpp>
#include <tpmsfill/recipe.hpp>
#include <tpmsfill/slice.hpp>
#include <tpmsfill/units.hpp>
#include <vector>

#include "cli/commands.hpp"
#include "cli/job_files.hpp"
#include "cli/job_flags.hpp"
#include "cli/memory_policy.hpp"
#include "cli/preflight.hpp"
#include "cli/ranks.hpp"
#include "cli/split_jobs.hpp"
#include "cli/terminal_progress.hpp"
#include "cli/thread_flags.hpp"
#include "cli/validators.hpp"

namespace tpmsfill::cli {
namespace {

namespace fs = std::filesystem;

struct SliceArgs {
  std::string input, output, report;
  JobArgs job;
  double layer = 0;
  std::optional<double> start, pixel;
  std::optional<std::string> format;
  bool binary = false, quiet = false, yes = false;
  int threads = 0;
};

// The format from --format, else from OUT's extension (.cli, .svg) or --pixel (PNGs).
LayerFormat output_format(const SliceArgs& a) {
  LayerFormat f = layer_format_for(a.output, a.format, a.pixel.has_value());
  if (a.binary) {
    if (f != LayerFormat::Cli && f != LayerFormat::CliBinary)
      throw InputError("--binary is for Common Layer Interface files (.cli)");
    f = LayerFormat::CliBinary;
  }
  if (a.pixel && f != LayerFormat::PngLayers)
    throw InputError("--pixel sets the PNG masks' pixel size: it needs --format png");
  return f;
}

// Whether `file` lies in `folder` (or below it), as paths resolve.
bool inside_folder(const fs::path& file, const fs::path& folder) {
  const fs::path f = fs::weakly_canonical(fs::absolute(file)),
                 d = fs::weakly_canonical(fs::absolute(folder));
  auto [di, fi] = std::mismatch(d.begin(), d.end(), f.begin(), f.end());
  return di == d.end() || (std::next(di) == d.end() && di->empty());
}

int run_slice(SliceArgs a) {
  const auto threads = thread_limit(a.threads);
  FillOptions options = job_options(a.job);
  const SliceOptions slice_options{.layer = a.layer, .start = a.start};
  const LayerFormat format = output_format(a);
  const bool folder = writes_folder(format);
  std::vector<OutputFile> outputs;
  if (!folder) outputs.push_back({"OUT", a.output});
  if (folder && !a.report.empty() && inside_folder(a.report, a.output))
    throw InputError("--report " + a.report +
                     " is inside OUT, a folder that is replaced whole; "
                     "put the report elsewhere (OUT gets index.json, the same report)");
  if (!a.report.empty()) outputs.push_back({"--report", a.report});
  std::vector<fs::path> inputs{a.input};
  for (const std::string& f : {a.job.field, a.job.recipe})
    if (!f.empty()) inputs.emplace_back(f);
  require_writable_outputs(inputs, outputs);

  std::unique_ptr<TerminalProgress> progress;
  if (rank() == 0 && progress_wanted(a.quiet)) progress = std::make_unique<TerminalProgress>();
  options.progress = progress.get();
  SliceOptions so = slice_options;
  so.progress = progress.get();
  so.rounding = layer_rounding(format);

  const MeshFile file = read_mesh_file(a.input);
  print_warnings(file.warnings);
  // The writer needs the part's box and layer count before the first layer arrives.
  Box3 box = bounding_box(file.soup);
  const double f = options.units.factor();
  box = {f * box.min, f * box.max};
  LayerFileOptions files{.format = format,
                         .bounds = box,
                         .layer_count = box.empty() ? 0 : layer_count(box, slice_options),
                         .layer = a.layer,
                         .pixel = a.pixel.value_or(0.05),
                         .label = fs::path(a.input).stem().string()};

  // Under mpirun each rank slices its share of the layers: into the one staged folder rank 0
  // made (a shared file system), or sent to rank 0 for a one-file format.
  const bool root = rank() == 0;
  std::optional<StagedFolder> staged_folder;
  StagedOutputs staged;
  if (folder && root) staged_folder.emplace(a.output);
  const fs::path target = broadcast(
      !root ? std::string() : (folder ? staged_folder->path() : staged.stage(a.output)).string());
  so.preflight = [&](const SliceForecast& f) {
    run_preflight({.samples = f.samples,
                   .made = count_text(static_cast<double>(f.layers)) + " layers of about " +
                           count_text(f.points) + " contour points",
                   .made_json = {{"layers", f.layers}, {"points", std::round(f.points)}},
                   .bytes = layer_file_bytes(files, f.points),
                   .format = std::string(layer_format_name(format)),
                   .seconds_low = f.seconds_low,
                   .seconds_high = f.seconds_high,
                   .smaller = "a larger --voxel or --layer" +
                              std::string(format == LayerFormat::PngLayers ? " or --pixel" : "")},
                  a.yes, progress.get());
  };
  std::optional<LayerFileWriter> writer;
  if (root || folder) writer.emplace(target, files);
  std::optional<SliceReport> on_ranks = slice_on_ranks(
      file.soup, options, so, files.layer_count, [&](const Layer& layer) { writer->add(layer); },
      folder);
  if (writer) writer->finish();
  if (!on_ranks) return kOk;
  SliceReport& report = *on_ranks;
  if (progress) progress->clear();

  JobReport& job = report.job;
  job.recipe = recipe_json(report.resolved);
  record_provenance(job, a.input);
  const std::string json = to_json(report);
  if (folder) write_file_atomically(target / "index.json", json);
  if (!a.report.empty()) write_file_atomically(staged.stage(a.report), json);
  if (folder) staged_folder->commit();
  staged.commit();

  if (!a.quiet) {
    std::printf("%s -> %s (%s)\n%s", a.input.c_str(), a.output.c_str(),
                std::string(layer_format_name(format)).c_str(), to_text(report).c_str());
    if (!a.report.empty()) std::printf("report       %s\n", a.report.c_str());
  }
  print_warnings(job.warnings);
  return kOk;
}

}  // namespace

Command add_slice_command(CLI::App& app) {
  auto args = std::make_shared<SliceArgs>();
  CLI::App* sub = app.add_subcommand(
      "slice", "Slice the lattice fill would make into printer layers, without a mesh");
  sub->footer(
      "Each layer is the cross-section of exactly the solid `tpmsfill fill` meshes with the "
      "same options (model clipping, lattice, grading, blends, skin): its field is sampled on "
      "the plane through the layer's centre at fill's grid nodes (--voxel), and its zero level "
      "traced by marching squares with marching cubes' rules. Contours are closed, outer ones "
      "counter-clockwise and holes clockwise seen from above, and checked with exact "
      "predicates never to cross or touch. No mesh is made, so memory stays small whatever "
      "the part's size: one slab of planes per layer being worked on.\n\n"
      "Formats: .cli (Common Layer Interface, what laser powder-bed machines read; --binary "
      "for its binary form), .svg (every layer in one file), or a folder with --format "
      "svg-layers (one SVG per layer) or png (one 8-bit mask per layer for DLP/SLA, "
      "antialiased, --pixel mm per pixel). A folder also gets index.json: the report, with "
      "every layer's height, area and contour counts. The report's volume (the layers' areas "
      "times --layer) matches the lattice volume of fill --keep-islands with the same "
      "options.\n\n"
      "Islands (pieces fill removes because they float free) are kept: a single layer cannot "
      "tell them; run fill to see whether there are any.\n\n"
      "Examples:\n"
      "  tpmsfill slice femur.stl femur.cli --layer 0.03 --cell 2 --voxel 0.03\n"
      "  tpmsfill slice part.stl part.cli --binary --layer 0.05 --porosity 0.7 --skin 0.4\n"
      "  tpmsfill slice part.stl layers.svg --layer 0.1 --lattice diamond --sheet\n"
      "  tpmsfill slice part.stl masks/ --format png --pixel 0.05 --layer 0.05\n\n"
      "Exit code 0: written; 1: a layer's contours failed the exact check (nothing written; a "
      "bug); 2: unreadable input, bad arguments or over the memory budget.");
  sub->add_option(
         "IN", args->input,
         "Mesh: STL, OBJ, PLY, OFF (gzip allowed), 3MF or a scene (glTF, FBX, COLLADA, ...), "
         "mm; holes, flipped faces and "
         "overlapping shells are fine")
      ->required();
  sub->add_option("OUT", args->output,
                  "Layers: a .cli or .svg file, or a folder for --format svg-layers or png")
      ->required();
  sub->add_option("--layer", args->layer, "Layer thickness in mm, e.g. 0.03 or 0.05")
      ->required()
      ->check(positive());
  sub->add_option("--start", args->start,
                  "Height of the first layer's bottom in mm (default: the model's lowest point)");
  sub->add_option("--format", args->format,
                  "cli, cli-binary, svg, svg-layers or png (default: from OUT's extension)");
  sub->add_flag("--binary", args->binary, "Binary Common Layer Interface instead of ASCII");
  sub->add_option("--pixel", args->pixel, "PNG pixel size in mm (default 0.05)")->check(positive());
  add_job_options(sub, args->job);
  sub->add_option("--report", args->report, "Write the JSON report here (fields: docs/cli.md)");
  add_threads_option(sub, args->threads);
  add_yes_flag(sub, args->yes);
  sub->add_flag("--quiet", args->quiet, "Print nothing but errors and warnings");
  return [args] { return run_slice(*args); };
}

}  // namespace tpmsfill::cli
