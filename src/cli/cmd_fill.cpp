// `tpmsfill fill IN OUT`: read a mesh, fill it with a TPMS lattice (tpmsfill::fill), write the
// validated lattice and, when asked, the report. This file only parses, times I/O and prints.
#include <tbb/global_control.h>
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <memory>
#include <optional>
#include <string>
#include <tpmsfill/error.hpp>
#include <tpmsfill/fill.hpp>
#include <tpmsfill/io.hpp>
#include <vector>

#include "cli/commands.hpp"
#include "cli/terminal_progress.hpp"

namespace tpmsfill::cli {
namespace {

struct FillArgs {
  std::string input, output, report;
  std::string lattice = "gyroid";
  std::string inside = "auto";
  bool sheet = false;
  std::vector<double> cell{2.0};
  std::optional<double> level, thickness;
  double voxel = 0.1;
  double scale = 1.0;
  int band = 1;
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

double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

int run_fill(const FillArgs& args) {
  std::optional<tbb::global_control> threads;
  if (args.threads > 0)
    threads.emplace(tbb::global_control::max_allowed_parallelism,
                    static_cast<std::size_t>(args.threads));

  FillOptions options;
  options.grid.voxel_size = args.voxel;
  options.lattice.type = lattice_from_name(args.lattice);
  options.lattice.style = args.sheet ? LatticeStyle::Sheet : LatticeStyle::Network;
  if (args.cell.size() != 1 && args.cell.size() != 3)
    throw InputError("--cell takes one size or three (x y z), in mm");
  options.lattice.cell = args.cell.size() == 1 ? Vec3{args.cell[0], args.cell[0], args.cell[0]}
                                               : Vec3{args.cell[0], args.cell[1], args.cell[2]};
  if (args.sheet && args.level)
    throw InputError("--level is for network lattices; use --thickness with --sheet");
  if (!args.sheet && args.thickness) throw InputError("--thickness needs --sheet");
  if (args.level) options.lattice.level = *args.level;
  if (args.thickness) options.lattice.thickness = *args.thickness;
  options.band.width = args.band;
  if (args.inside == "parity")
    options.inside = InsideRule::Parity;
  else if (args.inside == "winding")
    options.inside = InsideRule::Winding;
  else if (args.inside != "auto")
    throw InputError("--inside: '" + args.inside + "' is not auto, parity or winding");
  options.full_field = args.full_field;
  options.keep_islands = args.keep_islands;
  options.check_self_intersections = !args.no_self_intersections;
  if (!args.memory.empty()) options.memory_budget = parse_bytes(args.memory);
  // Fail on a bad output name before the work, not after it.
  if (format_from_extension(args.output) == MeshFormat::Auto)
    throw InputError(args.output + ": unknown extension (use .stl, .obj, .ply or .off)");

  std::unique_ptr<TerminalProgress> progress;
  if (!args.quiet && isatty(STDERR_FILENO)) progress = std::make_unique<TerminalProgress>();
  options.progress = progress.get();

  auto t0 = std::chrono::steady_clock::now();
  MeshFile file = read_mesh_file(args.input);
  if (args.scale != 1.0)
    for (Vec3& p : file.soup.points) p = args.scale * p;
  const StageTime read{"read", seconds_since(t0), peak_memory_mb()};
  for (const std::string& w : file.warnings)
    std::fprintf(stderr, "tpmsfill: warning: %s\n", w.c_str());

  FillResult result = fill(file.soup, options);
  if (progress) progress->clear();

  t0 = std::chrono::steady_clock::now();
  write_mesh(args.output, result.mesh);
  FillReport& report = result.report;
  report.stages.insert(report.stages.begin(), read);
  report.stages.push_back({"write", seconds_since(t0), peak_memory_mb()});
  if (!args.report.empty()) write_file_atomically(args.report, to_json(report));

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
      "written. Lengths are millimetres. Network lattices are solid where f/|grad f| + level < 0; "
      "sheet lattices are walls of --thickness around the minimal surface.\n\n"
      "Examples:\n"
      "  tpmsfill fill femur.stl scaffold.stl --lattice gyroid --cell 2 --voxel 0.1\n"
      "  tpmsfill fill part.obj shell.stl --lattice diamond --sheet --thickness 0.4 --report "
      "r.json\n\n"
      "Exit code 0: written; 1: the lattice failed validation (nothing written); 2: unreadable "
      "input, bad arguments or over the memory budget.");
  sub->add_option("IN", args->input,
                  "Mesh: STL, OBJ, PLY or OFF (gzip allowed), mm; holes, flipped faces and "
                  "overlapping shells are fine")
      ->required();
  sub->add_option("OUT", args->output,
                  "Output mesh; the extension picks the format (.stl, .obj, .ply, .off)")
      ->required();
  sub->add_option("--lattice", args->lattice, "gyroid, primitive or diamond (default gyroid)");
  sub->add_flag("--sheet", args->sheet, "Sheet (shell) lattice instead of a network");
  sub->add_option("--cell", args->cell,
                  "Cell size in mm: one value, or three for x y z (default 2)")
      ->expected(1, 3);
  sub->add_option("--level", args->level,
                  "Network level in mm: 0 is the minimal surface, positive thins the struts "
                  "(default 0)");
  sub->add_option("--thickness", args->thickness, "Sheet wall thickness in mm (default 0.3)");
  sub->add_option("--voxel", args->voxel, "Grid spacing in mm (default 0.1)");
  sub->add_option("--inside", args->inside,
                  "What counts as inside: winding (the generalized winding number >= 1/2 of the "
                  "cleaned mesh, holes closed the way a person would close them), parity (odd "
                  "ray crossings, the method paper's rule, for closed meshes only) or auto "
                  "(default: the winding number, cleaning the mesh only if some grid row finds "
                  "it open or inside out)");
  sub->add_option("--scale", args->scale,
                  "Multiply the input's coordinates by this first, e.g. 25.4 for inches or 1000 "
                  "for metres (default 1)")
      ->check(CLI::PositiveNumber);
  sub->add_option("--band", args->band,
                  "Half-width of the exact-distance band in voxels (default 1, the paper's)")
      ->check(CLI::Range(1, 64));
  sub->add_flag("--full-field", args->full_field,
                "Compute the model distance at every node, not just the band (the paper's "
                "reference; slow)");
  sub->add_flag("--keep-islands", args->keep_islands,
                "Keep lattice pieces that float free of the main body (removed by default)");
  sub->add_flag("--no-self-intersections", args->no_self_intersections,
                "Skip the self-intersection search when validating");
  sub->add_option("--memory", args->memory,
                  "Memory budget, e.g. 8G or 512M (default: half of physical memory); larger "
                  "jobs are refused with the voxel size that fits");
  sub->add_option("--report", args->report, "Write the JSON report here (fields: docs/cli.md)");
  sub->add_option("--threads", args->threads, "Worker threads (default: all cores)")
      ->check(CLI::Range(1, 1024));
  sub->add_flag("--quiet", args->quiet, "Print nothing but errors and warnings");
  return [args] { return run_fill(*args); };
}

}  // namespace tpmsfill::cli
