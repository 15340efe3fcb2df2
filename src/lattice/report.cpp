// Stage "report": the job's report and fill's as JSON (nlohmann, kept private) and as a human
// summary.
#include "tpmsfill/report.hpp"

#include <sys/resource.h>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <nlohmann/json.hpp>

#include "core/format_numbers.hpp"
#include "lattice/report_text.hpp"

namespace tpmsfill {
namespace {

using json = nlohmann::ordered_json;

json point(Vec3 p) {
  return json::array({p.x, p.y, p.z});
}

json sizes(const SizeDistribution& d) {
  json smallest = json::array();
  for (const SizeSample& s : d.smallest)
    smallest.push_back({{"diameter", s.diameter}, {"at", point(s.at)}});
  return {
      {"samples", d.samples}, {"min", d.min},        {"mean", d.mean}, {"max", d.max},
      {"p10", d.p10},         {"p50", d.p50},        {"p90", d.p90},   {"bin_edges", d.bin_edges},
      {"counts", d.counts},   {"smallest", smallest}};
}

// The printability check: the limits and how many of the measured samples (`m`, null: none
// taken) fell below them; null without limits.
json printability(const JobReport& r, const LatticeMeasures* m) {
  if (r.min_wall <= 0 && r.min_pore <= 0) return nullptr;
  const auto limit = [](double v) { return v > 0 ? json(v) : json(nullptr); };
  const auto below = [&](const SizeDistribution* d, double v) {
    if (!d || v <= 0) return json(nullptr);
    return json{{"inside", d->below_limit}, {"at_surface", d->below_limit_at_surface}};
  };
  return {{"min_wall", limit(r.min_wall)},
          {"min_pore", limit(r.min_pore)},
          {"walls_below", below(m ? &m->wall : nullptr, r.min_wall)},
          {"pores_below", below(m ? &m->pore : nullptr, r.min_pore)}};
}

using detail::format;

std::string inside_summary(const JobReport& r) {
  if (r.inside_rule != "winding") return "parity of ray crossings";
  const CleanReport& c = r.clean;
  std::string s = r.cleaned() ? "winding number"
                              : "winding number (signed crossings; input needed no cleaning)";
  std::string what;
  auto add = [&](std::uint64_t n, const char* text) {
    if (n) what += (what.empty() ? "" : ", ") + format(text, static_cast<double>(n));
  };
  add(c.holes, "%.0f hole(s) capped");
  add(c.flipped_triangles, "%.0f triangle(s) flipped");
  add(c.reversed_pieces, "%.0f piece(s) turned outward");
  add(c.repeated_corner_triangles + c.duplicate_triangles + c.cancelled_triangles,
      "%.0f degenerate or duplicate triangle(s) dropped");
  add(r.overlap_rows, "shells overlap along %.0f row(s)");
  if (!what.empty()) s += " (" + what + ")";
  s += r.parity_disagreements ? format("; parity would differ at %.0f node(s)",
                                       static_cast<double>(r.parity_disagreements))
                              : std::string("; agrees with parity at every node");
  return s;
}

}  // namespace

double peak_memory_mb() {
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  return static_cast<double>(usage.ru_maxrss) / 1024.0;
}

double JobReport::total_seconds() const {
  double s = 0;
  for (const StageTime& t : stages) s += t.seconds;
  return s;
}

namespace {

json nullable(const std::string& s) {
  return s.empty() ? json(nullptr) : json(s);
}

json islands(const std::vector<RemovedIsland>& list) {
  json a = json::array();
  for (const RemovedIsland& i : list)
    a.push_back(
        {{"volume", i.volume}, {"bbox", {{"min", point(i.bbox.min)}, {"max", point(i.bbox.max)}}}});
  return a;
}

}  // namespace

namespace detail {

json job_json(const JobReport& r) {
  json stages = json::array();
  for (const StageTime& t : r.stages)
    stages.push_back(
        {{"name", t.name}, {"seconds", t.seconds}, {"peak_memory_mb", t.peak_memory_mb}});
  return {
      {"warnings", r.warnings},
      {"provenance",
       {{"input", nullable(r.input_path)},
        {"input_sha256", nullable(r.input_sha256)},
        {"command_line", nullable(r.command_line)},
        {"version", nullable(r.version)}}},
      {"input",
       {{"units", r.units},
        {"scale", r.scale},
        {"mm_per_unit", r.mm_per_unit},
        {"triangles", r.input_triangles},
        {"bbox", r.input_bbox.empty()
                     ? json(nullptr)
                     : json{{"min", point(r.input_bbox.min)}, {"max", point(r.input_bbox.max)}}}}},
      {"lattice",
       {{"type", r.design},
        {"cell", point(r.cell)},
        {"rotation_degrees", point(r.rotation_degrees)},
        {"grading", nullable(r.grading)},
        {"level", r.level},
        {"thickness", r.thickness},
        {"level_unit", r.level_unit},
        {"porosity_target", r.porosity_target ? json(*r.porosity_target) : json(nullptr)},
        {"skin", r.skin}}},
      {"grid",
       {{"origin", point(r.grid.origin)},
        {"voxel", r.grid.spacing},
        {"dims", r.grid.dims},
        {"samples", r.samples}}},
      {"band_nodes", r.band_nodes},
      {"distance_queries", r.distance_queries},
      {"rays", r.rows},
      {"crossings", r.crossings},
      {"odd_rays", r.odd_rows},
      {"inside",
       {{"rule", r.inside_rule},
        {"cleaned", r.cleaned()},
        {"merged_points", r.clean.merged_points},
        {"repeated_corner_triangles", r.clean.repeated_corner_triangles},
        {"duplicate_triangles", r.clean.duplicate_triangles},
        {"cancelled_triangles", r.clean.cancelled_triangles},
        {"pieces", r.clean.pieces},
        {"flipped_triangles", r.clean.flipped_triangles},
        {"reversed_pieces", r.clean.reversed_pieces},
        {"nested_pieces", r.clean.nested_pieces},
        {"border_edges", r.clean.border_edges},
        {"holes", r.clean.holes},
        {"cap_triangles", r.clean.cap_triangles},
        {"overlap_rows", r.overlap_rows},
        {"parity_disagreements", r.parity_disagreements},
        {"cap_evaluations", r.cap_evaluations}}},
      {"estimated_memory_bytes", r.estimated_memory_bytes},
      {"ranks", r.ranks},
      {"model_volume", r.model_volume},
      {"unclipped_porosity", r.unclipped_porosity},
      {"printability", printability(r, nullptr)},
      {"stages", stages},
      {"total_seconds", r.total_seconds()},
      {"peak_memory_mb", peak_memory_mb()},
      {"recipe", r.recipe.empty() ? json(nullptr) : json::parse(r.recipe)},
  };
}

}  // namespace detail

std::string to_json(const FillReport& r) {
  const MeshValidity& v = r.validation;
  // The mesh's figures, each after the job's key it follows in the report (docs/cli.md).
  const std::pair<const char*, json> mesh[] = {
      {"distance_queries", {{"full_field", r.full_field}}},
      {"estimated_memory_bytes",
       {{"slab_planes", r.slab_planes ? json(r.slab_planes) : json(nullptr)}}},
      {"ranks",
       {{"output",
         {{"vertices", r.vertices()},
          {"triangles", r.triangles()},
          {"components", r.components()},
          {"surface_area", r.surface_area()}}},
        {"lattice_volume", r.lattice_volume()}}},
      {"model_volume", {{"porosity", r.porosity()}}},
      {"unclipped_porosity",
       {{"specific_surface", r.specific_surface()},
        {"surface_density", r.surface_density()},
        {"islands_removed", r.islands_removed},
        {"islands_volume", r.islands_volume},
        {"largest_islands", islands(r.largest_islands)},
        {"measures", !r.measures
                         ? json(nullptr)
                         : json{{"pore_diameter", sizes(r.measures->pore)},
                                {"wall_thickness", sizes(r.measures->wall)},
                                {"void_components", r.measures->void_components},
                                {"labyrinths", r.measures->labyrinths},
                                {"largest_void_fraction", r.measures->largest_void_fraction}}}}},
      {"printability",
       {{"cavities", r.cavities},
        {"cavities_volume", r.cavities_volume},
        {"validation",
         {{"closed", v.closed()},
          {"manifold", v.manifold()},
          {"border_edges", v.border_edges},
          {"non_manifold_edges", v.non_manifold_edges},
          {"non_manifold_vertices", v.non_manifold_vertices},
          {"inconsistent_edges", v.inconsistent_edges},
          {"degenerate_triangles", v.degenerate_triangles},
          {"duplicate_points", v.duplicate_points},
          {"self_intersecting_pairs",
           v.self_intersecting_pairs ? json(*v.self_intersecting_pairs) : json(nullptr)},
          {"validated_by", v.validated_by == ValidatedBy::Construction ? "construction" : "search"},
          {"self_intersection_search", !v.self_intersecting_pairs ? json(nullptr)
                                       : v.validated_by == ValidatedBy::Construction
                                           ? json("construction")
                                       : v.searched_by_cells ? json("cells")
                                                             : json("general")},
          {"outward", v.outward == true}}}}},
  };
  const json job = detail::job_json(r);
  json j = {{"valid", v.valid()}, {"problems", v.problems()}};
  for (const auto& [key, value] : job.items()) {
    j[key] = value;
    for (const auto& [after, figures] : mesh)
      if (key == after)
        for (const auto& [name, figure] : figures.items()) j[name] = figure;
  }
  j["printability"] = printability(r, r.measures ? &*r.measures : nullptr);
  return j.dump(2) + "\n";
}

namespace detail {

std::string settings_text(const JobReport& r) {
  std::string s;
  s += "lattice      " + r.design + format(", cell %g x %g x %g mm", r.cell.x, r.cell.y, r.cell.z);
  // A porous structure's porosity moves its thresholds, shown in its label, not a level.
  const bool structure = r.design.starts_with("scanned-field");
  if (r.porosity_target && structure)
    s += format(", for porosity %.4g %%", 100 * *r.porosity_target);
  else if (r.porosity_target)
    s += format(r.sheet ? ", thickness %.4g mm for porosity %.4g %%"
                        : ", level %.4g mm for porosity %.4g %%",
                r.sheet ? r.thickness : r.level, 100 * *r.porosity_target);
  if (r.skin > 0) s += format(", skin %g mm", r.skin);
  const Vec3 rot = r.rotation_degrees;
  if (rot.x != 0 || rot.y != 0 || rot.z != 0)
    s += format(", rotated %.4g %.4g %.4g deg", rot.x, rot.y, rot.z);
  s += "\n";
  if (!r.grading.empty()) s += "grading      " + r.grading + "\n";
  if (r.mm_per_unit != 1)
    s += "input        read as " + r.units +
         (r.scale != 1 ? format(" scaled by %g", r.scale) : std::string()) +
         format(": %g mm per unit\n", r.mm_per_unit);
  return s;
}

std::string closing_text(const JobReport& r) {
  std::string s;
  for (const std::string& w : r.warnings) s += "warning      " + w + "\n";
  // The names' column is as wide as the longest name (at least 14).
  std::size_t width = 14;
  for (const StageTime& t : r.stages) width = std::max(width, t.name.size());
  auto padded = [&](const std::string& name) {
    return "  " + name + std::string(width - name.size(), ' ');
  };
  s += "stage" + std::string(width - 2, ' ') + "seconds   peak MB\n";
  for (const StageTime& t : r.stages)
    s += padded(t.name) + format(" %8.3f  %8.0f\n", t.seconds, t.peak_memory_mb);
  s += padded("total") + format(" %8.3f\n", r.total_seconds());
  return s;
}

std::string inside_text(const JobReport& r) {
  return inside_summary(r);
}

}  // namespace detail

std::string to_text(const FillReport& r) {
  const MeshValidity& v = r.validation;
  std::string s = detail::settings_text(r);
  s += format("grid         %.0f x %.0f x %.0f", r.grid.dims[0], r.grid.dims[1], r.grid.dims[2]) +
       format(" nodes at %g mm (%.3g samples)\n", r.grid.spacing, static_cast<double>(r.samples));
  s += "inside       " + inside_summary(r) + "\n";
  if (r.slab_planes)
    s += format("memory       slabs of %.0f node planes (the whole grid did not fit the budget)\n",
                r.slab_planes);
  s += format("distances    %.3g queries", static_cast<double>(r.distance_queries)) +
       (r.full_field
            ? std::string(" (full field)\n")
            : format(" on the band (%.1fx fewer than the full field)\n",
                     static_cast<double>(r.samples) /
                         static_cast<double>(std::max<std::uint64_t>(r.distance_queries, 1))));
  s += format("output       %.0f vertices, %.0f triangles", static_cast<double>(r.vertices()),
              static_cast<double>(r.triangles())) +
       format(", %.0f component(s), area %.1f mm2\n", static_cast<double>(r.components()),
              r.surface_area());
  s +=
      format("volume       lattice %.1f mm3, model %.1f mm3\n", r.lattice_volume(), r.model_volume);
  s += std::isfinite(r.unclipped_porosity)
           ? format("porosity     %.2f %% (unclipped lattice %.2f %%)\n", 100 * r.porosity(),
                    100 * r.unclipped_porosity)
           : format("porosity     %.2f %% (graded)\n", 100 * r.porosity());
  s += format("surface      %.3g mm^-1 per solid volume, %.3g mm^-1 per model volume\n",
              r.specific_surface(), r.surface_density());
  if (r.measures) {
    const LatticeMeasures& m = *r.measures;
    auto line = [&](const char* label, const SizeDistribution& d) {
      if (!d.samples) return std::string(label) + "none measured\n";
      return std::string(label) +
             format("mean %.3g mm (10-90 %%: %.3g-%.3g", d.mean, d.p10, d.p90) +
             format(", max %.3g mm)\n", d.max);
    };
    s += line("pores        diameter ", m.pore);
    s += line("walls        thickness ", m.wall);
    s += format("void         %.0f labyrinth(s)", static_cast<double>(m.labyrinths)) +
         (m.labyrinths == 1   ? std::string(": one connected void")
          : m.labyrinths == 2 ? std::string(": two interwoven voids, as a sheet makes")
                              : std::string()) +
         format(" (%.0f piece(s) in all)\n", static_cast<double>(m.void_components));
    for (const auto& [label, limit, d] :
         {std::tuple{"printable    walls >= ", r.min_wall, &m.wall},
          std::tuple{"printable    pores >= ", r.min_pore, &m.pore}})
      if (limit > 0)
        s += std::string(label) +
             format("%g mm: %.0f sample(s) below inside the part, %.0f at its surface\n", limit,
                    static_cast<double>(d->below_limit),
                    static_cast<double>(d->below_limit_at_surface));
  }
  if (r.islands_removed)
    s += format("islands      %.0f removed (%.3g mm3)\n", static_cast<double>(r.islands_removed),
                r.islands_volume);
  s += std::string("validation   ") +
       (v.valid() ? "closed 2-manifold, outward, no degenerate faces" : "FAILED") +
       (v.self_intersecting_pairs
            ? (*v.self_intersecting_pairs == 0 ? ", no self-intersections" : "")
            : ", self-intersections not searched") +
       "\n";
  for (const std::string& p : v.problems()) s += "  problem: " + p + "\n";
  s += detail::closing_text(r);
  return s;
}

MeshMetadata lattice_metadata(const FillReport& r, MeshMetadata given) {
  if (given.description.empty()) {
    const MeshValidity& v = r.validation;
    given.description =
        "TPMS lattice (" + r.design +
        format(", cell %g x %g x %g mm", r.cell.x, r.cell.y, r.cell.z) +
        (r.grading.empty() ? std::string() : ", " + r.grading) +
        (r.skin > 0 ? format(", skin %g mm", r.skin) : std::string()) + ") made by tpmsfill" +
        format(": porosity %.2f %%", 100 * r.porosity()) +
        format(", %.0f triangles, %.1f mm3 of solid", static_cast<double>(r.triangles()),
               r.lattice_volume()) +
        (v.valid() ? std::string("; validated as a closed, outward 2-manifold without degenerate "
                                 "faces") +
                         (v.self_intersecting_pairs && *v.self_intersecting_pairs == 0
                              ? " or self-intersections"
                              : "")
                   : std::string("; NOT valid")) +
        ".";
  }
  // Without the seconds and the peak memory, which differ from run to run: the same job
  // writes the same bytes (docs/formats.md).
  json report = json::parse(to_json(r));
  report.erase("total_seconds");
  report.erase("peak_memory_mb");
  for (json& stage : report["stages"]) {
    stage.erase("seconds");
    stage.erase("peak_memory_mb");
  }
  given.attachments.emplace_back("Metadata/tpmsfill-report.json", report.dump(2) + "\n");
  return given;
}

}  // namespace tpmsfill
