// `tpmsfill check FILE [--json]`: is FILE a closed 2-manifold ready to print, and if not,
// where not? The facts come from tpmsfill::check_mesh; this file only prints them.
#include <algorithm>
#include <cinttypes>
#include <cstdint>
#include <cstdio>
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <tpmsfill/check.hpp>
#include <tpmsfill/io.hpp>
#include <tpmsfill/render.hpp>
#include <tpmsfill/units.hpp>

#include "cli/commands.hpp"
#include "cli/job_files.hpp"
#include "cli/picture_flags.hpp"
#include "cli/thread_flags.hpp"
#include "cli/units_flag.hpp"
#include "cli/validators.hpp"

namespace tpmsfill::cli {
namespace {

struct CheckArgs {
  std::string input;
  bool json = false;
  bool skip_self_intersections = false;
  std::size_t max_examples = 10;
  std::string units = "mm";
  int threads = 0;
  std::string picture;  ///< --picture: where the defects are drawn
  PictureArgs view;
};

std::string point(const Vec3& p) {
  char s[96];
  std::snprintf(s, sizeof s, "(%.6g, %.6g, %.6g)", p.x, p.y, p.z);
  return s;
}

const char* yes_no(bool b) {
  return b ? "yes" : "no";
}

// Up to `limit` example locations under a problem line, so the user can find the spot.
void print_edge_examples(const std::vector<EdgeLocation>& edges, std::size_t limit) {
  for (std::size_t i = 0; i < edges.size() && i < limit; ++i)
    std::printf("      at edge %s - %s of triangle %" PRIu32 "\n", point(edges[i].ends[0]).c_str(),
                point(edges[i].ends[1]).c_str(), edges[i].triangle);
}

void print_triangle_examples(const char* what, const std::vector<std::uint32_t>& triangles,
                             std::size_t limit) {
  if (triangles.empty()) return;
  std::printf("  %s:", what);
  for (std::size_t i = 0; i < triangles.size() && i < limit; ++i)
    std::printf(" %" PRIu32, triangles[i]);
  std::printf("\n");
}

void print_text(const std::string& path, const MeshFile& file, const MeshCheck& c) {
  const Vec3 size = c.bbox.size();
  std::printf("%s: %s%s, %" PRIu64 " triangles, %" PRIu64 " vertices (%" PRIu64
              " points in the file)\n",
              path.c_str(), std::string(format_name(file.format)).c_str(),
              file.gzip ? " (gzip)" : "", c.triangles, c.vertices, c.points);
  if (!c.bbox.empty())
    std::printf("  bounding box     %s to %s, size %.6g x %.6g x %.6g mm\n",
                point(c.bbox.min).c_str(), point(c.bbox.max).c_str(), size.x, size.y, size.z);
  // Holes are counted after non-manifold edges are split, so a closed but non-manifold mesh
  // can have some: say so rather than print "0 border edges in 2 holes".
  if (!c.closed())
    std::printf("  closed           no (%" PRIu64 " border edges in %" PRIu64 " holes)\n",
                c.border_edges, c.holes.value_or(0));
  else if (c.holes.value_or(0) > 0)
    std::printf("  closed           yes (0 border edges; %" PRIu64
                " holes once its non-manifold edges are split)\n",
                *c.holes);
  else
    std::printf("  closed           yes (0 border edges)\n");
  std::printf("  2-manifold       %s (%" PRIu64 " non-manifold edges, %" PRIu64
              " non-manifold vertices)\n",
              yes_no(c.manifold()), c.non_manifold_edges, c.non_manifold_vertices);
  std::printf("  oriented         %s",
              c.consistently_oriented() ? "consistently" : "inconsistently");
  if (!c.consistently_oriented()) std::printf(" (%" PRIu64 " edges)", c.inconsistent_edges);
  if (c.outward) std::printf(", %s", *c.outward ? "outward" : "INWARD (inside out)");
  std::printf("\n  degenerate       %" PRIu64 " triangles; %" PRIu64 " duplicate triangles\n",
              c.degenerate_triangles, c.duplicate_triangles);
  if (c.self_intersecting_pairs)
    std::printf("  self-intersect   %" PRIu64 " triangle pairs\n", *c.self_intersecting_pairs);
  else
    std::printf("  self-intersect   not searched (--no-self-intersections)\n");
  std::printf("  components       %" PRIu64 " (%" PRIu64 " when only shared edges connect)\n",
              c.components, c.edge_components);
  std::printf("  duplicate points %" PRIu64 " merged (bit-identical), %" PRIu64 " unreferenced\n",
              c.duplicate_points, c.unreferenced_points);
  std::printf("  area             %.6g mm^2\n", c.area);
  if (c.volume) std::printf("  volume           %.6g mm^3\n", *c.volume);
  if (c.genus) std::printf("  genus            %" PRId64 "\n", *c.genus);

  if (c.valid()) {
    std::printf(
        "verdict: VALID: a closed, outward-oriented 2-manifold without self-intersections "
        "or degenerate faces\n");
    return;
  }
  std::printf("verdict: NOT VALID\n");
  for (const std::string& problem : c.problems()) std::printf("  - %s\n", problem.c_str());
  // Where: a few locations for each defect class (all of them are in --json).
  const std::size_t n = 3;
  if (!c.border_edge_examples.empty()) {
    std::printf("  border edges:\n");
    print_edge_examples(c.border_edge_examples, n);
  }
  if (!c.non_manifold_edge_examples.empty()) {
    std::printf("  non-manifold edges:\n");
    print_edge_examples(c.non_manifold_edge_examples, n);
  }
  if (!c.inconsistent_edge_examples.empty()) {
    std::printf("  inconsistently oriented edges:\n");
    print_edge_examples(c.inconsistent_edge_examples, n);
  }
  if (!c.non_manifold_vertex_examples.empty()) {
    std::printf("  non-manifold vertices:\n");
    for (std::size_t i = 0; i < c.non_manifold_vertex_examples.size() && i < n; ++i)
      std::printf("      at %s\n", point(c.non_manifold_vertex_examples[i]).c_str());
  }
  print_triangle_examples("degenerate triangles", c.degenerate_triangle_examples, n);
  print_triangle_examples("duplicate triangles", c.duplicate_triangle_examples, n);
  if (!c.self_intersection_examples.empty()) {
    std::printf("  self-intersecting triangle pairs:");
    for (std::size_t i = 0; i < c.self_intersection_examples.size() && i < n; ++i)
      std::printf(" (%" PRIu32 ", %" PRIu32 ")", c.self_intersection_examples[i][0],
                  c.self_intersection_examples[i][1]);
    std::printf("\n");
  }
  std::printf(
      "  (triangles are numbered from 0 in file order, polygons counted after "
      "triangulation)\n");
}

// The check with at most n examples of each defect class (the picture draws them all).
MeshCheck with_examples(MeshCheck c, std::size_t n) {
  auto cut = [n](auto& v) { v.resize(std::min(v.size(), n)); };
  cut(c.border_edge_examples);
  cut(c.non_manifold_edge_examples);
  cut(c.inconsistent_edge_examples);
  cut(c.non_manifold_vertex_examples);
  cut(c.degenerate_triangle_examples);
  cut(c.duplicate_triangle_examples);
  cut(c.self_intersection_examples);
  return c;
}

// The defects drawn over the mesh (in millimetres, as the check's locations are).
void write_picture(const CheckArgs& args, TriangleSoup soup, const MeshCheck& check,
                   double mm_per_unit) {
  if (mm_per_unit != 1)
    for (Vec3& p : soup.points) p = mm_per_unit * p;
  const RenderOptions options = mark_defects(soup, check, picture_options(args.view));
  write_png(args.picture, render_mesh(soup, options));
}

int run_check(const CheckArgs& args) {
  const auto threads = thread_limit(args.threads);
  if (!args.picture.empty()) {
    require_png_name("--picture", args.picture);
    require_writable_outputs({args.input}, {{"--picture", args.picture}});
    picture_options(args.view);  // refuse a bad --view before the work
  }

  MeshFile file = read_mesh_file(args.input);
  CheckOptions options;
  options.self_intersections = !args.skip_self_intersections;
  options.max_examples = args.picture.empty() ? args.max_examples : SIZE_MAX;
  options.units.units = units_from_name(args.units);
  const MeshCheck all = check_mesh(file.soup, options);
  if (!args.picture.empty()) write_picture(args, std::move(file.soup), all, options.units.factor());
  const MeshCheck check = with_examples(all, args.max_examples);
  // A part a thousandth or a thousand times the size of anything printable was most likely
  // modelled in another unit: say which before the user fills it.
  std::string hint = units_hint(check.bbox, options.units.units);
  if (!hint.empty()) {
    const Vec3 s = check.bbox.size();
    char size[96];
    std::snprintf(size, sizeof size, "the mesh is %.3g mm across, implausible for a part in %s",
                  std::max({s.x, s.y, s.z}), args.units.c_str());
    hint = size + hint;
  }

  if (args.json) {
    nlohmann::ordered_json j;
    j["file"] = args.input;
    j["format"] = format_name(file.format);
    j["gzip"] = file.gzip;
    j["faces_in_file"] = file.faces_in_file;
    j["polygons_triangulated"] = file.polygons_triangulated;
    j["warnings"] = file.warnings;
    j["units"] = units_name(options.units.units);
    j["units_hint"] = hint.empty() ? nlohmann::ordered_json(nullptr) : nlohmann::ordered_json(hint);
    const auto facts = nlohmann::ordered_json::parse(to_json(check));  // outlives the loop
    for (const auto& [key, value] : facts.items()) j[key] = value;
    std::printf("%s\n", j.dump(2).c_str());
  } else {
    print_warnings(file.warnings);
    print_text(args.input, file, check);
    if (!hint.empty()) std::printf("hint: %s\n", hint.c_str());
    if (!args.picture.empty()) std::printf("picture: %s\n", args.picture.c_str());
  }
  return check.valid() ? kOk : kNotValid;
}

}  // namespace

Command add_check_command(CLI::App& app) {
  auto args = std::make_shared<CheckArgs>();
  CLI::App* sub = app.add_subcommand(
      "check", "Is a mesh a closed 2-manifold ready to print? If not, where not?");
  sub->footer(
      "Reports border edges and holes, non-manifold edges and vertices, orientation (consistent "
      "and outward), self-intersecting triangle pairs, degenerate and duplicate triangles, "
      "duplicate points, components, and volume, area and genus when closed. Points with "
      "bit-identical coordinates are merged first (STL stores three per facet); no tolerance is "
      "used.\n\nExit code 0: a closed, outward-oriented 2-manifold without self-intersections or "
      "degenerate faces; 1: readable but not that; 2: unreadable file or bad arguments.\n\n"
      "--picture draws the mesh with its defects marked: border edges, non-manifold edges and "
      "vertices, self-intersecting pairs and flipped faces in their own colours (told apart "
      "with colour-blind eyes too), edges thick and paler where the surface hides them, with a "
      "legend; a valid mesh gives a plain picture that says so.\n\n"
      "Examples:\n"
      "  tpmsfill check femur.stl --json > femur-check.json\n"
      "  tpmsfill check scan.stl --picture scan-defects.png\n"
      "  tpmsfill check scan.stl --picture underside.png --view=-z --size 1024");
  sub->add_option("FILE", args->input,
                  "Mesh file: STL, OBJ, PLY, OFF (gzip allowed), 3MF, or a scene (glTF/GLB, FBX, "
                  "COLLADA, 3DS, ... through assimp)")
      ->required();
  sub->add_flag("--json", args->json,
                "Print one JSON object instead of text (fields: docs/cli.md)");
  add_units_flag(sub, args->units);
  sub->add_flag("--no-self-intersections", args->skip_self_intersections,
                "Skip the self-intersection search (the slowest check)");
  sub->add_option("--max-examples", args->max_examples,
                  "Locations kept per defect class (default 10)")
      ->check(between(0, 1000000, "0 to 1000000"));
  add_threads_option(sub, args->threads);
  sub->add_option("--picture", args->picture,
                  "Also draw the mesh with its defects marked to this PNG (written whatever the "
                  "verdict); --view, --clip and --size as for render");
  add_picture_options(sub, args->view, true);
  return [args] { return run_check(*args); };
}

}  // namespace tpmsfill::cli
