// The field job: what fill and slice settle before they sample the lattice's field.
#include "lattice/field_job.hpp"

#include <tbb/global_control.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>

#include "lattice/review.hpp"
#include "tpmsfill/error.hpp"
#include "tpmsfill/sampling/distance.hpp"
#include "tpmsfill/scan/porous.hpp"
#include "tpmsfill/units.hpp"

namespace tpmsfill::detail {
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

// A TPMS's surface area per unit volume times its cell size, at porosities near a half, as
// measured in a 20 mm cube of 2 mm cells (docs/benchmarks.md §27): network, then sheet (two
// walls, a little less than twice the network's).
double area_per_volume(const TpmsOptions& t) {
  static constexpr double kNetwork[] = {3.1, 2.2, 3.8, 3.6, 3.3, 4.8, 6.1, 5.2};
  static constexpr double kSheet[] = {5.5, 4.3, 6.6, 6.2, 6.1, 7.6, 8.3, 8.1};
  const double cell = std::fmin(t.cell.x, std::fmin(t.cell.y, t.cell.z));
  if (t.type == TpmsType::Fourier) {
    // Scaled from the primitive's (one period a cell) by the terms' rms frequency, weighted as
    // they weigh in |∇f|: 3.1, 3.8 for the gyroid's and diamond's terms (measured 3.1, 3.8),
    // 5.4 for FRD's (4.8), so a little over where high waves are many.
    double moment = 0, weight = 0;
    for (const FourierTerm& term : t.terms) {
      const double a2 = term.amplitude * term.amplitude;
      const double w2 =
          term.wave[0] * term.wave[0] + term.wave[1] * term.wave[1] + term.wave[2] * term.wave[2];
      if (w2 > 0) moment += a2 * w2, weight += a2;
    }
    const double frequency = weight > 0 ? std::sqrt(moment / weight) : 1;
    const auto primitive = static_cast<std::size_t>(TpmsType::Primitive);
    return (t.style == TpmsStyle::Sheet ? kSheet : kNetwork)[primitive] * frequency / cell;
  }
  const auto type = static_cast<std::size_t>(t.type);
  return (t.style == TpmsStyle::Sheet ? kSheet : kNetwork)[type] / cell;
}

// The options' settings into the report and the design resolved against the model's box.
LatticeDesign describe(const Box3& bounds, std::uint64_t triangles, const FillOptions& o,
                       JobReport& r) {
  r.min_wall = o.min_wall;
  r.min_pore = o.min_pore;
  r.units = units_name(o.units.units);
  r.scale = o.units.scale;
  r.mm_per_unit = o.units.factor();
  r.input_triangles = triangles;
  r.input_bbox = bounds;
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
  r.level_unit = d.unit == LevelUnit::Raw ? "c" : "mm";
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

// The outermost nodes outside, and one more layer so that the band never reaches the grid's
// faces.
void require_padding(const GridOptions& grid) {
  if (grid.padding < 2) throw InputError("the grid padding must be at least 2 voxels");
}

}  // namespace

FieldJob start_field_job(const TriangleSoup& input, const FillOptions& options, JobReport& report) {
  require_valid(options.units);
  require_valid(options.design);
  require_valid(ComposeOptions{.skin = options.skin});  // fail before any work
  require_padding(options.grid);
  FieldJob job;
  job.input = &input;
  if (options.units.factor() != 1) job.in_mm = to_millimetres(input, options.units);
  job.design = describe(bounding_box(job.model()), job.model().triangles.size(), options, report);
  return job;
}

FieldJob start_field_job(const Box3& bounds, const FillOptions& options, JobReport& report) {
  static const TriangleSoup no_model;
  require_valid(options.units);
  require_valid(options.design);
  require_padding(options.grid);
  if (options.units.factor() != 1)
    throw InputError("a field meshed without a model has its bounds in mm: units do not apply");
  if (options.skin > 0) throw InputError("a skin follows a model's surface: there is no model");
  if (depth_reach(options.design) > 0)
    throw InputError("depth ramps grade by the depth below a model's surface: there is no model");
  FieldJob job;
  job.input = &no_model;
  job.design = describe(bounds, 0, options, report);
  return job;
}

void record_classification(const FillOptions& o, const Occupancy::PlaneCounts& c, bool any_inside,
                           JobReport& r) {
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

std::optional<FillPart::SolvedPorosity> solve_porosity_with_skin(const FillOptions& o,
                                                                 const MeshIndex& tree,
                                                                 LatticeDesign& d, JobReport& r) {
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

void apply_solved_porosity(const FillPart::SolvedPorosity& s, LatticeDesign& d, JobReport& r) {
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

void warn_porosity(const LatticeDesign& d, double got, JobReport& r) {
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

std::pair<double, double> seconds_range(double on_two) {
  const auto cores = static_cast<double>(
      tbb::global_control::active_value(tbb::global_control::max_allowed_parallelism));
  const double middle = on_two * 2.0 / std::max(cores, 1.0);
  return {0.5 * middle, 2.0 * middle};
}

}  // namespace tpmsfill::detail
