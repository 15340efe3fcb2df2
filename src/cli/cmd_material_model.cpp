// `tpmsfill material slice|iso MODEL OUT`: a fitted solid (.tsm) sliced directly into printer
// layers with its material, or its iso-material surfaces (seed 001 §3, §4.3). This file only
// parses, calls the stages, times and prints; `material info|fit` are in cmd_material.cpp.
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <map>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <tpmsfill/check.hpp>
#include <tpmsfill/error.hpp>
#include <tpmsfill/io.hpp>
#include <tpmsfill/layer_files.hpp>
#include <tpmsfill/slice.hpp>
#include <tpmsfill/solid/material_layers.hpp>
#include <tpmsfill/solid/solid_model.hpp>
#include <tpmsfill/solid/solid_slice.hpp>
#include <vector>

#include "cli/commands.hpp"
#include "cli/job_files.hpp"
#include "cli/preflight.hpp"
#include "cli/terminal_progress.hpp"
#include "cli/validators.hpp"
#include "core/parallel.hpp"

namespace tpmsfill::cli {
namespace {
namespace fs = std::filesystem;

struct ModelArgs {
  std::string input, output;
  double layer = 0, tau = 0, pixel = 0.05;
  std::optional<double> start;
  std::optional<std::string> format;
  std::vector<double> values;
  int bins = 10, initial_level = 1, max_level = 8;
  bool json = false, quiet = false, colour = false, yes = false;
};

std::pair<double, double> material_range(const SolidSpline& s) {
  if (s.material.empty()) return {0, 1};
  const auto [lo, hi] = std::minmax_element(s.material.begin(), s.material.end());
  return {*lo, *hi};
}

double seconds_since(std::chrono::steady_clock::time_point t) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t).count();
}

// A progress line for work counted in items (layers, surfaces).
struct ItemProgress {
  std::unique_ptr<TerminalProgress> terminal;
  ItemProgress(bool quiet, const char* stage) {
    if (progress_wanted(quiet)) {
      terminal = std::make_unique<TerminalProgress>();
      terminal->begin(stage);
    }
  }
  void report(double fraction) {
    if (terminal) terminal->report(fraction);
  }
};

// The preflight of a material slice: a few layers spread over the stack sliced first forecast
// the rest (a solid's sections change little from one layer to the next, and a section's
// octree is the work), so a stack of thousands of layers is known before it starts.
void preflight_material_slice(const ModelArgs& a, const SolidSpline& spline, double start,
                              const LayerFileOptions& files, const SolidSliceOptions& options,
                              TerminalProgress* progress) {
  const std::uint64_t count = files.layer_count, probes = 6;
  if (count <= 2 * probes) return;  // as quick as its forecast
  std::vector<double> points(probes), triangles(probes);
  const auto t = std::chrono::steady_clock::now();
  tpmsfill::detail::parallel_for(probes, 1, [&](std::size_t b, std::size_t e) {
    for (std::size_t k = b; k < e; ++k) {
      // Spread by the golden ratio, not at simple fractions of the stack: the layers on the
      // octree's cell faces (halves, quarters) are slower and carry more triangles.
      const double place = std::fmod(0.5 + 0.6180339887498949 * static_cast<double>(k), 1.0);
      const auto index = std::min(count - 1, static_cast<std::uint64_t>(place * double(count)));
      const SolidSection s =
          slice_solid(spline, start + a.layer * (static_cast<double>(index) + 0.5), options);
      for (const Contour& c : s.contours) points[k] += static_cast<double>(c.points.size());
      triangles[k] = static_cast<double>(s.mesh.triangles.size());
    }
  });
  const double per_layer = seconds_since(t) / probes, scale = double(count) / probes;
  double all_points = 0, all_triangles = 0;
  for (std::size_t k = 0; k < probes; ++k)
    all_points += scale * points[k], all_triangles += scale * triangles[k];
  const double seconds = per_layer * static_cast<double>(count);
  run_preflight(
      {.made = count_text(static_cast<double>(count)) + " layers of about " +
               count_text(all_points) + " contour points and " + count_text(all_triangles) +
               " triangles",
       .made_json = {{"layers", count},
                     {"points", std::round(all_points)},
                     {"triangles", std::round(all_triangles)}},
       .bytes = layer_file_bytes(files, all_points, all_triangles),
       .format = std::string(layer_format_name(files.format)),
       .seconds_low = 0.5 * seconds,
       .seconds_high = 2 * seconds,
       .smaller = "a larger --layer or --tau" +
                  std::string(files.format == LayerFormat::PngLayers ? " or --pixel" : "")},
      a.yes, progress);
}

int run_material_slice(const ModelArgs& a) {
  const LayerFormat format = layer_format_for(a.output, a.format);
  if (a.colour && format != LayerFormat::PngLayers)
    throw InputError("--colour draws PNG layers (--format png); SVG layers are coloured already");
  const bool folder = writes_folder(format);
  if (!folder) require_writable_outputs({a.input}, {{"OUT", a.output}});
  const auto t0 = std::chrono::steady_clock::now();
  const SolidModel model = read_solid_model(a.input);
  const SolidSpline& spline = model.fit.spline;
  const Box3 box = solid_box(spline);
  const double start = a.start.value_or(box.min.z);
  const std::uint64_t count = layer_count(box, {.layer = a.layer, .start = start});
  const auto [lo, hi] = material_range(spline);
  const double tau = a.tau > 0 ? a.tau : default_slice_tau(box);
  const LayerFileOptions files{.format = format,
                               .bounds = box,
                               .layer_count = count,
                               .layer = a.layer,
                               .pixel = a.pixel,
                               .material_colour = a.colour,
                               .label = fs::path(a.input).stem().string()};
  const SolidSliceOptions options{
      .tau = tau, .initial_level = a.initial_level, .max_level = a.max_level};
  ItemProgress progress(a.quiet, "material slice");
  preflight_material_slice(a, spline, start, files, options, progress.terminal.get());
  std::optional<StagedFolder> staged_folder;
  StagedOutputs staged;
  if (folder) staged_folder.emplace(a.output);
  const fs::path target = folder ? staged_folder->path() : staged.stage(a.output);
  LayerFileWriter writer(target, files);
  nlohmann::ordered_json layers = nlohmann::ordered_json::array();
  std::size_t triangles = 0, flipped = 0;
  double volume = 0;
  // Layers are independent: a batch at a time in parallel, written in order.
  const std::uint64_t batch = 16;
  for (std::uint64_t first = 0; first < count; first += batch) {
    const std::uint64_t n = std::min(batch, count - first);
    std::vector<SolidSection> sections(n);
    std::vector<double> seconds(n);
    tpmsfill::detail::parallel_for(n, 1, [&](std::size_t b, std::size_t e) {
      for (std::size_t k = b; k < e; ++k) {
        const auto t = std::chrono::steady_clock::now();
        const double bottom = start + a.layer * static_cast<double>(first + k);
        sections[k] = slice_solid(spline, bottom + 0.5 * a.layer, options);
        seconds[k] = seconds_since(t);
      }
    });
    for (std::uint64_t k = 0; k < n; ++k) {
      const SolidSection& s = sections[k];
      const double bottom = start + a.layer * static_cast<double>(first + k);
      writer.add(material_layer(s, first + k, bottom, bottom + a.layer, lo, hi));
      triangles += s.mesh.triangles.size();
      flipped += s.flipped;
      volume += s.area * a.layer;  // the layer's prism: its middle section times its height
      layers.push_back({{"index", first + k},
                        {"z", s.z},
                        {"area_mm2", s.area},
                        {"contours", s.contours.size()},
                        {"triangles", s.mesh.triangles.size()},
                        {"level", s.mesh.level},
                        {"cells", s.mesh.cells},
                        {"flipped", s.flipped},
                        {"material_area_mm2", material_histogram(s, lo, hi, a.bins)},
                        {"seconds", seconds[k]}});
    }
    progress.report(double(first + n) / double(count));
  }
  writer.finish();
  nlohmann::ordered_json j;
  j["input"] = a.input;
  j["output"] = a.output;
  j["format"] = layer_format_name(format);
  j["box_mm"] = {{box.min.x, box.min.y, box.min.z}, {box.max.x, box.max.y, box.max.z}};
  j["layer_mm"] = a.layer;
  j["layers"] = count;
  j["tau_mm3"] = tau;
  j["material_scale"] = {lo, hi};
  j["material_bins"] = a.bins;
  j["triangles"] = triangles;
  j["flipped"] = flipped;
  j["volume_mm3"] = volume;
  j["wall_seconds"] = seconds_since(t0);
  j["per_layer"] = layers;
  if (folder) write_file_atomically(target / "index.json", j.dump(2));
  if (folder) staged_folder->commit();
  staged.commit();
  if (progress.terminal) progress.terminal->clear();
  if (a.json) {
    std::printf("%s\n", j.dump(2).c_str());
  } else if (!a.quiet) {
    double largest = 0;
    for (const auto& l : layers) largest = std::max(largest, l["area_mm2"].get<double>());
    std::printf(
        "%s -> %s (%s): %llu layers of %g mm, tau %g mm3, %zu triangles, largest section "
        "%g mm2, %.2f s\n",
        a.input.c_str(), a.output.c_str(), std::string(layer_format_name(format)).c_str(),
        static_cast<unsigned long long>(count), a.layer, tau, triangles, largest,
        j["wall_seconds"].get<double>());
  }
  if (flipped > 0)
    print_warnings({std::to_string(flipped) +
                    " section triangles are turned over (where G folds): each layer's "
                    "contours and area are those of the region its triangles cover"});
  return kOk;
}

// Edges used once (open, where the surface meets the solid's boundary) and more than twice.
std::pair<std::size_t, std::size_t> edge_counts(const SolidLevelSet& s) {
  std::map<std::pair<std::uint32_t, std::uint32_t>, int> uses;
  for (const auto& t : s.triangles)
    for (int e = 0; e < 3; ++e) ++uses[std::minmax(t[e], t[(e + 1) % 3])];
  std::size_t open = 0, over = 0;
  for (const auto& [edge, n] : uses) open += n == 1, over += n > 2;
  return {open, over};
}

// The areas of the surface's pieces (triangles joined through their corners), largest first.
std::vector<double> piece_areas(const SolidLevelSet& s) {
  std::vector<std::uint32_t> parent(s.points.size());
  for (std::uint32_t p = 0; p < parent.size(); ++p) parent[p] = p;
  const auto root = [&](std::uint32_t p) {
    while (parent[p] != p) p = parent[p] = parent[parent[p]];
    return p;
  };
  for (const auto& t : s.triangles)
    for (int e = 1; e < 3; ++e) parent[root(t[e])] = root(t[0]);
  std::map<std::uint32_t, double> area;
  for (const auto& t : s.triangles)
    area[root(t[0])] +=
        norm(cross(s.points[t[1]] - s.points[t[0]], s.points[t[2]] - s.points[t[0]])) / 2;
  std::vector<double> out;
  for (const auto& [r, a] : area) out.push_back(a);
  std::sort(out.rbegin(), out.rend());
  return out;
}

int run_material_iso(const ModelArgs& a) {
  if (a.values.empty()) throw InputError("--values needs at least one material value");
  require_writable_outputs({a.input}, {{"OUT", a.output}});
  const auto t0 = std::chrono::steady_clock::now();
  const SolidModel model = read_solid_model(a.input);
  const SolidSpline& spline = model.fit.spline;
  if (spline.material.empty()) throw InputError(a.input + " has no material (fitted without one)");
  const auto [lo, hi] = material_range(spline);
  const Box3 box = solid_box(spline);
  const double tau = a.tau > 0 ? a.tau : default_slice_tau(box);
  TriangleSoup all;
  nlohmann::ordered_json surfaces = nlohmann::ordered_json::array();
  ItemProgress progress(a.quiet, "material iso");
  std::vector<std::string> warnings;
  const SolidSliceOptions options{
      .tau = tau, .initial_level = a.initial_level, .max_level = a.max_level};
  for (std::size_t v = 0; v < a.values.size(); ++v) {
    const auto t = std::chrono::steady_clock::now();
    const SolidLevelSet s = iso_material_surface(spline, a.values[v], options);
    const auto first = static_cast<std::uint32_t>(all.points.size());
    all.points.insert(all.points.end(), s.points.begin(), s.points.end());
    for (const auto& tri : s.triangles)
      all.triangles.push_back({first + tri[0], first + tri[1], first + tri[2]});
    double area = 0, worst = 0;
    for (const auto& tri : s.triangles)
      area +=
          norm(cross(s.points[tri[1]] - s.points[tri[0]], s.points[tri[2]] - s.points[tri[0]])) / 2;
    for (double m : s.material) worst = std::max(worst, std::abs(m - a.values[v]));
    const auto [open, over] = edge_counts(s);
    // Whole or in pieces: a small piece is a cap where the material just reaches the value
    // (the tets' own surface has it too) or a tear where G or M fold; the count tells.
    const std::vector<double> pieces = piece_areas(s);
    std::size_t small = 0;
    for (double p : pieces) small += p < 0.01 * pieces.front();
    if (s.triangles.empty())
      warnings.push_back("no surface at material " + std::to_string(a.values[v]) +
                         " (the solid's material spans " + std::to_string(lo) + " to " +
                         std::to_string(hi) + ")");
    surfaces.push_back(
        {{"material", a.values[v]},
         {"triangles", s.triangles.size()},
         {"area_mm2", area},
         {"open_edges", open},
         {"non_manifold_edges", over},
         {"pieces", pieces.size()},
         {"small_pieces", small},
         {"smallest_piece_share", pieces.empty() ? 0.0 : pieces.back() / pieces.front()},
         {"max_material_error", worst},
         {"level", s.level},
         {"seconds", seconds_since(t)}});
    progress.report(double(v + 1) / double(a.values.size()));
  }
  // The surfaces as OUT holds them (STL's floats, 3MF's micrometres): far from the origin a
  // sliver's corners can round onto one point or one line, which no rule of the surfaces'
  // own prevents (their points come through G, off any grid). Counted, and warned about with
  // what to do when the rounding made any.
  const RoundingCheck held = check_rounding(all, rounding_for(format_from_extension(a.output)));
  if (!held.warning.empty()) warnings.push_back(held.warning);
  write_mesh(a.output, all);
  if (progress.terminal) progress.terminal->clear();
  nlohmann::ordered_json j;
  j["input"] = a.input;
  j["output"] = a.output;
  j["tau_mm3"] = tau;
  j["surfaces"] = surfaces;
  j["degenerate_triangles"] = held.held_degenerate;
  j["wall_seconds"] = seconds_since(t0);
  if (a.json || !a.quiet) {
    if (a.json) {
      std::printf("%s\n", j.dump(2).c_str());
    } else {
      for (const auto& s : surfaces)
        std::printf(
            "material %-10g %8zu triangles  %10.4g mm2  %zu open edges  %zu pieces (%zu "
            "under 1 %% of the largest)\n",
            s["material"].get<double>(), s["triangles"].get<std::size_t>(),
            s["area_mm2"].get<double>(), s["open_edges"].get<std::size_t>(),
            s["pieces"].get<std::size_t>(), s["small_pieces"].get<std::size_t>());
    }
  }
  print_warnings(warnings);
  return kOk;
}

void add_octree_options(CLI::App* sub, ModelArgs& args) {
  sub->add_option("--tau", args.tau,
                  "Split cells while their volume exceeds this, mm3 (default: (box diagonal / "
                  "64)^3; the seed used 10, 1 and 0.1 on a femur's end)")
      ->check(positive());
  sub->add_option("--initial-level", args.initial_level,
                  "The uniform start (default 1, the seed's)")
      ->check(CLI::Range(0, 8));
  sub->add_option(
         "--max-level", args.max_level,
         "Never split below this level (default 8: 256 cells per axis; at most 10: a layer "
         "at level L may cost 4^L cells, and one bear layer at 10 took 49 s)")
      ->check(CLI::Range(1, 10));
  sub->add_flag("--json", args.json, "Print JSON");
  sub->add_flag("--quiet", args.quiet, "Print nothing but errors and warnings");
}

}  // namespace

std::function<std::optional<int>()> add_material_model_commands(CLI::App* material) {
  auto args = std::make_shared<ModelArgs>();
  CLI::App* slice = material->add_subcommand(
      "slice", "Slice a fitted model (.tsm) directly into printer layers with its material");
  slice->footer(
      "No mesh of the solid is made: per layer an octree in the parameter cube is refined where "
      "the plane z = layer centre crosses it, until each crossed cell's volume is within --tau; "
      "marching cubes on its cells, each at its own level and without cracks, gives the filled "
      "section, its vertices mapped through G and M (docs/method.md, seed 001 step 11). "
      "Formats: .cli (contours), .svg (triangles coloured by material), or --format "
      "svg-layers|png with a folder (PNG: grey = material, 0 empty). "
      "The report gives each layer's area, triangles and material histogram (--bins). Before "
      "a stack of more than 12 layers, six layers spread over it are sliced first to forecast "
      "its size and time (the preflight; --yes runs a job past its limits).\n\n"
      "Examples:\n"
      "  tpmsfill material slice femur.tsm femur.svg --layer 0.5\n"
      "  tpmsfill material slice femur.tsm layers/ --layer 0.1 --format png --pixel 0.05\n"
      "  tpmsfill material slice femur.tsm preview/ --layer 1 --format png --colour\n");
  slice->add_option("MODEL", args->input, "A fitted model (.tsm)")->required();
  slice->add_option("OUT", args->output, "A .cli or .svg file, or a folder")->required();
  slice->add_option("--layer", args->layer, "Layer thickness, mm")->required()->check(positive());
  slice->add_option("--start", args->start, "The first layer's bottom, mm (default: the solid's)");
  slice->add_option("--format", args->format, "cli, cli-binary, svg, svg-layers or png");
  slice->add_option("--pixel", args->pixel, "PNG pixel size, mm (default 0.05)")->check(positive());
  slice->add_flag("--colour,--color", args->colour,
                  "PNG: colour by material (the SVG's blue-green-yellow scale on white), to look "
                  "at, instead of grey = material for a printer");
  slice->add_option("--bins", args->bins, "Material histogram bins per layer (default 10)")
      ->check(CLI::Range(1, 1000));
  add_yes_flag(slice, args->yes);
  add_octree_options(slice, *args);
  CLI::App* iso = material->add_subcommand(
      "iso", "The surfaces of equal material of a fitted model (.tsm), as one mesh");
  iso->footer(
      "Each surface M = m is found like a slice (an octree in the parameter cube, marching "
      "cubes, vertices mapped through G) and is open where it meets the solid's boundary. The "
      "report gives each surface's triangles, area, open and non-manifold edges, and the "
      "largest |M - m| at its vertices.\n\n"
      "Example:\n"
      "  tpmsfill material iso femur.tsm femur-iso.ply --values 10 20 30\n");
  iso->add_option("MODEL", args->input, "A fitted model (.tsm)")->required();
  iso->add_option("OUT", args->output, "The surfaces, one mesh (STL, OBJ, PLY, OFF, 3MF)")
      ->required();
  iso->add_option("--values", args->values, "Material values, one surface each")
      ->required()
      ->expected(1, -1);
  add_octree_options(iso, *args);
  return [args, slice, iso]() -> std::optional<int> {
    if (slice->parsed()) return run_material_slice(*args);
    if (iso->parsed()) return run_material_iso(*args);
    return std::nullopt;
  };
}

}  // namespace tpmsfill::cli
