// Stage "slice": fill()'s field on one plane per layer, traced by marching squares.
#include "tpmsfill/slice.hpp"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <map>
#include <optional>
#include <string>
#include <tuple>
#include <utility>

#include "core/job_progress.hpp"
#include "core/stage_progress.hpp"
#include "lattice/field_job.hpp"
#include "lattice/field_planes.hpp"
#include "lattice/review.hpp"
#include "sampling/rounded_grid.hpp"
#include "tpmsfill/error.hpp"
#include "tpmsfill/grid.hpp"
#include "tpmsfill/lattice/compose.hpp"
#include "tpmsfill/mesh/clean.hpp"
#include "tpmsfill/sampling/classify.hpp"
#include "tpmsfill/sampling/spatial.hpp"
#include "tpmsfill/sampling/voxel.hpp"
#include "tpmsfill/units.hpp"

namespace tpmsfill {
namespace {

constexpr std::uint32_t kNone = std::numeric_limits<std::uint32_t>::max();

// The preflight's model of a slice's time on 2 cores: per plane node of each layer (its slab's
// inside test and band distances), per contour point (tracing and the exact check).
constexpr double kSliceSecondsPerSample = 80e-9;
constexpr double kSliceSecondsPerPoint = 2e-6;

// One plane's marching squares. Square (i, j) has corners c0 (i, j), c1 (i+1, j),
// c2 (i+1, j+1), c3 (i, j+1), counter-clockwise; edge e of the square joins corner e to corner
// e+1. Walking a square's border counter-clockwise, the solid is left at an "exit" edge and
// entered at an "entry" edge; a segment from an exit to an entry has the solid on its left.
class Tracer {
 public:
  Tracer(const Field& plane, const detail::RoundedGrid& held)
      : g_(plane.grid),
        held_(held),
        v_(plane.values.data()),
        nx_(static_cast<std::size_t>(g_.dims[0])),
        ny_(static_cast<std::size_t>(g_.dims[1])),
        edge_vertex_(2 * nx_ * ny_, kNone) {}

  std::vector<Contour> trace() {
    for (std::size_t j = 0; j + 1 < ny_; ++j)
      for (std::size_t i = 0; i + 1 < nx_; ++i) square(i, j);
    return loops();
  }

 private:
  bool inside(std::size_t i, std::size_t j) const { return v_[i + nx_ * j] < 0; }

  // Edge e of square (i, j): its id (horizontal edges first, then vertical ones by their lower
  // node) and its vertex, made on first use.
  std::uint32_t vertex(std::size_t i, std::size_t j, int e) {
    const int axis = e % 2 == 0 ? 0 : 1;
    const std::size_t ei = i + (e == 1 ? 1 : 0), ej = j + (e == 2 ? 1 : 0);
    std::uint32_t& id = edge_vertex_[ei + nx_ * ej + (axis ? nx_ * ny_ : 0)];
    if (id != kNone) return id;
    const std::size_t n0 = ei + nx_ * ej, n1 = n0 + (axis ? nx_ : 1);
    const double v0 = v_[n0], v1 = v_[n1];
    const double t = detail::edge_crossing(v0, v1, 0);
    const int at[2] = {static_cast<int>(ei), static_cast<int>(ej)};
    const double c0 = g_.coordinate(axis, at[axis]), c1 = g_.coordinate(axis, at[axis] + 1);
    // As the file holds it: the other coordinate on its held node line, this one strictly
    // inside the held edge (detail::RoundedGrid), so contours stay simple once written.
    double p[2];
    p[1 - axis] = held_.node(1 - axis, at[1 - axis]);
    p[axis] = held_.inside_edge(axis, at[axis], c0 + t * (c1 - c0));
    id = static_cast<std::uint32_t>(points_.size());
    points_.push_back({p[0], p[1]});
    next_.push_back(kNone);
    return id;
  }

  void square(std::size_t i, std::size_t j) {
    const bool c[4] = {inside(i, j), inside(i + 1, j), inside(i + 1, j + 1), inside(i, j + 1)};
    int exits[2], entries[2], n_exit = 0, n_entry = 0;
    for (int e = 0; e < 4; ++e) {
      if (c[e] && !c[(e + 1) % 4]) exits[n_exit++] = e;
      if (!c[e] && c[(e + 1) % 4]) entries[n_entry++] = e;
    }
    if (n_exit == 0) return;
    if (n_exit == 1) return link(i, j, exits[0], entries[0]);
    // Two solid corners on one diagonal: the asymptotic decider, as marching cubes decides a
    // cube face (values rounded to float once, products exact in double, a tie separates).
    const double d[4] = {v_[i + nx_ * j], v_[i + 1 + nx_ * j], v_[i + 1 + nx_ * (j + 1)],
                         v_[i + nx_ * (j + 1)]};
    const bool first_diagonal = c[0];
    const double in = first_diagonal ? d[0] * d[2] : d[1] * d[3];
    const double out = first_diagonal ? d[1] * d[3] : d[0] * d[2];
    const bool joined = in > out;
    // Joined: each exit meets the next entry, cutting off the empty corner between them;
    // separated: the entry before it, cutting off its own solid corner.
    for (int k = 0; k < 2; ++k) {
      const int e = exits[k];
      link(i, j, e, joined ? (e + 1) % 4 : (e + 3) % 4);
    }
  }

  void link(std::size_t i, std::size_t j, int exit, int entry) {
    const std::uint32_t a = vertex(i, j, exit), b = vertex(i, j, entry);
    next_[a] = b;
  }

  // Every vertex has one segment out and one in (its two squares), so following `next_`
  // from any vertex comes back to it. Contours start at their first-made vertex.
  std::vector<Contour> loops() const {
    std::vector<Contour> out;
    std::vector<std::uint8_t> seen(points_.size(), 0);
    for (std::uint32_t start = 0; start < points_.size(); ++start) {
      if (seen[start]) continue;
      Contour c;
      std::uint32_t v = start;
      do {
        seen[v] = 1;
        c.points.push_back(points_[v]);
        v = next_[v];
      } while (v != start && v != kNone);
      if (v == kNone) throw Error("trace_contours: an open contour (a bug)");
      c.area = signed_area(c.points);
      out.push_back(std::move(c));
    }
    return out;
  }

  const Grid& g_;
  const detail::RoundedGrid& held_;
  const float* v_;
  std::size_t nx_, ny_;
  std::vector<std::uint32_t> edge_vertex_;
  std::vector<Vec2> points_;
  std::vector<std::uint32_t> next_;
};

// The plane's x and y as a file holds them (its z is no contour's coordinate).
detail::RoundedGrid held_plane(const Grid& grid, CoordinateRounding rounding) {
  Grid plane = grid;
  plane.dims[2] = 1;
  plane.origin.z = 0;
  return {plane, rounding, detail::HeldFile::Layers};
}

// trace_contours with its checks done and the held grid made once for every layer.
std::vector<Contour> trace_plane(const Field& plane, const detail::RoundedGrid& held) {
  const Grid& g = plane.grid;
  if (g.dims[2] != 1 || g.dims[0] < 2 || g.dims[1] < 2 || plane.values.size() != g.node_count())
    throw InputError("trace_contours: the field is not one plane of at least 2 x 2 nodes");
  const std::size_t nx = g.dims[0], ny = g.dims[1];
  for (std::size_t i = 0; i < nx; ++i)
    for (std::size_t j : {std::size_t{0}, ny - 1})
      if (!(plane.values[i + nx * j] > 0))
        throw InputError("trace_contours: a node on the plane's border is not outside");
  for (std::size_t j = 0; j < ny; ++j)
    for (std::size_t i : {std::size_t{0}, nx - 1})
      if (!(plane.values[i + nx * j] > 0))
        throw InputError("trace_contours: a node on the plane's border is not outside");
  return Tracer(plane, held).trace();
}

// Layer m's centre height: its bottom start + m·L plus half a layer.
double layer_centre(double start, double L, std::uint64_t m) {
  return start + (static_cast<double>(m) + 0.5) * L;
}

}  // namespace

std::vector<Contour> trace_contours(const Field& plane, CoordinateRounding rounding) {
  return trace_plane(plane, held_plane(plane.grid, rounding));
}

void require_valid(const SliceOptions& options) {
  if (!(options.layer > 0) || !std::isfinite(options.layer))
    throw InputError("the layer thickness must be a positive number of millimetres");
  if (options.start && !std::isfinite(*options.start))
    throw InputError("the first layer's height must be a finite number of millimetres");
}

std::uint64_t layer_count(const Box3& model, const SliceOptions& options) {
  require_valid(options);
  const double L = options.layer;
  const double span = model.max.z - options.start.value_or(model.min.z);
  const double n = std::ceil(span / L);
  // A million layers is a metre at a micron: more is a thickness in the wrong unit, and would
  // run for days (a material layer takes 0.03-1 s, docs/benchmarks.md §22).
  if (n > 1e6) {
    char what[160];
    std::snprintf(what, sizeof what,
                  "%.3g layers of %g mm for a %g mm tall part (more than a million): is the layer "
                  "thickness in mm?",
                  n, L, span);
    throw InputError(what);
  }
  return n >= 1 ? static_cast<std::uint64_t>(n) : std::uint64_t{1};
}

namespace {

// One layer's plane: fill()'s grid's x and y nodes at height z.
Grid layer_plane(const Grid& grid, double z) {
  return {{grid.origin.x, grid.origin.y, z}, grid.spacing, {grid.dims[0], grid.dims[1], 1}};
}

// Depth below the surface for the layers' planes, which lie between fill's node planes. fill's
// grid planes within the depth ramps' reach are classified once each as the layers rise, and
// kept as 2D squared distance transforms; a layer node's depth is its distance to the nearest
// outside node of those planes and of its own plane. That is exact over that set of nodes (a
// 3D transform is the smallest of each plane's 2D one plus the height between), and costs a
// layer a pass over the planes in reach instead of classifying them again.
class DepthPlanes {
 public:
  DepthPlanes(const MeshIndex& tree, InsideRule rule, const Grid& grid, double reach)
      : tree_(tree), rule_(rule), grid_(grid), reach_(reach) {}

  // The grid planes layers in [z_lo, z_hi] read, classified; those below them dropped.
  void prepare(double z_lo, double z_hi) {
    const int lo = std::max(first(z_lo), 0), hi = std::min(last(z_hi), grid_.dims[2] - 1);
    d2_.erase(d2_.begin(), d2_.lower_bound(lo));
    std::vector<int> missing;
    for (int k = lo; k <= hi; ++k)
      if (!d2_.count(k)) missing.push_back(k);
    std::vector<std::vector<float>> made(missing.size());
    tbb::parallel_for(std::size_t{0}, missing.size(), [&](std::size_t m) {
      Grid plane = grid_;
      plane.z_offset = missing[m];
      plane.dims[2] = 1;
      Field d = planar_distances(classify_grid(tree_, plane, {.rule = rule_}).inside);
      for (float& v : d.values) v *= v;
      made[m] = std::move(d.values);
    });
    for (std::size_t m = 0; m < missing.size(); ++m) d2_[missing[m]] = std::move(made[m]);
  }

  Field depth(const Mask& inside) const {
    Field out = planar_distances(inside);
    const double z = inside.grid.coordinate(2, 0);
    for (float& v : out.values) v *= v;
    for (int k = first(z); k <= last(z); ++k) {
      const double dz = z - grid_.coordinate(2, k);
      const float h2 = static_cast<float>(dz * dz);
      const auto it = d2_.find(k);
      if (it == d2_.end()) {  // beyond the grid: every node there is outside
        for (float& v : out.values) v = std::min(v, h2);
        continue;
      }
      const std::vector<float>& d2 = it->second;
      for (std::size_t n = 0; n < out.values.size(); ++n)
        out.values[n] = std::min(out.values[n], d2[n] + h2);
    }
    for (float& v : out.values) v = std::sqrt(v);
    return out;
  }

  // Distances within one plane. Beyond a one-plane grid the transform would see outside nodes
  // one voxel above and below; counting them as inside leaves the plane's own nodes, and the
  // plane's border nodes (fill's padding) are outside, so no distance reaches past it.
  static Field planar_distances(const Mask& plane) {
    return distance_transform(plane, /*beyond_grid_set=*/true);
  }

  // Planes held at most: those within reach above and below a layer, and a batch's spread.
  static double planes_held(double reach, double spacing) { return 2 * (reach / spacing + 2) + 8; }

 private:
  int first(double z) const {
    return static_cast<int>(std::ceil((z - reach_ - grid_.origin.z) / grid_.spacing));
  }
  int last(double z) const {
    return static_cast<int>(std::floor((z + reach_ - grid_.origin.z) / grid_.spacing));
  }

  const MeshIndex& tree_;
  InsideRule rule_;
  const Grid& grid_;
  double reach_;
  std::map<int, std::vector<float>> d2_;
};

// Refuses a job whose layers at once do not fit: per layer, the slab's mask and band
// temporaries (4 bytes a node) and the plane's fields and contour tables (about 40 bytes a
// node, 8 more with depth); the depth ramps' grid planes (4 bytes a node each); the model and
// its tree.
void require_budget(const FillOptions& options, SliceReport& report, std::size_t at_once,
                    double depth_planes, std::size_t model_triangles) {
  const double plane = static_cast<double>(report.plane_nodes);
  const double bytes = static_cast<double>(at_once) * plane *
                           (report.slab_planes * 4 + 40 + (depth_planes > 0 ? 8 : 0)) +
                       plane * depth_planes * 4 +
                       static_cast<double>(model_triangles) * detail::kBytesPerInputTriangle +
                       detail::kFixedBytes;
  report.job.estimated_memory_bytes = static_cast<std::uint64_t>(std::min(bytes, 1.8e19));
  const double budget =
      static_cast<double>(options.memory_budget ? options.memory_budget : default_memory_budget());
  if (bytes <= budget) return;
  const double fixed =
      static_cast<double>(model_triangles) * detail::kBytesPerInputTriangle + detail::kFixedBytes;
  // The rest grows with the plane's nodes, about as 1/voxel²: the voxel that fits.
  char fit[120] = "the input alone exceeds it";
  if (fixed < budget)
    std::snprintf(fit, sizeof fit, "a --voxel of %.4g mm or more fits",
                  report.job.grid.spacing * std::sqrt((bytes - fixed) / (budget - fixed)) * 1.02);
  char text[320];
  std::snprintf(text, sizeof text,
                "slicing needs about %s (%zu layers at once, each a slab of %d planes of "
                "%llu nodes) but the memory budget is %s; %s",
                detail::memory_text(bytes).c_str(), at_once, report.slab_planes,
                static_cast<unsigned long long>(report.plane_nodes),
                detail::memory_text(budget).c_str(), fit);
  throw ResourceError(text);
}

// Layers that start above the model's bottom leave its lowest part out, ones far below it are
// empty, and layers a millimetre thick are no printer's (a thickness meant in µm): say so.
void warn_layers(double start, double L, JobReport& r) {
  const double bottom = r.input_bbox.min.z, top = r.input_bbox.max.z;
  if (start < top && start + 0.5 * L > top) {
    char text[240];
    std::snprintf(text, sizeof text,
                  "layers %g mm thick: the first one's centre (z = %g mm) lies above the model's "
                  "top (%g mm), so no layer meets it (--layer is in mm: 30 um is --layer 0.03)",
                  L, start + 0.5 * L, top);
    throw InputError(text);
  }
  if (L >= 1) {
    char text[200];
    std::snprintf(text, sizeof text,
                  "layers %g mm thick make %.0f layer(s) of this %.3g mm tall model: printers use "
                  "0.02 to 0.2 mm (--layer is in mm: 30 um is --layer 0.03)",
                  L, std::ceil((top - std::min(start, top)) / L), top - bottom);
    r.warnings.push_back(text);
  }
  if (start < bottom - L) {
    char text[200];
    std::snprintf(text, sizeof text,
                  "layers start at z = %g mm, %.4g mm below the model's bottom (%g mm): the first "
                  "%.0f layer(s) are empty",
                  start, bottom - start, bottom, std::floor((bottom - start) / L));
    r.warnings.push_back(text);
  }
  if (start >= top) {
    char text[160];
    std::snprintf(text, sizeof text,
                  "the first layer starts at z = %g mm, at or above the model's top (%g mm)", start,
                  top);
    throw InputError(text);
  }
  if (start <= bottom) return;
  char text[200];
  std::snprintf(text, sizeof text,
                "layers start at z = %g mm, above the model's bottom (%g mm): its lowest %.4g mm "
                "are not sliced",
                start, bottom, start - bottom);
  r.warnings.push_back(text);
}

// A layer's figures into the report, after the exact check of its contours.
void record_layer(const Layer& layer, const detail::SampledPlanes& plane, double L,
                  SliceReport& report, Occupancy::PlaneCounts& totals, bool& any_inside) {
  std::uint64_t checked = 0;
  if (const std::uint64_t bad =
          count_contour_defects(layer.contours, layer.field.grid.spacing, &checked))
    throw ValidationError("layer " + std::to_string(layer.index) +
                          " at z = " + std::to_string(layer.z) + " mm: " + std::to_string(bad) +
                          " pairs of contour segments cross or touch (a bug)");
  report.segment_pairs_checked += checked;
  LayerSummary s{.z = layer.z, .area = layer.area};
  for (const Contour& c : layer.contours) {
    (c.outer() ? s.outer : s.holes) += 1;
    s.points += c.points.size();
  }
  report.layers.push_back(s);
  report.contours += s.outer + s.holes;
  report.holes += s.holes;
  report.points += s.points;
  report.volume += layer.area * L;
  JobReport& r = report.job;
  Occupancy::PlaneCounts c = plane.counts.front();
  c.volume *= L / layer.field.grid.spacing;  // the section's area × L
  totals += c;
  any_inside = any_inside || std::find(plane.inside.values.begin(), plane.inside.values.end(),
                                       std::uint8_t{1}) != plane.inside.values.end();
  r.band_nodes += plane.band_nodes;
  r.distance_queries += plane.band_nodes;
}

// The layers, a few at once (each parallel inside too), handed to the sink in order.
void slice_layers(const detail::FieldPlanes& job, const Grid& grid, double start, double L,
                  std::uint64_t from, std::uint64_t to, bool whole, SliceReport& report,
                  const LayerSink& sink, Progress* progress, DepthPlanes* depth,
                  const detail::RoundedGrid& held) {
  Occupancy::PlaneCounts totals;
  bool any_inside = false;
  const std::size_t at_once = detail::slabs_at_once();
  std::vector<Layer> batch;
  std::vector<detail::SampledPlanes> planes;
  for (std::uint64_t first = from; first < to; first += at_once) {
    const std::size_t n = static_cast<std::size_t>(std::min<std::uint64_t>(at_once, to - first));
    batch.assign(n, Layer{});
    planes.assign(n, {});
    if (depth) depth->prepare(layer_centre(start, L, first), layer_centre(start, L, first + n - 1));
    tbb::parallel_for(std::size_t{0}, n, [&](std::size_t b) {
      Layer& layer = batch[b];
      layer.index = first + b;
      layer.bottom = start + static_cast<double>(layer.index) * L;
      layer.top = start + static_cast<double>(layer.index + 1) * L;
      layer.z = layer_centre(start, L, layer.index);
      planes[b] = detail::sample_planes(job, layer_plane(grid, layer.z));
      layer.field = std::move(planes[b].phi);
      layer.contours = trace_plane(layer.field, held);
      for (const Contour& c : layer.contours) layer.area += c.area;
    });
    for (std::size_t b = 0; b < n; ++b) {
      record_layer(batch[b], planes[b], L, report, totals, any_inside);
      sink(batch[b]);
    }
    detail::report_or_cancel(
        progress, static_cast<double>(first + n - from) / static_cast<double>(to - from));
  }
  // As fill reports it (the parity rule's warning; no volume refused, when this is the whole
  // stack: a share of it may hold none), the sections' volume.
  detail::record_classification(job.options, totals, any_inside || !whole, report.job);
}

}  // namespace

SliceReport slice(const TriangleSoup& input, const FillOptions& options,
                  const SliceOptions& slice_options, const LayerSink& sink) {
  const double L = slice_options.layer;
  require_valid(slice_options);  // before any work
  SliceReport report;
  JobReport& r = report.job;
  const detail::FieldJob field = detail::start_field_job(input, options, r);
  const TriangleSoup& model = field.model();
  report.layer = L;
  const InsideRule rule = options.inside.value_or(InsideRule::Winding);
  std::vector<detail::PlannedStage> plan{{"review", 0.5}};
  for (detail::PlannedStage& s : detail::index_stages(options)) plan.push_back(std::move(s));
  plan.push_back({"slice", 85});
  detail::JobProgress job(slice_options.progress ? slice_options.progress : options.progress, plan);
  detail::StageClock stage(r, job);

  report.resolved = options;
  report.resolved.design = field.design;
  LatticeDesign& design = report.resolved.design;
  Grid grid;
  stage("review", [&] {
    grid = make_grid(r.input_bbox, options.grid);
    for (std::string& w : review_design(
             design, r.input_bbox, {.voxel = grid.spacing, .input_units = options.units.units}))
      r.warnings.push_back(std::move(w));
  });
  r.grid = grid;
  // A grid finer than the layer file's coordinates where the part sits cannot be written
  // simple: refused now, before any work.
  const detail::RoundedGrid held = held_plane(grid, slice_options.rounding);
  // Depth ramps read fill's grid planes around each layer (DepthPlanes), so the layer's own
  // slab needs only the band's reach.
  const double reach = detail::depth_reach(design);
  const int halo = detail::band_width(options, grid.spacing);
  report.slab_planes = 2 * halo + 1;
  report.plane_nodes = static_cast<std::uint64_t>(grid.dims[0]) * grid.dims[1];
  const double start = slice_options.start.value_or(r.input_bbox.min.z);
  const std::uint64_t count = layer_count(r.input_bbox, slice_options);
  const std::uint64_t from = slice_options.first_layer,
                      to = slice_options.end_layer ? slice_options.end_layer : count;
  if (from >= to || to > count)
    throw InputError("layers " + std::to_string(from) + " to " + std::to_string(to) +
                     " are not a range of the " + std::to_string(count) + " layers");
  const bool whole = from == 0 && to == count;
  warn_layers(start, L, r);
  require_budget(options, report, detail::slabs_at_once(),
                 reach > 0 ? DepthPlanes::planes_held(reach, grid.spacing) : 0,
                 model.triangles.size());
  if (slice_options.preflight) {
    SliceForecast f{.layers = count, .samples = report.plane_nodes * count};
    f.points =
        detail::output_area(detail::model_size(model), report.resolved, detail::Count::Expected) /
        (L * grid.spacing);
    // Seconds on 2 cores (docs/benchmarks.md §26: the femur and the tube of §4 sliced).
    std::tie(f.seconds_low, f.seconds_high) = detail::seconds_range(
        kSliceSecondsPerSample * static_cast<double>(f.samples) + kSliceSecondsPerPoint * f.points +
        1e-6 * static_cast<double>(model.triangles.size()));
    slice_options.preflight(f);
  }

  // Auto: the input as it is, unless a row of some layer's slab finds it open or inside out.
  detail::IndexedModel indexed;
  detail::index_for_rule(
      model, options, indexed, r, stage, to - from,
      [&](std::uint64_t m) {
        return detail::widened(layer_plane(grid, layer_centre(start, L, from + m)), halo);
      },
      slice_options.any_unbalanced, job.get());
  detail::solve_porosity_with_skin(options, *indexed.tree, design, r);
  stage("slice", [&] {
    std::optional<DepthPlanes> depth;
    if (reach > 0) depth.emplace(*indexed.tree, rule, grid, reach);
    detail::FieldPlanes field{*indexed.tree, rule, options, design, halo};
    if (depth) field.depth = [&](const Mask& inside) { return depth->depth(inside); };
    slice_layers(field, grid, start, L, from, to, whole, report, sink, job.get(),
                 depth ? &*depth : nullptr, held);
  });
  r.samples = report.plane_nodes * (to - from);
  if (whole) detail::warn_porosity(design, report.porosity(), r);
  job.finish();
  return report;
}

}  // namespace tpmsfill
