// The whole pipeline, stage by stage, timing each into the report.
#include "tpmsfill/fill.hpp"

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

#include "core/grid_border.hpp"
#include "core/job_progress.hpp"
#include "lattice/field_job.hpp"
#include "lattice/field_planes.hpp"
#include "lattice/fill_job.hpp"
#include "lattice/review.hpp"
#include "sampling/rounded_grid.hpp"
#include "tpmsfill/error.hpp"
#include "tpmsfill/field.hpp"
#include "tpmsfill/lattice/compose.hpp"
#include "tpmsfill/lattice/design.hpp"
#include "tpmsfill/lattice/measure.hpp"
#include "tpmsfill/mesh/clean.hpp"
#include "tpmsfill/mesh/validate.hpp"
#include "tpmsfill/sampling/classify.hpp"
#include "tpmsfill/sampling/distance.hpp"
#include "tpmsfill/sampling/marching_cubes.hpp"
#include "tpmsfill/sampling/spatial.hpp"

namespace tpmsfill {
namespace {

using detail::Job;

// Bytes per grid node at the peak: occupancy, the band stage's three temporary masks, and the
// composed field (plus the full distance field with --full-field).
constexpr double kBytesPerNode = 8.0;
constexpr double kBytesPerFullFieldNode = 4.0;
using detail::Count;
using detail::kBytesPerInputTriangle;
using detail::kFixedBytes;
using detail::model_size;
using detail::ModelSize;
using detail::output_area;
// Bytes per output triangle: indices, half a vertex, validation's edge table and buckets
// (the peak of a shark of mechanical holes at 10.4 million triangles is 149 a triangle over
// the fixed share, docs/benchmarks.md §27).
constexpr double kBytesPerOutputTriangle = 160.0;
// Bytes per triangle while the field is held: marching cubes' mesh and the islands' labels and
// components (56 measured). Validation by marching cubes' proof needs no more: the mesh, the
// used points, the components and the volumes (a dragon at 0.5 mm peaked at islands, 54 a
// triangle over the field's share, and validation added nothing).
constexpr double kBytesPerMeshedTriangle = 60.0;

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
// kBytesPerMeshedTriangle) and validation, since the field is gone before validation starts:
// searched, the mesh and its tables (kBytesPerOutputTriangle); `proved` by marching cubes'
// construction, no more than the field stages' share of the mesh.
double peak_bytes(const ModelSize& m, const FillOptions& o, double field_bytes, bool proved) {
  const double out = output_triangles(m, o);
  const double validation = (proved ? kBytesPerMeshedTriangle : kBytesPerOutputTriangle) * out;
  return static_cast<double>(m.triangles) * kBytesPerInputTriangle +
         std::fmax(field_bytes + kBytesPerMeshedTriangle * out, validation) + kFixedBytes;
}

// The whole grid's peak: proved unless a full search is asked for.
double estimate_bytes(const ModelSize& m, const FillOptions& o) {
  const double nodes = static_cast<double>(grid_node_count(m.bounds, o.grid));
  return peak_bytes(m, o, nodes * (kBytesPerNode + (o.full_field ? kBytesPerFullFieldNode : 0.0)),
                    o.validation == FillOptions::Validation::Proof);
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
  // Held, the slabs' mesh is proved as the whole grid's is.
  if (!streamed) return peak_bytes(m, o, field, o.validation == FillOptions::Validation::Proof);
  // Streamed, only one slab's share of the output is held (marching cubes' triangles and
  // points, their labels), beside the three records validation reads and the writer's buffers.
  const double share = std::fmin(1.0, (planes + 2.0) / std::max(g.dims[2], 1));
  return static_cast<double>(m.triangles) * kBytesPerInputTriangle + field +
         48 * share * output_triangles(m, o) + kStreamBytes + kFixedBytes;
}

// The thinnest slabs the plan chooses: thinner ones would spend more on their halos and
// marching cubes' lookahead planes than on their own.
constexpr int kMinSlabPlanes = 4;

// Whole-grid estimates above one of these go in slabs that fit it (plan_memory's cost model).
constexpr double kSlabTargets[] = {512.0 * (1u << 20), 2048.0 * (1u << 20)};

// The memory plan: the whole grid at once when it fits the budget (or slabs when asked), else
// slabs as thick as fit; when nothing fits, the refusal to throw after the review, naming a
// voxel size that fits.
detail::MemoryPlan plan_memory(const ModelSize& m, const FillOptions& o, const LatticeDesign& d,
                               bool streamed, bool whole_only = false) {
  const Box3& bounds = m.bounds;
  const std::uint64_t triangles = m.triangles;
  const double budget =
      static_cast<double>(o.memory_budget ? o.memory_budget : default_memory_budget());
  const double whole = estimate_bytes(m, o);
  const int nz = make_grid(bounds, o.grid).dims[2];
  if (o.slab_planes > 0 && !whole_only) {
    if (o.measure)
      throw InputError(
          "measures need the whole grid: they cannot be taken in slabs "
          "(FillOptions::slab_planes)");
    const int planes = std::min(o.slab_planes, nz);
    return {planes, saturated_bytes(slab_bytes(m, o, d, planes, streamed)), {}};
  }
  // The thickest slabs that fit `bytes` (bytes grow with the thickness until validation's
  // peak, the output's, dominates): bisect; 0 when none does.
  auto thickest_within = [&](double bytes) {
    if (whole_only || slab_bytes(m, o, d, kMinSlabPlanes, streamed) > bytes) return 0;
    int lo = kMinSlabPlanes, hi = nz;
    if (slab_bytes(m, o, d, hi, streamed) <= bytes) lo = hi;
    while (hi - lo > 1) {
      const int mid = lo + (hi - lo) / 2;
      (slab_bytes(m, o, d, mid, streamed) <= bytes ? lo : hi) = mid;
    }
    return lo;
  };
  // The cost model: a large grid goes in slabs even when it fits whole. Slabs reuse one slab's
  // arrays where the whole grid faults in fresh memory for each of its own, and that costs
  // more than the slabs' halos (docs/benchmarks.md §32: the femur at 4.9·10⁷ samples, 1.23 s
  // and 244 MB in slabs that fit 512 MiB against 1.60 s and 393 MB whole; at 1.1·10⁹ samples,
  // 18 s and 1.6 GB in slabs that fit 2 GiB against 24 s and 6.1 GB). The slabs fit the first
  // of kSlabTargets that the whole grid exceeds and that some slabs fit (a large input or
  // output may need more than 512 MiB); `--measure` needs the whole grid.
  if (!o.measure)
    for (const double target : kSlabTargets)
      if (whole > target)
        if (const int planes = thickest_within(std::min(budget, target)))
          return {planes, saturated_bytes(slab_bytes(m, o, d, planes, streamed)), {}};
  if (whole <= budget) return {0, saturated_bytes(whole), {}};
  int fit = thickest_within(budget);
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
    // Measures, and a field without a model, need the whole grid: only its estimate counts.
    return o.measure || whole_only
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
    // The model outlives the job: the tree reads an STL's corners in place.
    job.stage("spatial",
              [&] { job.tree.emplace(build_index(job.model, {.borrow_points = true})); });
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

// Marching cubes on the whole grid's φ, with its proof unless a full search is asked for.
void march(Job& job) {
  const McOptions mc{.progress = job.progress, .rounding = job.options.rounding};
  job.stage("marching cubes", [&] {
    if (job.options.validation == FillOptions::Validation::Full) {
      job.mesh = marching_cubes(job.phi, mc);
      return;
    }
    ProvedMesh proved = marching_cubes_proved(job.phi, mc);
    job.mesh = std::move(proved.mesh);
    job.proof = std::move(proved.proof);
  });
}

// Nothing is returned that failed validation.
void validate(Job& job) {
  const FillOptions& o = job.options;
  FillReport& r = job.report;
  if (job.mesh.triangles.empty()) throw InputError(detail::kEmptyLattice);
  round_coordinates(o.rounding, job.mesh);
  r.validation = job.stage("validate", [&] {
    return validate_mesh(job.mesh, {.self_intersections = o.check_self_intersections,
                                    .proof = job.proof ? &*job.proof : nullptr,
                                    .cell_grid = job.grid,
                                    .progress = job.progress});
  });
  detail::require_valid_lattice(r.validation);
}

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

void warn_printability(const FillOptions& o, double voxel, FillReport& r) {
  if (!r.measures) return;
  warn_below(r.measures->wall, o.min_wall, "walls", "--min-wall",
             "thicken them (a lower --porosity, a larger --thickness or --cell)", voxel, r);
  warn_below(r.measures->pore, o.min_pore, "pores", "--min-pore",
             "powder or resin may stay trapped; widen them (a higher --porosity or a larger "
             "--cell)",
             voxel, r);
}

}  // namespace

FillOptions::Validation validation_from_name(std::string_view name) {
  if (name == "proof") return FillOptions::Validation::Proof;
  if (name == "full") return FillOptions::Validation::Full;
  throw InputError("unknown validation '" + std::string(name) + "': use proof or full");
}

const char* validation_name(FillOptions::Validation validation) {
  return validation == FillOptions::Validation::Full ? "full" : "proof";
}

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

FillForecast forecast_fill(const TriangleSoup& model, const FillOptions& options) {
  require_valid(options.units);
  const ModelSize m =
      model_size(options.units.factor() != 1 ? to_millimetres(model, options.units) : model);
  // As fill_to_file() plans it: a grid over the budget streams by slabs.
  return forecast(m, options,
                  plan_memory(m, options, resolve_design(options.design, m.bounds), true));
}

namespace {

// What every entry point settles first: the field job (the options checked, the model in
// millimetres, the design resolved), fill's own options checked, the memory plan.
struct Setup {
  detail::FieldJob field;
  detail::MemoryPlan plan;
  const TriangleSoup& model() const { return field.model(); }
};

void set_up(const TriangleSoup& input, const FillOptions& options, FillResult& result, Setup& s,
            bool streamed = false) {
  s.field = detail::start_field_job(input, options, result.report);
  for (const double limit : {options.min_wall, options.min_pore})
    if (!(limit >= 0 && std::isfinite(limit)))
      throw InputError("min_wall and min_pore must be finite and not negative (0: no limit)");
  if ((options.min_wall > 0 || options.min_pore > 0) && !options.measure)
    throw InputError("min_wall and min_pore are checked against the measures: set measure too");
  result.report.full_field = options.full_field;
  result.resolved = options;
  result.resolved.design = s.field.design;
  s.plan = plan_memory(model_size(s.model()), options, result.resolved.design, streamed);
}

// Islands, measures, validation: the mesh as the field's stages left it, finished.
void finish(Job& job) {
  FillResult& result = job.result;
  const FillOptions& options = job.options;
  job.stage("islands", [&] { detail::remove_islands(job); });
  if (options.measure) {
    result.report.measures = job.stage("measure", [&] {
      return measure_lattice(
          job.phi, job.occupancy.inside,
          {.min_wall = options.min_wall, .min_pore = options.min_pore, .progress = job.progress});
    });
    warn_printability(options, job.grid.spacing, result.report);
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
  Job job(s.model(), options, result, plan_stages(options, s.plan.slab_planes > 0),
          s.plan.slab_planes);
  resolve(job, s.plan);
  if (job.slab_planes > 0) {
    detail::mesh_in_slabs(job);
  } else {
    classify(job);
    compose(job);
    march(job);
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

// The design's own field on the job's grid, its outermost nodes taken as outside so that the
// mesh closes there.
Field design_field(const Job& job) {
  Field phi = sample_field(design_source(job.result.resolved.design), job.grid, job.progress);
  const Grid& g = phi.grid;
  const auto outside = static_cast<float>(g.spacing);
  detail::for_each_border_node(
      g, [&](std::size_t n) { phi.values[n] = std::fmax(phi.values[n], outside); });
  return phi;
}

}  // namespace

FillResult fill_box(const Box3& box, const FillOptions& options) {
  return fill(box_soup(box), options);
}

FillResult fill_field(const Box3& bounds, const FillOptions& options) {
  FillResult result;
  Setup s;
  s.field = detail::start_field_job(bounds, options, result.report);
  result.resolved = options;
  result.resolved.design = s.field.design;
  const Vec3 size = bounds.size();
  const ModelSize m{bounds, 0, size.x * size.y * size.z, 0};
  // No slabs without a model: the whole grid, or a refusal naming a voxel size that fits.
  s.plan = plan_memory(m, options, result.resolved.design, false, true);
  std::vector<detail::PlannedStage> plan{
      {"review", 0.5}, {"field", 30}, {"marching cubes", 7}, {"islands", 6}};
  if (options.measure) plan.push_back({"measure", 35});
  plan.push_back({"validate", 46});
  Job job(s.model(), options, result, std::move(plan), 0);
  resolve(job, s.plan);
  result.report.inside_rule = "none (no model: the design's own field)";
  job.phi = job.stage("field", [&] { return design_field(job); });
  job.occupancy.inside = Mask{job.grid, std::vector<std::uint8_t>(job.phi.values.size(), 1)};
  march(job);
  finish(job);
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
  Job job(s.model(), options, result, plan_stages(options, true, true), s.plan.slab_planes);
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
  Job job(s.model(), options, result, plan_stages(options, true),
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
  Job job(s.model(), options, result,
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
  Job job(s.model(), options, result,
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
