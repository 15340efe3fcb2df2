// `tpmsfill conformal SURFACE OUT --height H`: a lattice layer that follows a surface (seed
// 004's microchannels; tpmsfill::conformal_fill). This file only parses and prints.
#include <unistd.h>

#include <algorithm>
#include <memory>
#include <optional>
#include <string>
#include <tpmsfill/conformal.hpp>
#include <tpmsfill/error.hpp>
#include <tpmsfill/io.hpp>
#include <tpmsfill/recipe.hpp>
#include <tpmsfill/units.hpp>
#include <vector>

#include "cli/commands.hpp"
#include "cli/design_flags.hpp"
#include "cli/job_files.hpp"
#include "cli/terminal_progress.hpp"
#include "cli/thread_flags.hpp"
#include "cli/units_flag.hpp"
#include "cli/validators.hpp"

namespace tpmsfill::cli {
namespace {

struct ConformalArgs {
  std::string input, output, report, recipe, side = "out", map = "field", layout = "auto";
  TpmsArgs tpms;
  double height = 0;
  std::optional<double> voxel, normal_scale, scale;
  std::optional<std::string> units;
  std::vector<double> slab, skins;
  std::vector<std::uint32_t> corners;
  bool keep_islands = false, allow_distortion = false, quiet = false;
  int threads = 0;
};

ConformalJobOptions job_options(const ConformalArgs& a) {
  ConformalJobOptions o;
  // A recipe gives the slab's design (its blends, rings, grading); flags win over it.
  if (!a.recipe.empty()) o.design = read_recipe_file(a.recipe).design;
  apply_tpms_flags(a.tpms, o.design);
  require_valid(o.design);
  o.layer.height = a.height;
  o.layer.side = surface_side_from_name(a.side);
  o.map = slab_map_from_name(a.map);
  if (a.normal_scale) o.layer.normal_scale = *a.normal_scale;
  if (!a.slab.empty()) o.layer.length_u = a.slab[0], o.layer.length_v = a.slab[1];
  if (!a.skins.empty()) o.layer.skin_surface = a.skins[0], o.layer.skin_top = a.skins[1];
  require_valid(o.layer);
  o.grid.voxel_size = a.voxel.value_or(a.height / 10);
  if (!a.corners.empty())
    o.layout.corners =
        std::array<std::uint32_t, 4>{a.corners[0], a.corners[1], a.corners[2], a.corners[3]};
  o.layout.method = layout_method_from_name(a.layout);
  o.allow_distortion = a.allow_distortion;
  o.keep_islands = a.keep_islands;
  return o;
}

int run_conformal(const ConformalArgs& a) {
  const auto threads = thread_limit(a.threads);
  ConformalJobOptions o = job_options(a);
  if (format_from_extension(a.output) == MeshFormat::Auto)
    throw InputError(unknown_mesh_extension(a.output));
  // STL stores floats, 3MF what lib3mf prints, the others doubles: the mesh validated is the
  // file's.
  o.rounding = rounding_for(format_from_extension(a.output));
  std::vector<OutputFile> outputs{{"OUT", a.output}};
  if (!a.report.empty()) outputs.push_back({"--report", a.report});
  std::vector<std::filesystem::path> inputs{a.input};
  if (!a.recipe.empty()) inputs.emplace_back(a.recipe);
  require_writable_outputs(inputs, outputs);

  std::unique_ptr<TerminalProgress> progress;
  if (progress_wanted(a.quiet)) progress = std::make_unique<TerminalProgress>();
  o.progress = progress.get();
  const MeshFile file = read_mesh_file(a.input);
  print_warnings(file.warnings);
  ModelUnits units;
  if (a.units) units.units = units_from_name(*a.units);
  if (a.scale) units.scale = *a.scale;
  require_valid(units);
  const TriangleSoup surface = to_millimetres(file.soup, units);
  // A wrong unit makes a layer of millimetres on a surface of metres (or microns): say so
  // before the memory estimate does, in numbers that make no sense.
  const Box3 box = bounding_box(surface);
  if (const std::string hint = units_hint(box, units.units); !hint.empty()) {
    const Vec3 size = box.size();
    std::fprintf(stderr, "tpmsfill: warning: the surface is %.3g mm across, implausible in %s%s\n",
                 std::max({size.x, size.y, size.z}), std::string(units_name(units.units)).c_str(),
                 hint.c_str());
  }
  ConformalResult result = conformal_fill(surface, o);
  result.fill.units = units_name(units.units);
  result.fill.scale = units.scale;
  result.fill.mm_per_unit = units.factor();
  if (progress) progress->clear();

  FillReport& report = result.fill;
  record_provenance(report, a.input);
  StagedOutputs staged;
  write_mesh(staged.stage(a.output), result.mesh, write_options_for(a.output));
  if (!a.report.empty()) write_file_atomically(staged.stage(a.report), to_json(result));
  staged.commit();
  if (!a.quiet) {
    std::printf("%s -> %s\n%s", a.input.c_str(), a.output.c_str(), to_text(result).c_str());
    if (!a.report.empty()) std::printf("report       %s\n", a.report.c_str());
  }
  print_warnings(report.warnings);
  return kOk;
}

}  // namespace

Command add_conformal_command(CLI::App& app) {
  auto args = std::make_shared<ConformalArgs>();
  CLI::App* sub = app.add_subcommand(
      "conformal", "Grow a lattice layer of a given height that follows a surface");
  sub->footer(
      "The surface (one boundary loop, or two for a tube such as a blade, cut along a seam) is "
      "laid flat: on the unit square by mean-value coordinates, or free (as rigid as possible, "
      "the boundary let move), whichever spreads the cells' sizes less (--layout). A surface "
      "whose cells would come out under half or over twice the size asked is refused (a deep "
      "face or cap: cut it into flatter pieces) unless --allow-distortion. The lattice is designed "
      "in a "
      "slab of LU x LV x H mm (x along u, y along v, z up the layer; LU and LV default to the "
      "surface's mean lengths, so cells keep their size on average) and carried onto the "
      "surface: each grid node takes its closest point on the surface, the (u, v) there and "
      "its height h along the normal. The layer is what lies between h = 0 and h = H; skins "
      "close it into a channel. The output is validated like every fill: closed, 2-manifold, "
      "outward, no self-intersections.\n\n"
      "The report gives the layout's flips (0 expected) and distortion (area scale and angle "
      "ratio, p5/p50/p95), the cell sizes on the surface, the smallest radius of curvature on "
      "the layer's side (the layer folds where H exceeds it: warned) and the output's heights.\n\n"
      "Examples:\n"
      "  tpmsfill conformal face.off channel.stl --height 3 --lattice primitive --cell 5\n"
      "  tpmsfill conformal lion-head.off mask.stl --scale 100 --height 4 --cell 8\n"
      "  tpmsfill conformal blade.off skin.stl --height 1 --side in --skins 0.2 0.2 --voxel 0.1\n"
      "  tpmsfill conformal dome.stl dome-lattice.stl --height 2 --recipe rings.json "
      "(rings: docs/recipes.md)\n\n"
      "Exit code 0: written; 1: the lattice failed validation (nothing written); 2: unreadable "
      "input, a surface that is not a disk or a tube, or bad arguments.");
  sub->add_option("SURFACE", args->input,
                  "Surface mesh (STL, OBJ, PLY, OFF; mm): oriented, one piece, one or two "
                  "boundary loops, no handles")
      ->required();
  sub->add_option("OUT", args->output, "Output mesh (.stl, .obj, .ply, .off, .3mf)")->required();
  sub->add_option("--height", args->height, "Height H of the layer above the surface, mm")
      ->required()
      ->check(positive());
  sub->add_option("--side", args->side,
                  "out: along the surface's normals (the side its triangles face); in: against "
                  "them (default out)");
  sub->add_option("--recipe", args->recipe,
                  "JSON recipe for the slab's design: lattice, blends and ring regions in slab "
                  "millimetres (docs/recipes.md); flags given as well override it")
      ->check(existing_file());
  sub->add_option("--map", args->map,
                  "field (default: every grid node takes its closest point's (u, v) and height; "
                  "always valid) or vertex (the seed's: the slab's mesh lifted vertex by vertex "
                  "along the normals, edges split where they stray; disks only, "
                  "refused where it folds)");
  add_tpms_options(sub, args->tpms);
  add_units_flag(sub, args->units);
  sub->add_option("--scale", args->scale,
                  "Multiply the surface's coordinates (after --units) by this (default 1)")
      ->check(positive());
  sub->add_option("--voxel", args->voxel, "Grid spacing in mm (default H/10)")->check(positive());
  sub->add_option("--slab", args->slab,
                  "The slab's size LU LV in mm (default: the surface's mean lengths along u and "
                  "v; a tube's LU is rounded to whole cells so the lattice closes)")
      ->expected(2);
  sub->add_option("--normal-scale", args->normal_scale,
                  "Stretch the design across the layer: its z is h / S (default 1)")
      ->check(positive());
  sub->add_option("--skins", args->skins,
                  "Solid skins A B mm thick on the surface and under the top (0 for none), "
                  "making the layer a closed channel")
      ->expected(2);
  sub->add_option("--layout", args->layout,
                  "auto (default: free where it has no flips and spreads the area scale less, "
                  "else the square), square (mean-value coordinates on the unit square) or free "
                  "(as rigid as possible: cells keep their size on deep surfaces)");
  sub->add_flag("--allow-distortion", args->allow_distortion,
                "Write the layer even where cells come out under half or over twice the size "
                "asked (refused otherwise, with the sizes)");
  sub->add_option("--corners", args->corners,
                  "Disks: the four boundary vertices (indices in SURFACE) placed at the unit "
                  "square's corners, in order along the boundary (default: where it turns most, "
                  "then every quarter of its length)")
      ->expected(4);
  sub->add_flag("--keep-islands", args->keep_islands,
                "Keep lattice pieces that float free of the main body (removed by default)");
  sub->add_option("--report", args->report, "Write the JSON report here (fields: docs/cli.md)");
  add_threads_option(sub, args->threads);
  sub->add_flag("--quiet", args->quiet, "Print nothing but errors and warnings");
  return [args] { return run_conformal(*args); };
}

}  // namespace tpmsfill::cli
