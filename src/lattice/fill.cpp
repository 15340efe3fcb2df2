// The whole pipeline, stage by stage, timing each into the report.
#include "tpmsfill/fill.hpp"

#include <tbb/global_control.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <functional>
#include <limits>
#include <optional>
#include <string>
#include <tuple>
#include <utility>

#include "core/index_limits.hpp"
#include "core/job_progress.hpp"
#include "core/parallel.hpp"
#include "lattice/field_planes.hpp"
#include "lattice/fill_job.hpp"
#include "lattice/job_settings.hpp"
#include "lattice/review.hpp"
#include "sampling/rounded_grid.hpp"
#include "tpmsfill/error.hpp"
#include "tpmsfill/lattice/compose.hpp"
#include "tpmsfill/lattice/measure.hpp"
#include "tpmsfill/mesh/clean.hpp"
#include "tpmsfill/mesh/components.hpp"
#include "tpmsfill/mesh/validate.hpp"
#include "tpmsfill/sampling/classify.hpp"
#include "tpmsfill/sampling/distance.hpp"
#include "tpmsfill/sampling/marching_cubes.hpp"
#include "tpmsfill/sampling/spatial.hpp"
#include "tpmsfill/scan/porous.hpp"

namespace tpmsfill {
namespace {

using detail::Job;
using detail::StageClock;

// Bytes per grid node at the peak: occupancy, the band stage's three temporary masks, and the
// composed field (plus the full distance field with --full-field).
constexpr double kBytesPerNode = 8.0;
constexpr double kBytesPerFullFieldNode = 4.0;
using detail::kBytesPerInputTriangle;
using detail::kFixedBytes;
// Bytes per output triangle: indices, half a vertex, validation's edge table and buckets
// (the peak of a shark of mechanical holes at 10.4 million triangles is 149 a triangle over
// the fixed share, docs/benchmarks.md §27).
constexpr double kBytesPerOutputTriangle = 160.0;
// Bytes per triangle while the field is held: marching cubes' mesh and the islands' labels and
// components (56 measured).
constexpr double kBytesPerMeshedTriangle = 60.0;

// What the estimates know of the model (mm): its box, triangles, and the volume and area its
// lattice's surface scales with.
struct ModelSize {
  Box3 bounds;
  std::uint64_t triangles = 0;
  double volume = 0;  ///< enclosed, as far as the soup tells; at most the box's
  double area = 0;    ///< of its surface (a scan's overlapping shells count twice: more is safe)
};

// The soup's size. Its signed volume is the enclosed volume for a closed, consistently
// oriented mesh, the same about any reference point. Holes and flipped faces make it depend on
// the point (by the volume of the cones from it over the holes, or twice over the flipped
// faces), so the difference between two references, the box's opposite corners, bounds how far
// it may be off: the volume is taken as the larger of the two plus that difference, at most
// the box. A dragon with two small holes keeps its own volume; a rounded block with 397 of its
// 840 faces flipped is taken as its box (it fills 85 % of it; the quarter of the box assumed
// before left its estimate below its peak), and a closed femur is no longer taken as the
// quarter of its box it does not fill (15 %: its lattice looked 1.6 times larger).
ModelSize model_size(const TriangleSoup& model) {
  ModelSize m{bounding_box(model), model.triangles.size()};
  const Vec3 low = m.bounds.min, high = m.bounds.max;
  double six_v_low = 0, six_v_high = 0, twice_a = 0;
  for (const Triangle& t : model.triangles) {
    const Vec3 a = model.points[t[0]], b = model.points[t[1]], c = model.points[t[2]];
    six_v_low += dot(a - low, cross(b - low, c - low));
    six_v_high += dot(a - high, cross(b - high, c - high));
    twice_a += norm(cross(b - a, c - a));
  }
  if (model.triangles.empty()) return m;
  const Vec3 s = m.bounds.size();
  const double box = s.x * s.y * s.z;
  const double off = std::fabs(six_v_low - six_v_high);
  m.volume = std::fmin((std::fmax(std::fabs(six_v_low), std::fabs(six_v_high)) + off) / 6, box);
  m.area = 0.5 * twice_a;
  return m;
}

// A TPMS's surface area per unit volume times its cell size, at porosities near a half, as
// measured in a 20 mm cube of 2 mm cells (docs/benchmarks.md §27): network, then sheet (two
// walls, a little less than twice the network's).
double area_per_volume(const TpmsOptions& t) {
  static constexpr double kNetwork[] = {3.1, 2.2, 3.8, 3.6, 3.3, 4.8, 6.1, 5.2};
  static constexpr double kSheet[] = {5.5, 4.3, 6.6, 6.2, 6.1, 7.6, 8.3, 8.1};
  const auto type = static_cast<std::size_t>(t.type);
  return (t.style == TpmsStyle::Sheet ? kSheet : kNetwork)[type] /
         std::fmin(t.cell.x, std::fmin(t.cell.y, t.cell.z));
}

// How output_triangles reads: the count to expect (the preflight), or a bound on it (memory).
enum class Count { Expected, Bound };

// The output's area: the lattice's (area_per_volume of the densest layer, blends and cell
// grading included, over the model's volume) plus the model's surface where cut cells meet it
// (about half of it on a thick part, its solid fraction 1 - porosity: 0.15 to 0.64 measured
// over 22 meshes at the gyroid network's 0.5, docs/benchmarks.md §27). Expected: half the
// surface; Bound: all of it, since a shark of mechanical holes at 0.7 of it made 1.10 times
// the count (its thin walls carry more lattice than their volume's share).
double output_area(const ModelSize& m, const FillOptions& o, Count count) {
  double density = area_per_volume(o.design);
  for (const Blend& b : o.design.blends) density = std::fmax(density, area_per_volume(b.tpms));
  // Cells graded smaller than the base cell pack more surface: the smallest counts.
  for (const Grading& g : o.design.grading)
    if (g.what == Graded::Cell && std::fmin(g.ramp.start, g.ramp.end) > 0)
      density *= std::fmax(1.0, o.design.cell.x / std::fmin(g.ramp.start, g.ramp.end));
  return density * m.volume + (count == Count::Bound ? 1.0 : 0.5) * m.area;
}

// Output triangles: the output's area over a², times marching cubes' triangles per a² of
// surface (with its centroid fans 3.3 to 4.6, measured over the eight types, network and sheet,
// a = T/40 to T/5; 4.3 on a dragon at T/5): 4.0 expected, 4.3 for the bound, so the memory
// estimate bounds the peak.
double output_triangles(const ModelSize& m, const FillOptions& o, Count count = Count::Bound) {
  const double a = o.grid.voxel_size;
  return (count == Count::Bound ? 4.3 : 4.0) * output_area(m, o, count) / (a * a);
}

// The peak of a job whose field stages hold `field_bytes`: the input and its tree throughout;
// then the larger of the field stages (with marching cubes' mesh and islands' components,
// kBytesPerMeshedTriangle) and validation (the mesh and its tables, kBytesPerOutputTriangle), since
// the field is gone before validation starts.
double peak_bytes(const ModelSize& m, const FillOptions& o, double field_bytes) {
  const double out = output_triangles(m, o);
  return static_cast<double>(m.triangles) * kBytesPerInputTriangle +
         std::fmax(field_bytes + kBytesPerMeshedTriangle * out, kBytesPerOutputTriangle * out) +
         kFixedBytes;
}

double estimate_bytes(const ModelSize& m, const FillOptions& o) {
  const double nodes = static_cast<double>(grid_node_count(m.bounds, o.grid));
  return peak_bytes(m, o, nodes * (kBytesPerNode + (o.full_field ? kBytesPerFullFieldNode : 0.0)));
}

// Bytes as a count, saturating where a double estimate leaves the 64-bit range.
std::uint64_t saturated_bytes(double bytes) {
  return bytes >= 1.8e19 ? std::numeric_limits<std::uint64_t>::max()
                         : static_cast<std::uint64_t>(bytes);
}

// Streaming's fixed buffers: three records of validation windows, the spill file's and the
// writer's buffers, and the component labels of a heavily fragmented lattice.
constexpr double kStreamBytes = 64e6;

// Bytes the slab path needs with slabs of `planes` node planes: per node of a slab and its
// halo the classification, the band's temporaries (and the depth's distance transform); per
// node of the slab φ and the inside copy; the masks islands need as runs (about two inside
// runs per row, two solid runs per cell along it); the input and the output as the whole
// grid's path.
double slab_bytes(const ModelSize& m, const FillOptions& o, const LatticeDesign& d, int planes,
                  bool streamed) {
  const Box3& bounds = m.bounds;
  const Grid g = make_grid(bounds, o.grid);
  const double plane = static_cast<double>(g.dims[0]) * g.dims[1];
  const double halo = detail::halo_planes(o, d, g.spacing);
  const bool depth = detail::depth_reach(d) > 0;
  const double widened = planes + 2 + 2 * halo;
  const double cell = std::fmin(d.cell.x, std::fmin(d.cell.y, d.cell.z));
  const double runs = static_cast<double>(g.row_count()) * 12.0 *
                      (2 + 2 * bounds.size().x / std::fmax(cell, g.spacing));
  // The runs are copied once more when islands label them.
  const double field =
      plane * (widened * (depth ? 8.0 : 4.0) + (planes + 2) * (o.full_field ? 10.0 : 6.0)) +
      2 * runs;
  if (!streamed) return peak_bytes(m, o, field);
  // Streamed, only one slab's share of the output is held (marching cubes' triangles and
  // points, their labels), beside the three records validation reads and the writer's buffers.
  const double share = std::fmin(1.0, (planes + 2.0) / std::max(g.dims[2], 1));
  return static_cast<double>(m.triangles) * kBytesPerInputTriangle + field +
         48 * share * output_triangles(m, o) + kStreamBytes + kFixedBytes;
}

// The thinnest slabs the plan chooses: thinner ones would spend more on their halos and
// marching cubes' lookahead planes than on their own.
constexpr int kMinSlabPlanes = 4;

// The memory plan: the whole grid at once when it fits the budget (or slabs when asked), else
// slabs as thick as fit; when nothing fits, the refusal to throw after the review, naming a
// voxel size that fits.
detail::MemoryPlan plan_memory(const ModelSize& m, const FillOptions& o, const LatticeDesign& d,
                               bool streamed) {
  const Box3& bounds = m.bounds;
  const std::uint64_t triangles = m.triangles;
  const double budget =
      static_cast<double>(o.memory_budget ? o.memory_budget : default_memory_budget());
  const double whole = estimate_bytes(m, o);
  const int nz = make_grid(bounds, o.grid).dims[2];
  if (o.slab_planes > 0) {
    if (o.measure)
      throw InputError(
          "measures need the whole grid: they cannot be taken in slabs "
          "(FillOptions::slab_planes)");
    const int planes = std::min(o.slab_planes, nz);
    return {planes, saturated_bytes(slab_bytes(m, o, d, planes, streamed)), {}};
  }
  if (whole <= budget) return {0, saturated_bytes(whole), {}};
  // The thickest slabs that fit (bytes grow with the thickness until validation's peak, the
  // output's, dominates): bisect.
  int fit = slab_bytes(m, o, d, kMinSlabPlanes, streamed) <= budget ? kMinSlabPlanes : 0;
  if (fit) {
    int lo = kMinSlabPlanes, hi = nz;
    if (slab_bytes(m, o, d, hi, streamed) <= budget) lo = hi;
    while (hi - lo > 1) {
      const int mid = lo + (hi - lo) / 2;
      (slab_bytes(m, o, d, mid, streamed) <= budget ? lo : hi) = mid;
    }
    fit = lo;
  }
  if (fit && !o.measure) return {fit, saturated_bytes(slab_bytes(m, o, d, fit, streamed)), {}};
  if (o.measure && fit)
    return {0, saturated_bytes(whole),
            "--measure needs the whole grid in memory, about " + detail::memory_text(whole) +
                ", but the memory budget is " + detail::memory_text(budget) +
                "; without --measure the job runs in slabs that fit"};
  // The least any path needs falls as the voxel grows: bisect for the smallest that fits.
  auto least = [&](double voxel) {
    FillOptions t = o;
    t.grid.voxel_size = voxel;
    // Measures need the whole grid: only its estimate counts for them.
    return o.measure
               ? estimate_bytes(m, t)
               : std::fmin(estimate_bytes(m, t), slab_bytes(m, t, d, kMinSlabPlanes, streamed));
  };
  double lo = o.grid.voxel_size, hi = o.grid.voxel_size;
  do hi *= 2;
  while (least(hi) > budget && hi < 1e12);
  for (int it = 0; it < 60; ++it) {
    const double mid = 0.5 * (lo + hi);
    (least(mid) > budget ? lo : hi) = mid;
  }
  char fit_text[64];
  std::snprintf(fit_text, sizeof fit_text, "%.4g mm", hi * 1.0001);
  const double need = least(o.grid.voxel_size);
  const bool input_alone =
      static_cast<double>(triangles) * kBytesPerInputTriangle + kFixedBytes > budget;
  return {0, saturated_bytes(need),
          "the job needs about " + detail::memory_text(need) + " but the memory budget is " +
              detail::memory_text(budget) +
              (input_alone ? "; the input alone exceeds it"
                           : "; a voxel size of " + std::string(fit_text) + " or more fits")};
}

// The stages fill() will run, in order, with rough shares of the time: per cent of a job's,
// the femur's and the tube's stage tables averaged (docs/benchmarks.md §4; measure and the full
// field from the femur's). The auto inside rule plans the clean and the second classification
// it may need; they are credited when skipped, so the overall fraction does not go back.
std::vector<detail::PlannedStage> plan_stages(const FillOptions& o, bool slabs,
                                              bool streamed = false) {
  std::vector<detail::PlannedStage> plan{{"review", 0.5}};
  if (slabs) {
    for (detail::PlannedStage& s : detail::slab_stages(o)) plan.push_back(std::move(s));
    plan.insert(plan.end(),
                {{"islands", 6}, {streamed ? detail::kValidateAndWrite : "validate", 46}});
    return plan;
  }
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

// What islands are judged by: which nodes are solid (φ < 0), the model's parts (26-connected
// regions of inside nodes) and, on demand, the solid's pieces (6-connected regions of solid
// nodes). The whole-grid path reads them from φ and the occupancy, the slab path from runs.
struct IslandMasks {
  std::function<bool(int, int, int)> solid;
  Regions parts;
  std::function<Regions()> pieces;
};

// The masks of the path the job took.
IslandMasks island_masks(const Job& job) {
  if (job.slab_planes == 0) {
    const Field& phi = job.phi;
    return {[&phi](int i, int j, int k) { return phi.values[phi.grid.index(i, j, k)] < 0; },
            label_regions(job.occupancy.inside),
            [&phi] {
              Mask solid{phi.grid, std::vector<std::uint8_t>(phi.values.size())};
              detail::parallel_for(solid.values.size(), std::size_t{1} << 16,
                                   [&](std::size_t b, std::size_t e) {
                                     for (std::size_t n = b; n < e; ++n)
                                       solid.values[n] = phi.values[n] < 0;
                                   });
              return label_regions(solid, Connectivity::Face);
            }};
  }
  return {
      [&job](int i, int j, int k) { return job.solid_runs.region_at(i, j, k) != detail::kNoIndex; },
      label_runs(job.inside_runs),
      [&job] { return label_runs(job.solid_runs, Connectivity::Face); }};
}

// Islands: lattice components that are not the largest piece within their part of the model
// (a 26-connected region of inside nodes). A component is located by a solid corner (φ < 0
// implies the node is inside) of the cell holding its first triangle: its node index, or none.
std::vector<std::uint64_t> solid_nodes(const std::vector<Vec3>& first_centroid, const Grid& g,
                                       const IslandMasks& masks) {
  std::vector<std::uint64_t> node(first_centroid.size(), UINT64_MAX);
  for (std::size_t c = 0; c < first_centroid.size(); ++c) {
    const Vec3 centroid = first_centroid[c];
    int cell[3];
    for (int axis = 0; axis < 3; ++axis)
      cell[axis] =
          std::clamp(static_cast<int>(std::floor((centroid[axis] - g.origin[axis]) / g.spacing)), 0,
                     g.dims[axis] - 2);
    for (int corner = 0; corner < 8 && node[c] == UINT64_MAX; ++corner) {
      const int i = cell[0] + (corner & 1), j = cell[1] + (corner >> 1 & 1),
                k = cell[2] + (corner >> 2 & 1);
      if (masks.solid(i, j, k)) node[c] = g.index(i, j, k);
    }
  }
  return node;
}

std::vector<bool> main_bodies(const detail::ComponentFacts& comps, const Grid& g,
                              const IslandMasks& masks) {
  const std::uint32_t none = detail::kNoIndex;
  const std::vector<std::uint64_t> node = solid_nodes(comps.first_centroid, g, masks);
  auto region_of = [&](const Regions& r, std::size_t c) {
    if (node[c] == UINT64_MAX) return none;
    const std::uint64_t n = node[c], nx = g.dims[0], ny = g.dims[1];
    return r.region_at(static_cast<int>(n % nx), static_cast<int>(n / nx % ny),
                       static_cast<int>(n / (nx * ny)));
  };
  std::vector<std::uint32_t> part(comps.info.size(), none);
  for (std::size_t c = 0; c < comps.info.size(); ++c) part[c] = region_of(masks.parts, c);
  std::vector<std::size_t> largest(masks.parts.count, std::numeric_limits<std::size_t>::max());
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
  const Regions pieces = masks.pieces();
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

// The forecast of a job (FillForecast): its samples and triangles, the planned peak, and the
// time on the cores TBB may use.
FillForecast forecast(const ModelSize& m, const FillOptions& o, const detail::MemoryPlan& plan) {
  FillForecast f;
  f.samples = grid_node_count(m.bounds, o.grid);
  f.triangles = output_triangles(m, o, Count::Expected);
  f.memory_bytes = plan.bytes;
  // Seconds on 2 cores (docs/benchmarks.md §4: femur 6.4 M samples, 0.65 M triangles out,
  // 0.85 s; tube 34 M samples, 3.5 M out, 4.7 M in, 9-11 s), scaled by the cores.
  const double samples = static_cast<double>(f.samples);
  const double on_two =
      45e-9 * samples + 1.3e-6 * f.triangles + 0.5e-6 * static_cast<double>(m.triangles) +
      (o.full_field ? 0.8e-6 * samples : 0.0) + (o.measure ? 60e-9 * samples : 0.0);
  std::tie(f.seconds_low, f.seconds_high) = detail::seconds_range(on_two);
  return f;
}

// Settings into the report, the design resolved against the model's box; the caller's
// preflight given the forecast, once everything that can be refused before the work has been.
void resolve(Job& job, const detail::MemoryPlan& plan) {
  const FillOptions& o = job.options;
  FillReport& r = job.report;
  const LatticeDesign& d = job.result.resolved.design;
  job.grid = make_grid(r.input_bbox, o.grid);  // validates the options first
  // A grid finer than the output's coordinates where the part sits cannot be written valid.
  detail::require_held_grid(job.grid, o.rounding);
  // What cannot come out as asked is refused here, before the work; doubts are warnings.
  std::vector<std::string> doubts = job.stage("review", [&] {
    return review_design(d, r.input_bbox,
                         {.voxel = job.grid.spacing, .input_units = o.units.units});
  });
  for (std::string& w : doubts) r.warnings.push_back(std::move(w));
  if (!plan.refusal.empty()) throw ResourceError(plan.refusal);
  if (o.preflight) o.preflight(forecast(model_size(job.model), o, plan));
  r.estimated_memory_bytes = plan.bytes;
  r.slab_planes = plan.slab_planes;
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
  Occupancy::PlaneCounts total;
  for (const Occupancy::PlaneCounts& p : job.occupancy.planes) total += p;
  const std::vector<std::uint8_t>& in = job.occupancy.inside.values;
  detail::record_classification(o, total, std::find(in.begin(), in.end(), 1) != in.end(), r);
}

// φ = max(φ_model, φ_L): the model's distance on the band (or everywhere with --full-field),
// the design's field where the model does not decide.
void compose(Job& job) {
  const FillOptions& o = job.options;
  FillReport& r = job.report;
  const Mask& inside = job.occupancy.inside;
  // Depth ramps grade by the distance below the surface: the occupancy's distance transform.
  detail::solve_porosity_with_skin(o, *job.tree, job.result.resolved.design, r);
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
void warn_cavities(const FillOptions& o, const detail::ComponentFacts& comps,
                   const std::vector<bool>& keep, double voxel, FillReport& r) {
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

// Islands of the mesh held whole: its components, judged, and the islands dropped.
void remove_islands(Job& job) {
  const Components comps = mesh_components(job.mesh);
  detail::ComponentFacts facts;
  facts.info = comps.info;
  for (const Components::Info& c : comps.info) {
    const Triangle& t = job.mesh.triangles[c.first_triangle];
    const TriangleSoup& m = job.mesh;
    facts.first_centroid.push_back((1.0 / 3.0) *
                                   (m.points[t[0]] + m.points[t[1]] + m.points[t[2]]));
  }
  facts.boxes = [&](const std::vector<bool>& keep) {
    std::vector<Box3> box(comps.info.size());
    for (std::size_t t = 0; t < job.mesh.triangles.size(); ++t)
      if (const std::uint32_t c = comps.triangle_component[t]; !keep[c])
        for (std::uint32_t v : job.mesh.triangles[t]) box[c].extend(job.mesh.points[v]);
    return box;
  };
  const std::vector<bool> keep = detail::judge_islands(job, facts);
  if (std::find(keep.begin(), keep.end(), false) != keep.end())
    job.mesh = keep_components(job.mesh, comps, keep);
}

// Nothing is returned that failed validation.
void validate(Job& job) {
  const FillOptions& o = job.options;
  FillReport& r = job.report;
  if (job.mesh.triangles.empty()) throw InputError(detail::kEmptyLattice);
  round_coordinates(o.rounding, job.mesh);
  r.validation = job.stage("validate", [&] {
    return validate_mesh(job.mesh, {.self_intersections = o.check_self_intersections,
                                    .cell_grid = job.grid,
                                    .progress = job.progress});
  });
  detail::require_valid_lattice(r.validation);
}

// A structure's porosity is solved over its whole unit cube; the part sees only what the
// model covers of it, which may be mostly void or mostly solid. Say so with the numbers.
}  // namespace

namespace detail {

std::string memory_text(double bytes) {
  // Binary units, as --memory reads 512M and 8G: a budget of 150M shows as 150 MiB.
  constexpr double kMiB = 1024.0 * 1024.0, kGiB = 1024.0 * kMiB;
  char s[32];
  if (bytes >= kGiB)
    std::snprintf(s, sizeof s, "%.3g GiB", bytes / kGiB);
  else if (bytes >= kMiB)
    std::snprintf(s, sizeof s, "%.3g MiB", bytes / kMiB);
  else
    std::snprintf(s, sizeof s, "%.0f byte%s", bytes, bytes == 1 ? "" : "s");
  return s;
}

void require_valid_lattice(const ValidationReport& v) {
  if (v.valid()) return;
  std::string why;
  for (const std::string& p : v.problems()) why += (why.empty() ? "" : "; ") + p;
  throw ValidationError("the lattice failed validation, nothing was written: " + why);
}

// Cavities are counted (a closed skin seals them in); islands, the pieces that are not the
// main body of their part of the model, are to be removed unless kept, the largest listed.
std::vector<bool> judge_islands(const Job& job, const ComponentFacts& comps) {
  const FillOptions& o = job.options;
  FillReport& r = job.report;
  double lattice_before = 0;
  for (const auto& c : comps.info) lattice_before += c.volume;
  std::vector<bool> keep(comps.info.size(), true);
  if (!o.keep_islands && comps.info.size() >= 2)
    keep = main_bodies(comps, job.grid, island_masks(job));
  for (std::size_t c = 0; c < keep.size(); ++c)
    if (keep[c] && comps.info[c].volume < 0)
      ++r.cavities, r.cavities_volume -= comps.info[c].volume;
  warn_cavities(o, comps, keep, job.grid.spacing, r);
  if (std::find(keep.begin(), keep.end(), false) == keep.end()) return keep;
  // An island is a removed piece of positive volume; the cavities it enclosed go with it, so
  // the volume removed is the signed sum.
  const std::vector<Box3> box = comps.boxes(keep);
  for (std::size_t c = 0; c < keep.size(); ++c)
    if (!keep[c]) {
      r.islands_volume += comps.info[c].volume;
      if (comps.info[c].volume < 0) continue;
      ++r.islands_removed;
      r.largest_islands.push_back({comps.info[c].volume, box[c]});
    }
  // Largest first; equal volumes keep component order, so the list is deterministic.
  std::stable_sort(
      r.largest_islands.begin(), r.largest_islands.end(),
      [](const RemovedIsland& a, const RemovedIsland& b) { return a.volume > b.volume; });
  if (r.largest_islands.size() > 10) r.largest_islands.resize(10);
  if (r.islands_removed) warn_islands(o, lattice_before, r);
  return keep;
}

namespace {

// Share of the model's volume within `skin` mm of its surface, measured at the inside nodes of
// a coarse grid over the model (about 200,000 nodes; finer once when fewer than 20,000 fall
// inside), at most 50,000 of them, by their distance d to the surface. The grid is offset half
// a step from the model's box, so that its nodes tile the volume (on a CAD part's flat faces
// too: nodes on a face would leave its outer half step unsampled), and each node counts the
// share of its step that lies in the skin, clamp((skin - d) / h + ½): a shell of any thickness
// comes out within a few per cent of its volume.
double skin_share(const MeshIndex& tree, InsideRule rule, const Box3& box, double skin) {
  const Vec3 size = box.size();
  double h = std::cbrt(std::max(size.x * size.y * size.z, 1e-300) / 2e5);
  std::vector<Vec3> inside;
  for (int attempt = 0; attempt < 2 && inside.size() < 20000; ++attempt, h /= 2) {
    Grid g = make_grid(box, {.voxel_size = h, .padding = 2});
    g.origin = g.origin + Vec3{0.5 * h, 0.5 * h, 0.5 * h};
    const Occupancy occupancy = classify_grid(tree, g, {.rule = rule});
    inside.clear();
    for (int k = 0; k < g.dims[2]; ++k)
      for (int j = 0; j < g.dims[1]; ++j)
        for (int i = 0; i < g.dims[0]; ++i)
          if (occupancy.inside.values[g.index(i, j, k)]) inside.push_back(g.node(i, j, k));
  }
  if (inside.empty()) return 0;
  h *= 2;  // the step of the grid that was sampled
  std::vector<Vec3> sample;
  const std::size_t stride = (inside.size() + 49999) / 50000;
  for (std::size_t n = 0; n < inside.size(); n += stride) sample.push_back(inside[n]);
  const std::vector<Vec3> nearest = closest_points(tree, sample);
  double in_skin = 0;
  for (std::size_t n = 0; n < sample.size(); ++n)
    in_skin += std::clamp((skin - norm(nearest[n] - sample[n])) / h + 0.5, 0.0, 1.0);
  return in_skin / static_cast<double>(sample.size());
}

// Whether the design is one TPMS whose porosity is the same everywhere (no grading of how solid
// it is, no blends, no structure or custom field): then a porosity asked is the part's.
bool one_porosity(const LatticeDesign& d) {
  if (d.structure || d.custom || !d.blends.empty()) return false;
  return std::all_of(d.grading.begin(), d.grading.end(),
                     [](const Grading& g) { return g.what == Graded::Cell; });
}

// The most porous a lattice layer is solved to: the review refuses layers under 1 % solid and
// warns under 3 %.
constexpr double kMostPorousLattice = 0.97;

}  // namespace

std::optional<FillPart::SolvedPorosity> solve_porosity_with_skin(const FillOptions& o,
                                                                 const MeshIndex& tree,
                                                                 LatticeDesign& d, FillReport& r) {
  if (!(o.skin > 0) || !d.porosity || !one_porosity(d)) return std::nullopt;
  // The part's solid is the skin (share s of its volume) and the lattice in the rest, so a part
  // porosity p needs a lattice porosity of p / (1 - s).
  const double asked = *d.porosity;
  const double share =
      skin_share(tree, o.inside.value_or(InsideRule::Winding), r.input_bbox, o.skin);
  FillPart::SolvedPorosity s;
  s.lattice_porosity = share < 1 ? asked / (1 - share) : 1;
  if (s.lattice_porosity > kMostPorousLattice) {
    s.lattice_porosity = kMostPorousLattice;
    char text[400];
    std::snprintf(text, sizeof text,
                  "the %.3g mm skin is %.1f %% of the part's volume: with it the part can be at "
                  "most %.1f %% porous, not the %.1f %% asked (a thinner --skin, or --skin-windows "
                  "to open it at the pores)",
                  o.skin, 100 * share, 100 * kMostPorousLattice * (1 - share), 100 * asked);
    s.warnings.push_back(text);
  }
  LatticeDesign solved = o.design;
  solved.porosity = s.lattice_porosity;
  solved = resolve_design(solved, r.input_bbox);
  s.level = solved.level;
  s.thickness = solved.thickness;
  apply_solved_porosity(s, d, r);
  return s;
}

void apply_solved_porosity(const FillPart::SolvedPorosity& s, LatticeDesign& d, FillReport& r) {
  // The level (or thickness) is now fixed: a porosity left set would be solved again for the
  // lattice alone. The report keeps the part's target; the echoed recipe the level, which
  // reruns the job exactly.
  d.level = s.level;
  d.thickness = s.thickness;
  d.porosity.reset();
  r.level = s.level;
  r.thickness = s.thickness;
  r.unclipped_porosity = s.lattice_porosity;
  r.warnings.insert(r.warnings.end(), s.warnings.begin(), s.warnings.end());
}

void warn_porosity(const LatticeDesign& d, double got, FillReport& r) {
  if (!r.porosity_target || !(d.structure || one_porosity(d))) return;
  // A skin that leaves no room was warned about with its own numbers (solve_porosity_with_skin).
  if (r.skin > 0 && r.unclipped_porosity >= kMostPorousLattice) return;
  const double asked = *r.porosity_target;
  if (std::fabs(got - asked) <= 0.05) return;
  const char* side = got > asked ? "more void than the rest" : "more solid than the rest";
  const char* ask = got > asked ? "a lower porosity" : "a higher porosity";
  char why[300];
  if (d.structure)
    std::snprintf(why, sizeof why,
                  "the structure's porosity is solved over its whole cube, and the model covers "
                  "parts of the cube that are %s; tile it (--cell) or ask for %s",
                  side, ask);
  else
    std::snprintf(why, sizeof why,
                  "the lattice is clipped to a part only a few cells across, where its cut cells "
                  "are %s; ask for %s, or use smaller cells",
                  side, ask);
  char text[450];
  std::snprintf(text, sizeof text, "the part's porosity is %.1f %%, not the %.1f %% asked: %s",
                100 * got, 100 * asked, why);
  r.warnings.push_back(text);
}

namespace {

// "0.061 mm at (1.2, 3.4, 5.6), ..." for the first three.
std::string worst_places(const std::vector<SizeSample>& smallest) {
  std::string out;
  char text[120];
  for (std::size_t i = 0; i < std::min<std::size_t>(3, smallest.size()); ++i) {
    const SizeSample& s = smallest[i];
    std::snprintf(text, sizeof text, "%s%.3g mm at (%.2f, %.2f, %.2f)", i ? ", " : "", s.diameter,
                  s.at.x, s.at.y, s.at.z);
    out += text;
  }
  return out;
}

void warn_below(const SizeDistribution& d, double limit, const char* what, const char* flag,
                const char* remedy, double voxel, FillReport& r) {
  if (limit <= 0 || d.below_limit + d.below_limit_at_surface == 0) return;
  char text[600];
  std::string sentence;
  if (d.below_limit > 0) {
    std::vector<SizeSample> below;
    for (const SizeSample& s : d.smallest)
      if (s.diameter < limit) below.push_back(s);
    std::snprintf(text, sizeof text,
                  "%s below %s %g mm: %.3g %% of the %.0f measured inside the part (p10 %.3g "
                  "mm, median %.3g mm); the smallest: %s; %s",
                  what, flag, limit,
                  100.0 * static_cast<double>(d.below_limit) / static_cast<double>(d.samples),
                  static_cast<double>(d.samples), d.p10, d.p50, worst_places(below).c_str(),
                  remedy);
    sentence = text;
    if (d.below_limit_at_surface > 0) {
      std::snprintf(text, sizeof text, "; %.0f more where the part's surface cuts the lattice",
                    static_cast<double>(d.below_limit_at_surface));
      sentence += text;
    }
  } else {
    std::snprintf(text, sizeof text,
                  "%s below %s %g mm only where the part's surface cuts the lattice: %.0f "
                  "sample(s), slivers that may not print (a skin, --skin, holds them)",
                  what, flag, limit, static_cast<double>(d.below_limit_at_surface));
    sentence = text;
  }
  std::snprintf(text, sizeof text, " (sizes measured to about +-%g mm, half a voxel)", voxel / 2);
  r.warnings.push_back(sentence + text);
}

}  // namespace

void warn_printability(const FillOptions& o, double voxel, FillReport& r) {
  if (!r.measures) return;
  warn_below(r.measures->wall, o.min_wall, "walls", "--min-wall",
             "thicken them (a lower --porosity, a larger --thickness or --cell)", voxel, r);
  warn_below(r.measures->pore, o.min_pore, "pores", "--min-pore",
             "powder or resin may stay trapped; widen them (a higher --porosity or a larger "
             "--cell)",
             voxel, r);
}

LatticeDesign describe_job(const TriangleSoup& model, const FillOptions& o, FillReport& r) {
  r.min_wall = o.min_wall;
  r.min_pore = o.min_pore;
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
  } else if (!d.custom) {
    r.unclipped_porosity = 1.0 - tpms_solid_fraction(d);
    // A graded porosity, level or thickness has no one unclipped porosity: say so, rather than
    // the base lattice's.
    for (const Grading& g : d.grading)
      if (g.what != Graded::Cell) r.unclipped_porosity = std::nan("");
  }
  return d;
}

void record_classification(const FillOptions& o, const Occupancy::PlaneCounts& c, bool any_inside,
                           FillReport& r) {
  r.rows = c.rows;
  r.crossings = c.crossings;
  r.odd_rows = c.odd_rows;
  r.overlap_rows = c.overlap_rows;
  r.parity_disagreements = c.parity_disagreements;
  r.cap_evaluations = c.cap_evaluations;
  r.model_volume = c.volume;
  if (o.inside == InsideRule::Parity && c.odd_rows)
    r.warnings.push_back(std::to_string(c.odd_rows) +
                         " grid rows crossed the surface an odd number of times: the input is "
                         "not closed, so inside and outside may be wrong near its holes "
                         "(--inside winding handles holes)");
  if (!any_inside)
    throw InputError(
        "the mesh encloses no volume: no grid node is inside it (an open sheet, or a shell "
        "thinner than the voxel size)");
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

std::uint64_t estimate_fill_memory(const TriangleSoup& model, const FillOptions& options) {
  require_valid(options.units);
  const ModelSize m =
      model_size(options.units.factor() != 1 ? to_millimetres(model, options.units) : model);
  return plan_memory(m, options, resolve_design(options.design, m.bounds), false).bytes;
}

std::pair<double, double> detail::seconds_range(double on_two) {
  const auto cores = static_cast<double>(
      tbb::global_control::active_value(tbb::global_control::max_allowed_parallelism));
  const double middle = on_two * 2.0 / std::max(cores, 1.0);
  return {0.5 * middle, 2.0 * middle};
}

double detail::expected_output_area(const TriangleSoup& model, const FillOptions& options) {
  return output_area(model_size(model), options, Count::Expected);
}

FillForecast forecast_fill(const TriangleSoup& model, const FillOptions& options) {
  require_valid(options.units);
  const ModelSize m =
      model_size(options.units.factor() != 1 ? to_millimetres(model, options.units) : model);
  // As fill_to_file() plans it: a grid over the budget streams by slabs.
  return forecast(m, options,
                  plan_memory(m, options, resolve_design(options.design, m.bounds), true));
}

namespace {

// What every entry point settles first: the options checked, the model in millimetres (a copy
// only when the input is in another unit), the design resolved, the memory plan.
struct Setup {
  std::optional<TriangleSoup> in_mm;
  const TriangleSoup* model = nullptr;
  detail::MemoryPlan plan;
};

void set_up(const TriangleSoup& input, const FillOptions& options, FillResult& result, Setup& s,
            bool streamed = false) {
  require_valid(options.units);
  require_valid(options.design);
  require_valid(ComposeOptions{.skin = options.skin});  // fail before any work
  for (const double limit : {options.min_wall, options.min_pore})
    if (!(limit >= 0 && std::isfinite(limit)))
      throw InputError("min_wall and min_pore must be finite and not negative (0: no limit)");
  if ((options.min_wall > 0 || options.min_pore > 0) && !options.measure)
    throw InputError("min_wall and min_pore are checked against the measures: set measure too");
  if (options.units.factor() != 1) s.in_mm = to_millimetres(input, options.units);
  s.model = s.in_mm ? &*s.in_mm : &input;
  result.resolved = options;
  result.resolved.design = detail::describe_job(*s.model, options, result.report);
  s.plan = plan_memory(model_size(*s.model), options, result.resolved.design, streamed);
}

// Islands, measures, validation: the mesh as the field's stages left it, finished.
void finish(Job& job) {
  FillResult& result = job.result;
  const FillOptions& options = job.options;
  job.stage("islands", [&] { remove_islands(job); });
  if (options.measure) {
    result.report.measures = job.stage("measure", [&] {
      return measure_lattice(
          job.phi, job.occupancy.inside,
          {.min_wall = options.min_wall, .min_pore = options.min_pore, .progress = job.progress});
    });
    detail::warn_printability(options, job.grid.spacing, result.report);
  }
  job.phi = Field{};
  job.occupancy = Occupancy{};
  job.depth.reset();
  job.inside_runs = job.solid_runs = Regions{};
  validate(job);
  detail::warn_porosity(result.resolved.design, result.report.porosity(), result.report);
  job.job_progress.finish();
  result.mesh = std::move(job.mesh);
}

// The job with its mesh held: the whole grid, or slabs.
void fill_in_memory(const FillOptions& options, const Setup& s, FillResult& result) {
  Job job(*s.model, options, result, plan_stages(options, s.plan.slab_planes > 0),
          s.plan.slab_planes);
  resolve(job, s.plan);
  if (job.slab_planes > 0) {
    detail::mesh_in_slabs(job);
  } else {
    classify(job);
    compose(job);
    job.mesh = job.stage("marching cubes", [&] {
      return marching_cubes(job.phi, {.progress = job.progress, .rounding = options.rounding});
    });
  }
  finish(job);
}

}  // namespace

FillResult fill(const TriangleSoup& input, const FillOptions& options) {
  FillResult result;
  Setup s;
  set_up(input, options, result, s);
  fill_in_memory(options, s, result);
  return result;
}

namespace {

// Before any work: a name whose extension names no format.
void require_format(const std::filesystem::path& path, const WriteOptions& write) {
  if (write.format == MeshFormat::Auto && format_from_extension(path) == MeshFormat::Auto)
    throw InputError("cannot write " + unknown_mesh_extension(path));
}

// The options a job writing `path` runs with: a 3MF's rounding replaces the float rounding,
// so the package holds exactly the mesh that was validated.
FillOptions for_target(const FillOptions& options, const std::filesystem::path& path,
                       const WriteOptions& write) {
  FillOptions o = options;
  const MeshFormat format =
      write.format == MeshFormat::Auto ? format_from_extension(path) : write.format;
  if (rounding_for(format) == CoordinateRounding::ThreeMf && o.rounding != CoordinateRounding::None)
    o.rounding = CoordinateRounding::ThreeMf;
  return o;
}

// A held result written, the write timed into its report, its mesh let go.
void write_held(FillResult& result, const std::filesystem::path& path, const WriteOptions& write) {
  const auto t0 = std::chrono::steady_clock::now();
  WriteOptions described = write;
  described.metadata = lattice_metadata(result.report, write.metadata);
  write_mesh(path, result.mesh, described);
  result.report.stages.push_back(
      {"write", std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count(),
       peak_memory_mb()});
  result.mesh = {};
}

}  // namespace

FillResult fill_to_file(const TriangleSoup& input, const FillOptions& given,
                        const std::filesystem::path& path, const WriteOptions& write) {
  require_format(path, write);
  const FillOptions options = for_target(given, path, write);
  FillResult result;
  Setup s;
  set_up(input, options, result, s, true);
  if (s.plan.slab_planes == 0) {  // the whole grid fits, with its mesh: fill() as it is
    fill_in_memory(options, s, result);
    write_held(result, path, write);
    return result;
  }
  Job job(*s.model, options, result, plan_stages(options, true, true), s.plan.slab_planes);
  resolve(job, s.plan);
  detail::fill_streamed(job, path, write);
  return result;
}

Grid fill_grid(const TriangleSoup& input, const FillOptions& options) {
  require_valid(options.units);
  const Box3 box = bounding_box(input);
  const double f = options.units.factor();
  return make_grid({f * box.min, f * box.max}, options.grid);
}

FillPart fill_part(const TriangleSoup& input, const FillOptions& options,
                   const FillPartOptions& part) {
  FillResult result;
  Setup s;
  // Planned as a streamed job: the process finishing it streams the parts when they do not fit
  // (fill_parts_to_file); the share's own mesh is its share of the output.
  set_up(input, options, result, s, true);
  const auto t0 = std::chrono::steady_clock::now();
  // The share goes in slabs as thick as the whole job's plan allows, or whole.
  const int share = part.end_plane - part.first_plane;
  Job job(*s.model, options, result, plan_stages(options, true),
          s.plan.slab_planes > 0 ? std::min(s.plan.slab_planes, std::max(share, 1))
                                 : std::max(share, 1));
  resolve(job, s.plan);
  if (part.first_plane < 0 || share < 1 || part.end_plane > job.grid.dims[2])
    throw InputError("fill_part: planes " + std::to_string(part.first_plane) + " to " +
                     std::to_string(part.end_plane) + " are not a range of the grid's " +
                     std::to_string(job.grid.dims[2]));
  FillPart p = detail::mesh_planes(job, part.first_plane, part.end_plane, part.any_unbalanced, {});
  p.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  job.job_progress.finish();
  return p;
}

FillResult fill_parts(const TriangleSoup& input, const FillOptions& options,
                      std::vector<FillPart> parts) {
  FillResult result;
  Setup s;
  set_up(input, options, result, s);
  int thickest = 1;
  for (const FillPart& p : parts) thickest = std::max(thickest, p.end_plane - p.first_plane);
  Job job(*s.model, options, result,
          {{"review", 0.5}, {"join", 5}, {"islands", 6}, {"validate", 46}},
          s.plan.slab_planes > 0 ? s.plan.slab_planes : thickest);
  resolve(job, s.plan);
  result.report.ranks = static_cast<int>(parts.size());
  double slowest = 0;
  for (const FillPart& p : parts) slowest = std::max(slowest, p.seconds);
  result.report.stages.push_back({"parts (slowest)", slowest, 0});
  job.stage("join", [&] { detail::join_parts(job, std::move(parts)); });
  finish(job);
  return result;
}

FillResult fill_parts_to_file(const TriangleSoup& input, const FillOptions& given, int count,
                              const std::function<FillPart()>& next_part,
                              const std::filesystem::path& path, const WriteOptions& write) {
  require_format(path, write);
  const FillOptions options = for_target(given, path, write);
  FillResult result;
  Setup s;
  set_up(input, options, result, s, true);
  if (s.plan.slab_planes == 0) {  // the whole grid and its mesh fit: joined, held, written
    std::vector<FillPart> parts;
    for (int i = 0; i < count; ++i) parts.push_back(next_part());
    result = fill_parts(input, options, std::move(parts));
    write_held(result, path, write);
    return result;
  }
  Job job(*s.model, options, result,
          {{"review", 0.5}, {"join", 5}, {"islands", 6}, {detail::kValidateAndWrite, 46}},
          s.plan.slab_planes);
  resolve(job, s.plan);
  result.report.ranks = count;
  double slowest = 0;
  detail::fill_parts_streamed(
      job, count,
      [&] {
        FillPart p = next_part();
        slowest = std::max(slowest, p.seconds);
        return p;
      },
      path, write);
  auto& stages = result.report.stages;
  const auto join = std::find_if(stages.begin(), stages.end(),
                                 [](const StageTime& t) { return t.name == "join"; });
  stages.insert(join, {"parts (slowest)", slowest, 0});
  return result;
}

}  // namespace tpmsfill
