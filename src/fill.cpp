// The whole pipeline, stage by stage, timing each into the report.
#include "tpmsfill/fill.hpp"

#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <limits>
#include <optional>
#include <string>
#include <utility>

#include "detail/float_coordinates.hpp"
#include "detail/index_limits.hpp"
#include "detail/job_progress.hpp"
#include "detail/job_settings.hpp"
#include "tpmsfill/classify.hpp"
#include "tpmsfill/clean.hpp"
#include "tpmsfill/components.hpp"
#include "tpmsfill/compose.hpp"
#include "tpmsfill/distance.hpp"
#include "tpmsfill/error.hpp"
#include "tpmsfill/marching_cubes.hpp"
#include "tpmsfill/measure.hpp"
#include "tpmsfill/porous.hpp"
#include "tpmsfill/review.hpp"
#include "tpmsfill/spatial.hpp"
#include "tpmsfill/validate.hpp"

namespace tpmsfill {
namespace {

// Bytes per grid node at the peak: occupancy, the band stage's three temporary masks, and the
// composed field (plus the full distance field with --full-field).
constexpr double kBytesPerNode = 8.0;
constexpr double kBytesPerFullFieldNode = 4.0;
// Bytes per input triangle: the soup (three points, STL-style), the tree's copy and nodes.
constexpr double kBytesPerInputTriangle = 260.0;
// Bytes per output triangle: indices, half a vertex, validation's edge table and buckets.
constexpr double kBytesPerOutputTriangle = 110.0;

double estimate_bytes(const Box3& bounds, std::uint64_t triangles, const FillOptions& o) {
  const double nodes = static_cast<double>(grid_node_count(bounds, o.grid));
  const Vec3 size = bounds.size();
  const double a = o.grid.voxel_size;
  const double cell = std::fmin(o.design.cell.x, std::fmin(o.design.cell.y, o.design.cell.z));
  // Lattice area ≈ 3.1/T per unit volume (gyroid; the others are close), the clipped
  // boundary at most the box's surface; marching cubes makes about 2.6 triangles per a².
  const double area = 3.1 / cell * size.x * size.y * size.z +
                      2.0 * (size.x * size.y + size.y * size.z + size.z * size.x);
  const double out_triangles = 2.6 * area / (a * a);
  return nodes * (kBytesPerNode + (o.full_field ? kBytesPerFullFieldNode : 0.0)) +
         static_cast<double>(triangles) * kBytesPerInputTriangle +
         out_triangles * kBytesPerOutputTriangle + 64.0 * 1024 * 1024;
}

std::string gigabytes(double bytes) {
  char s[32];
  std::snprintf(s, sizeof s, "%.2f GB", bytes / 1e9);
  return s;
}

// Bytes as a count, saturating where a double estimate leaves the 64-bit range.
std::uint64_t saturated_bytes(double bytes) {
  return bytes >= 1.8e19 ? std::numeric_limits<std::uint64_t>::max()
                         : static_cast<std::uint64_t>(bytes);
}

// The job's estimated bytes; refuses a job over its budget, naming a voxel size that fits.
std::uint64_t require_budget(const Box3& bounds, std::uint64_t triangles, const FillOptions& o) {
  const double budget =
      static_cast<double>(o.memory_budget ? o.memory_budget : default_memory_budget());
  const double need = estimate_bytes(bounds, triangles, o);
  if (need <= budget) return saturated_bytes(need);
  // The estimate falls as the voxel grows: bisect for the smallest voxel size that fits.
  FillOptions trial = o;
  double lo = o.grid.voxel_size, hi = o.grid.voxel_size;
  do {
    hi *= 2;
    trial.grid.voxel_size = hi;
  } while (estimate_bytes(bounds, triangles, trial) > budget && hi < 1e12);
  for (int it = 0; it < 60; ++it) {
    trial.grid.voxel_size = 0.5 * (lo + hi);
    (estimate_bytes(bounds, triangles, trial) > budget ? lo : hi) = trial.grid.voxel_size;
  }
  char fit[64];
  std::snprintf(fit, sizeof fit, "%.4g mm", hi * 1.0001);
  const bool input_alone = static_cast<double>(triangles) * kBytesPerInputTriangle > budget;
  throw ResourceError("the job needs about " + gigabytes(need) + " but the memory budget is " +
                      gigabytes(budget) +
                      (input_alone ? "; the input alone exceeds it"
                                   : "; a voxel size of " + std::string(fit) + " or more fits"));
}

// Times each stage into the report and announces its start and end to the job's progress
// (which checks for cancelling at both, also for stages that report nothing themselves).
class StageClock {
 public:
  StageClock(FillReport& report, detail::JobProgress& progress)
      : report_(report), progress_(progress) {}
  template <class F>
  auto operator()(const char* name, F&& work) {
    progress_.begin_stage(name);
    const auto t0 = std::chrono::steady_clock::now();
    if constexpr (std::is_void_v<decltype(work())>) {
      work();
      record(name, t0);
      progress_.end_stage();
    } else {
      auto result = work();
      record(name, t0);
      progress_.end_stage();
      return result;
    }
  }

 private:
  void record(const char* name, std::chrono::steady_clock::time_point t0) {
    const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    report_.stages.push_back({name, s, peak_memory_mb()});
  }
  FillReport& report_;
  detail::JobProgress& progress_;
};

// The stages fill() will run, in order, with rough shares of the time: per cent of a job's,
// the femur's and the tube's stage tables averaged (docs/benchmarks.md §4; measure and the full
// field from the femur's). The auto inside rule plans the clean and the second classification
// it may need; they are credited when skipped, so the overall fraction does not go back.
std::vector<detail::PlannedStage> plan_stages(const FillOptions& o) {
  std::vector<detail::PlannedStage> plan{{"review", 0.5}};
  const InsideRule rule = o.inside.value_or(InsideRule::Winding);
  if (rule == InsideRule::Parity || !o.inside)
    plan.insert(plan.end(), {{"spatial", 10}, {"classify", 5}});
  if (rule == InsideRule::Winding)
    plan.insert(plan.end(), {{"clean", 5}, {"spatial", 10}, {"classify", 5}});
  for (const Grading& g : o.design.grading)
    if (g.ramp.shape == RampShape::Depth) {
      plan.push_back({"depth", 5});
      break;
    }
  if (!o.full_field) plan.push_back({"band", 8});
  plan.insert(plan.end(), {{"distance", o.full_field ? 200.0 : 16.0},
                           {"compose", 3},
                           {"marching cubes", 7},
                           {"islands", 6}});
  if (o.measure) plan.push_back({"measure", 35});
  plan.push_back({"validate", 46});
  return plan;
}

// Islands: lattice components that are not the largest piece within their part of the model
// (a 26-connected region of inside nodes). A component is located by a corner with φ < 0 of
// the cell holding its first triangle (φ < 0 implies the node is inside): `solid_node` gives
// that node's index, or none.
std::vector<std::uint64_t> solid_nodes(const TriangleSoup& mesh, const Components& comps,
                                       const Field& phi) {
  const Grid& g = phi.grid;
  std::vector<std::uint64_t> node(comps.info.size(), UINT64_MAX);
  for (std::size_t c = 0; c < comps.info.size(); ++c) {
    const Triangle& t = mesh.triangles[comps.info[c].first_triangle];
    const Vec3 centroid = (1.0 / 3.0) * (mesh.points[t[0]] + mesh.points[t[1]] + mesh.points[t[2]]);
    int cell[3];
    for (int axis = 0; axis < 3; ++axis)
      cell[axis] =
          std::clamp(static_cast<int>(std::floor((centroid[axis] - g.origin[axis]) / g.spacing)), 0,
                     g.dims[axis] - 2);
    for (int corner = 0; corner < 8 && node[c] == UINT64_MAX; ++corner) {
      const int i = cell[0] + (corner & 1), j = cell[1] + (corner >> 1 & 1),
                k = cell[2] + (corner >> 2 & 1);
      if (phi.values[g.index(i, j, k)] < 0) node[c] = g.index(i, j, k);
    }
  }
  return node;
}

std::vector<bool> main_bodies(const TriangleSoup& mesh, const Components& comps, const Field& phi,
                              const Regions& regions) {
  const Grid& g = phi.grid;
  const std::uint32_t none = detail::kNoIndex;
  const std::vector<std::uint64_t> node = solid_nodes(mesh, comps, phi);
  auto region_of = [&](const Regions& r, std::size_t c) {
    if (node[c] == UINT64_MAX) return none;
    const std::uint64_t n = node[c], nx = g.dims[0], ny = g.dims[1];
    return r.region_at(static_cast<int>(n % nx), static_cast<int>(n / nx % ny),
                       static_cast<int>(n / (nx * ny)));
  };
  std::vector<std::uint32_t> part(comps.info.size(), none);
  for (std::size_t c = 0; c < comps.info.size(); ++c) part[c] = region_of(regions, c);
  std::vector<std::size_t> largest(regions.count, std::numeric_limits<std::size_t>::max());
  for (std::size_t c = 0; c < comps.info.size(); ++c) {
    if (part[c] == none || comps.info[c].volume < 0) continue;
    std::size_t& best = largest[part[c]];
    if (best == std::numeric_limits<std::size_t>::max() ||
        std::fabs(comps.info[c].volume) > std::fabs(comps.info[best].volume))
      best = c;
  }
  std::vector<bool> keep(comps.info.size(), false);
  bool cavity = false, removed = false;
  for (std::size_t c = 0; c < comps.info.size(); ++c) {
    cavity = cavity || comps.info[c].volume < 0;
    keep[c] = part[c] == none || largest[part[c]] == c || comps.info[c].volume < 0;
    removed = removed || !keep[c];
  }
  if (!cavity || !removed) return keep;
  // A component of negative volume bounds a cavity (the pore inside a shell, a void a skin
  // encloses): it goes with the solid around it, which the shell's outer surface bounds too.
  // It stays only if a kept positive component bounds the same solid (6-connected φ < 0).
  Mask solid{g, std::vector<std::uint8_t>(g.node_count())};
  for (std::size_t n = 0; n < solid.values.size(); ++n) solid.values[n] = phi.values[n] < 0;
  const Regions pieces = label_regions(solid, Connectivity::Face);
  std::vector<bool> kept_piece(pieces.count, false);
  for (std::size_t c = 0; c < comps.info.size(); ++c)
    if (const std::uint32_t p = region_of(pieces, c);
        keep[c] && comps.info[c].volume > 0 && p != none)
      kept_piece[p] = true;
  for (std::size_t c = 0; c < comps.info.size(); ++c)
    if (const std::uint32_t p = region_of(pieces, c); comps.info[c].volume < 0 && p != none)
      keep[c] = kept_piece[p];
  return keep;
}

// The job's state between stages: what later stages need of earlier ones.
struct Job {
  const TriangleSoup& model;
  const FillOptions& options;
  FillResult& result;
  FillReport& report;
  detail::JobProgress job_progress;
  Progress* progress;  ///< what the stages report to: job_progress, or null without a caller's
  StageClock stage;
  Grid grid;
  Occupancy occupancy;
  std::optional<MeshIndex> tree;
  std::optional<Field> depth;
  Field phi;
  TriangleSoup mesh;

  Job(const TriangleSoup& m, const FillOptions& o, FillResult& r)
      : model(m),
        options(o),
        result(r),
        report(r.report),
        job_progress(o.progress, plan_stages(o)),
        progress(job_progress.get()),
        stage(r.report, job_progress) {}
};

// Settings into the report, the design resolved against the model's box.
void resolve(Job& job) {
  const FillOptions& o = job.options;
  FillReport& r = job.report;
  job.result.resolved = o;
  const LatticeDesign& d = job.result.resolved.design = detail::describe_job(job.model, o, r);
  job.grid = make_grid(r.input_bbox, o.grid);  // validates the options first
  // What cannot come out as asked is refused here, before the work; doubts are warnings.
  std::vector<std::string> doubts = job.stage("review", [&] {
    return review_design(d, r.input_bbox,
                         {.voxel = job.grid.spacing, .input_units = o.units.units});
  });
  for (std::string& w : doubts) r.warnings.push_back(std::move(w));
  r.estimated_memory_bytes = require_budget(r.input_bbox, job.model.triangles.size(), o);
  r.grid = job.grid;
  r.samples = job.grid.node_count();
}

// Inside/outside. Auto first tries the input as it is: along rows where it is closed and
// outward, the signed crossings are the winding number exactly; it cleans and caps only when
// some row says otherwise.
void classify(Job& job) {
  const FillOptions& o = job.options;
  FillReport& r = job.report;
  const InsideRule rule = o.inside.value_or(InsideRule::Winding);
  r.inside_rule = inside_name(rule);
  auto run = [&] {
    job.occupancy = job.stage("classify", [&] {
      return classify_grid(*job.tree, job.grid, {.rule = rule, .progress = job.progress});
    });
  };
  if (rule == InsideRule::Parity || !o.inside) {
    job.stage("spatial", [&] { job.tree.emplace(build_index(job.model)); });
    run();
  }
  if (rule == InsideRule::Winding && (o.inside || job.occupancy.unbalanced_rows > 0)) {
    job.tree.reset();
    CleanResult cleaned =
        job.stage("clean", [&] { return clean_soup(job.model, {.progress = job.progress}); });
    r.clean = cleaned.report;
    if (cleaned.soup.triangles.empty())
      throw InputError("the mesh encloses no volume: no triangle has three distinct corners");
    job.stage("spatial",
              [&] { job.tree.emplace(build_index(cleaned.soup, {.hole_caps = &cleaned.caps})); });
    run();
  }
  const Occupancy& occ = job.occupancy;
  r.rows = occ.rows;
  r.crossings = occ.crossings;
  r.odd_rows = occ.odd_rows;
  r.overlap_rows = occ.overlap_rows;
  r.parity_disagreements = occ.parity_disagreements;
  r.cap_evaluations = occ.cap_evaluations;
  r.model_volume = occ.volume;
  if (rule == InsideRule::Parity && occ.odd_rows)
    r.warnings.push_back(std::to_string(occ.odd_rows) +
                         " grid rows crossed the surface an odd number of times: the input is "
                         "not closed, so inside and outside may be wrong near its holes "
                         "(--inside winding handles holes)");
  if (std::find(occ.inside.values.begin(), occ.inside.values.end(), 1) == occ.inside.values.end())
    throw InputError(
        "the mesh encloses no volume: no grid node is inside it (an open sheet, or a shell "
        "thinner than the voxel size)");
}

// φ = max(φ_model, φ_L): the model's distance on the band (or everywhere with --full-field),
// the design's field where the model does not decide.
void compose(Job& job) {
  const FillOptions& o = job.options;
  FillReport& r = job.report;
  const Mask& inside = job.occupancy.inside;
  // Depth ramps grade by the distance below the surface: the occupancy's distance transform.
  const LatticeDesign& design = job.result.resolved.design;
  for (const Grading& g : design.grading)
    if (g.ramp.shape == RampShape::Depth && !job.depth)
      job.depth = job.stage("depth", [&] { return distance_transform(inside); });
  const FieldSource lattice = design_source(design, job.depth ? &*job.depth : nullptr);
  const ComposeOptions compose_options = detail::compose_options(o, job.progress);
  const DistanceOptions distance_options{.progress = job.progress};
  if (!o.full_field) {
    const BandOptions band_options{detail::band_width(o, job.grid.spacing)};
    const Band band = job.stage("band", [&] { return band_voxels(inside, band_options); });
    r.band_nodes = band.nodes.size();
    r.distance_queries = band.nodes.size();
    const std::vector<float> d = job.stage(
        "distance", [&] { return band_distances(*job.tree, inside, band, distance_options); });
    job.phi = job.stage("compose",
                        [&] { return compose_field(inside, band, d, lattice, compose_options); });
  } else {
    const Field d = job.stage(
        "distance", [&] { return signed_distance_field(*job.tree, inside, distance_options); });
    r.distance_queries = r.samples;
    job.phi = job.stage("compose", [&] { return compose_field(d, lattice, compose_options); });
  }
  job.tree.reset();  // the tree is no longer needed: give its memory back
}

// Sealed voids hold unfused powder or resin: say how many, whatever sealed them. Voids
// smaller than a voxel are marching cubes' specks between nearly touching surfaces, not pores.
void warn_cavities(const FillOptions& o, const Components& comps, const std::vector<bool>& keep,
                   double voxel, FillReport& r) {
  std::uint64_t count = 0;
  double volume = 0;
  for (std::size_t c = 0; c < comps.info.size(); ++c)
    if (keep[c] && -comps.info[c].volume >= voxel * voxel * voxel)
      ++count, volume -= comps.info[c].volume;
  if (!count) return;
  char figures[96];
  std::snprintf(figures, sizeof figures, "%llu void(s) (%.3g mm3)",
                static_cast<unsigned long long>(count), volume);
  const std::string drain = ", where unfused powder or resin cannot drain";
  if (o.skin > 0 && !o.skin_windows)
    r.warnings.push_back("the closed skin seals " + std::string(figures) + " in" + drain +
                         " (--skin-windows opens the skin at the pores)");
  else if (o.skin > 0)
    r.warnings.push_back("the skin windows left " + std::string(figures) + " sealed" + drain +
                         " (pores that never reach the skin; a thinner --skin or a larger --cell "
                         "opens more)");
  else
    r.warnings.push_back("the lattice encloses " + std::string(figures) + drain);
}

// Islands that are whole features: removal of more than 5 % of the lattice, or of any piece
// larger than a cell, is not the tidying it is meant to be.
void warn_islands(const FillOptions& o, double lattice_before, FillReport& r) {
  const double fraction = lattice_before > 0 ? r.islands_volume / lattice_before : 0;
  const Vec3 c = r.cell;
  const double largest = r.largest_islands.empty() ? 0 : r.largest_islands.front().volume;
  if (fraction <= 0.05 && largest <= c.x * c.y * c.z) return;
  const Vec3 s = r.largest_islands.front().bbox.size();
  char text[320];
  std::snprintf(text, sizeof text,
                "removing %llu island(s) took %.3g mm3, %.1f %% of the lattice (the largest "
                "%.3g mm3, %.3g x %.3g x %.3g mm)",
                static_cast<unsigned long long>(r.islands_removed), r.islands_volume,
                100 * fraction, largest, s.x, s.y, s.z);
  // Over half: the lattice itself falls apart (a level near its limit); else the islands
  // are parts of the model too thin for the lattice to join.
  const std::string apart =
      o.design.structure
          ? ": the structure falls apart into pieces at these thresholds; widen them (a lower "
            "--porosity) or --keep-islands keeps them"
          : ": the lattice falls apart into pieces at this level or thickness; move it towards "
            "0 (or --porosity nearer 0.5)";
  if (o.design.structure && fraction <= 0.5) {
    r.warnings.push_back(std::string(text) +
                         ": they are pieces of the structure that touch no larger piece "
                         "within the model; --keep-islands keeps them");
    return;
  }
  r.warnings.push_back(
      std::string(text) +
      (fraction > 0.5 ? apart
                      : std::string(": they are features of the model too thin for the lattice "
                                    "to join; a smaller --cell") +
                            (o.skin > 0 ? "" : ", a --skin") + " or --keep-islands keeps them"));
}

// Cavities are counted (a closed skin seals them in); islands, the pieces that are not the
// main body of their part of the model, are removed unless kept, the largest listed.
void remove_islands(Job& job) {
  const FillOptions& o = job.options;
  FillReport& r = job.report;
  const Components comps = mesh_components(job.mesh);
  double lattice_before = 0;
  for (const auto& c : comps.info) lattice_before += c.volume;
  std::vector<bool> keep(comps.info.size(), true);
  if (!o.keep_islands && comps.info.size() >= 2)
    keep = main_bodies(job.mesh, comps, job.phi, label_regions(job.occupancy.inside));
  for (std::size_t c = 0; c < keep.size(); ++c)
    if (keep[c] && comps.info[c].volume < 0)
      ++r.cavities, r.cavities_volume -= comps.info[c].volume;
  warn_cavities(o, comps, keep, job.grid.spacing, r);
  // An island is a removed piece of positive volume; the cavities it enclosed go with it, so
  // the volume removed is the signed sum.
  std::vector<RemovedIsland> removed(comps.info.size());
  for (std::size_t t = 0; t < job.mesh.triangles.size(); ++t)
    if (const std::uint32_t c = comps.triangle_component[t]; !keep[c])
      for (std::uint32_t v : job.mesh.triangles[t]) removed[c].bbox.extend(job.mesh.points[v]);
  for (std::size_t c = 0; c < keep.size(); ++c)
    if (!keep[c]) {
      r.islands_volume += comps.info[c].volume;
      if (comps.info[c].volume < 0) continue;
      ++r.islands_removed;
      removed[c].volume = comps.info[c].volume;
      r.largest_islands.push_back(removed[c]);
    }
  // Largest first; equal volumes keep component order, so the list is deterministic.
  std::stable_sort(
      r.largest_islands.begin(), r.largest_islands.end(),
      [](const RemovedIsland& a, const RemovedIsland& b) { return a.volume > b.volume; });
  if (r.largest_islands.size() > 10) r.largest_islands.resize(10);
  if (std::find(keep.begin(), keep.end(), false) != keep.end()) {
    job.mesh = keep_components(job.mesh, comps, keep);
    if (r.islands_removed) warn_islands(o, lattice_before, r);
  }
}

// Nothing is returned that failed validation.
void validate(Job& job) {
  const FillOptions& o = job.options;
  FillReport& r = job.report;
  if (job.mesh.triangles.empty())
    throw InputError(
        "the lattice is empty: no part of the model is thicker than the lattice's "
        "struts at this voxel size (try a smaller --voxel or a larger --cell)");
  if (o.float_coordinates) detail::round_to_float(job.mesh);
  r.validation = job.stage("validate", [&] {
    return validate_mesh(job.mesh, {.self_intersections = o.check_self_intersections,
                                    .cell_grid = job.grid,
                                    .progress = job.progress});
  });
  if (!r.validation.valid()) {
    std::string why;
    for (const std::string& p : r.validation.problems()) why += (why.empty() ? "" : "; ") + p;
    throw ValidationError("the lattice failed validation, nothing was written: " + why);
  }
}

// A structure's porosity is solved over its whole unit cube; the part sees only what the
// model covers of it, which may be mostly void or mostly solid. Say so with the numbers.
void warn_structure_porosity(const LatticeDesign& d, FillReport& r) {
  if (!d.structure || !r.porosity_target) return;
  const double asked = *r.porosity_target, got = r.porosity();
  if (std::fabs(got - asked) <= 0.05) return;
  char text[400];
  std::snprintf(text, sizeof text,
                "the part's porosity is %.1f %%, not the %.1f %% asked: the structure's porosity "
                "is solved over its whole cube, and the model covers parts of the cube that are "
                "%s; tile it (--cell) or ask for %s",
                100 * got, 100 * asked,
                got > asked ? "more void than the rest" : "more solid than the rest",
                got > asked ? "a lower porosity" : "a higher porosity");
  r.warnings.push_back(text);
}

}  // namespace

namespace detail {

LatticeDesign describe_job(const TriangleSoup& model, const FillOptions& o, FillReport& r) {
  r.units = units_name(o.units.units);
  r.scale = o.units.scale;
  r.mm_per_unit = o.units.factor();
  r.input_triangles = model.triangles.size();
  r.input_bbox = bounding_box(model);
  LatticeDesign d = resolve_design(o.design, r.input_bbox);
  r.design = d.structure ? structure_label(*d.structure)
             : d.custom  ? std::string("custom field")
                         : tpms_label(d);
  for (const Blend& b : d.blends) r.design += " + " + tpms_label(b.tpms);
  for (const Grading& g : d.grading)
    r.grading += (r.grading.empty() ? "" : "; ") + grading_label(g);
  r.rotation_degrees = euler_from_rotation(d.rotation);
  if (!d.structure) r.cell = d.cell;
  r.level = d.level;
  r.thickness = d.thickness;
  r.full_field = o.full_field;
  r.skin = o.skin;
  r.porosity_target = d.porosity;
  r.sheet = d.style == TpmsStyle::Sheet;
  if (d.structure) {  // its "cell" is the unit cube as placed: the model's box or the tile
    const std::array<double, 3> cube = unit_cube_map(*d.structure, r.input_bbox).extent;
    r.unclipped_porosity = 1.0 - porous_solid_share(*d.structure, cube);
    r.cell = {cube[0], cube[1], cube[2]};
  } else if (!d.custom)
    r.unclipped_porosity = 1.0 - tpms_solid_fraction(d);
  return d;
}

int band_width(const FillOptions& o, double spacing) {
  return std::max(o.band.width, skin_band_width(o.skin, spacing));
}

ComposeOptions compose_options(const FillOptions& o, Progress* progress) {
  return {.skin = o.skin, .skin_windows = o.skin_windows, .progress = progress};
}

double depth_reach(const LatticeDesign& design) {
  double reach = 0;
  for (const Grading& g : design.grading)
    if (g.ramp.shape == RampShape::Depth)
      reach = std::fmax(
          reach, std::fmax(std::fabs(g.ramp.from.value_or(0)), std::fabs(g.ramp.to.value_or(0))));
  return reach;
}

}  // namespace detail

std::uint64_t default_memory_budget() {
  const long pages = sysconf(_SC_PHYS_PAGES), page = sysconf(_SC_PAGE_SIZE);
  if (pages <= 0 || page <= 0) return 4ull << 30;
  return static_cast<std::uint64_t>(pages) * static_cast<std::uint64_t>(page) / 2;
}

std::uint64_t estimate_fill_memory(const Box3& bounds, std::uint64_t triangles,
                                   const FillOptions& options) {
  return saturated_bytes(estimate_bytes(bounds, triangles, options));
}

FillResult fill(const TriangleSoup& input, const FillOptions& options) {
  require_valid(options.units);
  require_valid(options.design);
  require_valid(ComposeOptions{.skin = options.skin});  // fail before any work
  // The pipeline works in millimetres; a copy only when the input is in another unit.
  std::optional<TriangleSoup> in_mm;
  if (options.units.factor() != 1) in_mm = to_millimetres(input, options.units);
  const TriangleSoup& model = in_mm ? *in_mm : input;
  FillResult result;
  Job job(model, options, result);
  resolve(job);
  classify(job);
  compose(job);
  job.mesh = job.stage("marching cubes",
                       [&] { return marching_cubes(job.phi, {.progress = job.progress}); });
  job.stage("islands", [&] { remove_islands(job); });
  if (options.measure)
    result.report.measures = job.stage("measure", [&] {
      return measure_lattice(job.phi, job.occupancy.inside, {.progress = job.progress});
    });
  job.phi = Field{};
  job.occupancy = Occupancy{};
  job.depth.reset();
  validate(job);
  warn_structure_porosity(result.resolved.design, result.report);
  job.job_progress.finish();
  result.mesh = std::move(job.mesh);
  return result;
}

}  // namespace tpmsfill
