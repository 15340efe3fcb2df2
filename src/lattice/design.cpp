// Stage "design": grading, blending and custom sources on top of the TPMS table, evaluated by
// blocks of rows. Without rotation or a radial warp a layer is separable and its per-axis
// trigonometry is computed once per grid line; otherwise per node.
#include "tpmsfill/lattice/design.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <deque>
#include <filesystem>
#include <memory>
#include <mutex>
#include <string>

#include "core/names.hpp"
#include "lattice/internal/box_samples.hpp"
#include "lattice/internal/polygon_miter.hpp"
#include "lattice/internal/region_distance.hpp"
#include "lattice/internal/tpms_kernel.hpp"
#include "tpmsfill/error.hpp"

namespace tpmsfill {
namespace {

constexpr detail::Named<Graded> kGraded[] = {{Graded::Porosity, "porosity"},
                                             {Graded::Level, "level"},
                                             {Graded::Thickness, "thickness"},
                                             {Graded::Cell, "cell"}};
constexpr detail::Named<RampShape> kRamps[] = {{RampShape::Linear, "linear"},
                                               {RampShape::Radial, "radial"},
                                               {RampShape::Depth, "depth"},
                                               {RampShape::Volume, "volume"}};
constexpr detail::Named<RegionShape> kRegions[] = {{RegionShape::HalfSpace, "half-space"},
                                                   {RegionShape::Slab, "slab"},
                                                   {RegionShape::Sphere, "sphere"},
                                                   {RegionShape::Cylinder, "cylinder"},
                                                   {RegionShape::Polygon, "polygon"}};
constexpr detail::Named<RingJoin> kJoins[] = {{RingJoin::Round, "round"},
                                              {RingJoin::Miter, "miter"}};
constexpr detail::Named<Transition> kTransitions[] = {{Transition::Sigmoid, "sigmoid"},
                                                      {Transition::Beta, "beta"}};

bool finite(Vec3 v) {
  return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
}

Vec3 unit(Vec3 v) {
  const double n = norm(v);
  return n > 0 ? (1.0 / n) * v : Vec3{};
}

const Grading* find_grading(const LatticeDesign& d, Graded what) {
  for (const Grading& g : d.grading)
    if (g.what == what) return &g;
  return nullptr;
}

// ---- ramps --------------------------------------------------------------------------------

// A resolved ramp: coordinate t(p) and the clamped linear value v(t).
struct RampEval {
  RampShape shape = RampShape::Linear;
  Vec3 point, axis;  // axis unit (zero: spherical)
  double from = 0, to = 1, start = 0, end = 0;
  std::shared_ptr<const ScalarVolume> volume;

  explicit RampEval(const Ramp& r)
      : shape(r.shape),
        point(r.point.value_or(Vec3{})),
        axis(unit(r.axis)),
        from(r.from.value_or(0)),
        to(r.to.value_or(1)),
        start(r.start),
        end(r.end),
        volume(r.volume) {}

  // Distance from the axis (or the point), and the unit direction away from it.
  double radius(Vec3 p, Vec3* direction) const {
    Vec3 d = p - point;
    d = d - dot(d, axis) * axis;
    const double r = norm(d);
    if (direction) *direction = r > 0 ? (1.0 / r) * d : Vec3{};
    return r;
  }
  double coordinate(Vec3 p) const {
    if (shape == RampShape::Volume) return sample_volume(*volume, p);
    return shape == RampShape::Linear ? dot(p - point, axis) : radius(p, nullptr);
  }
  double fraction(double t) const { return std::clamp((t - from) / (to - from), 0.0, 1.0); }
  double value(double t) const { return start + (end - start) * fraction(t); }
  // ∫ from `from` to t of dτ / value(τ), for a positive ramp (cell sizes).
  double integral_of_inverse(double t) const {
    const double lo = std::min(from, to), hi = std::max(from, to);
    const double v_lo = value(lo), v_hi = value(hi);
    auto inside = [&](double x) {  // ∫ lo..x, lo ≤ x ≤ hi, over the linear part
      const double slope = (v_hi - v_lo) / (hi - lo);
      if (std::fabs(slope) * (hi - lo) <= 1e-12 * v_lo) return (x - lo) / v_lo;
      return std::log(value(x) / v_lo) / slope;
    };
    double g;
    if (t <= lo)
      g = (t - lo) / v_lo;
    else if (t <= hi)
      g = inside(t);
    else
      g = inside(hi) + (t - hi) / v_hi;
    return from <= to ? g : g - inside(hi);
  }
};

// ---- regions and transitions ---------------------------------------------------------------

// μ, the blended lattice's weight, from the transition coordinate t (0 at the outer edge, 1
// at the inner one). A polygon's Beta peak is measured from its inner ring (seed 004), so its
// growth runs the other way: μ = 1 − g(1 − t).
double blend_weight(const Blend& b, const detail::RegionDistance& region, Vec3 p) {
  const double t = region.transition(p, b.width);
  if (t <= 0 || t >= 1) return t;
  const bool from_inner = b.region.shape == RegionShape::Polygon;
  const double x = from_inner ? 1 - t : t;
  double g = 0;
  if (b.transition == Transition::Beta) {
    const double e = 1.0 / (1.0 - b.peak);
    g = (1.0 + (1.0 - x) * e) * std::pow(x, e);
  } else {
    auto sigma = [](double y) { return 1.0 / (1.0 + std::exp(-10.0 * (y - 0.5))); };
    g = (sigma(x) - sigma(0)) / (sigma(1) - sigma(0));
  }
  return from_inner ? 1 - g : g;
}

}  // namespace

// ---- names -----------------------------------------------------------------------------------

std::string grading_label(const Grading& g) {
  char values[96];
  std::snprintf(values, sizeof values, " %.4g to %.4g", g.ramp.start, g.ramp.end);
  std::string s = std::string(graded_name(g.what)) + values;
  const Ramp& r = g.ramp;
  if (r.shape == RampShape::Depth) {
    s += " by depth";
  } else if (r.shape == RampShape::Volume) {
    s += " by the values of " + (r.volume_file.empty()
                                     ? std::string("a volume")
                                     : std::filesystem::path(r.volume_file).filename().string());
  } else {
    const char* axes[] = {"x", "y", "z"};
    std::string along;
    for (int a = 0; a < 3; ++a)
      if (r.axis[a] != 0 && r.axis[(a + 1) % 3] == 0 && r.axis[(a + 2) % 3] == 0) along = axes[a];
    if (r.shape == RampShape::Radial)
      s += norm(r.axis) == 0 ? " radially" : " radially from the " + along + " axis";
    else
      s += " along " + (along.empty() ? std::string("a direction") : along);
  }
  if (r.from && r.to) {
    char range[96];
    std::snprintf(range, sizeof range,
                  r.shape == RampShape::Volume ? " (%.4g to %.4g)" : " (%.4g to %.4g mm)", *r.from,
                  *r.to);
    s += range;
  }
  return s;
}

std::string_view graded_name(Graded what) {
  return detail::name_of(kGraded, what);
}
std::string_view ramp_name(RampShape shape) {
  return detail::name_of(kRamps, shape);
}
std::string_view ring_join_name(RingJoin join) {
  return detail::name_of(kJoins, join);
}
RingJoin ring_join_from_name(std::string_view name) {
  return detail::from_name(kJoins, name, "ring join");
}
std::string_view region_name(RegionShape shape) {
  return detail::name_of(kRegions, shape);
}
std::string_view transition_name(Transition transition) {
  return detail::name_of(kTransitions, transition);
}
Graded graded_from_name(std::string_view name) {
  return detail::from_name(kGraded, name, "graded quantity");
}
RampShape ramp_from_name(std::string_view name) {
  return detail::from_name(kRamps, name, "ramp");
}
RegionShape region_from_name(std::string_view name) {
  return detail::from_name(kRegions, name, "region");
}
Transition transition_from_name(std::string_view name) {
  return detail::from_name(kTransitions, name, "transition");
}

// ---- validation and resolution ----------------------------------------------------------------

// A porosity target solves the base's level or thickness; a ramp of that quantity would
// override it, and the part would silently miss the porosity asked for.
namespace {
std::string porosity_and(const std::string& graded) {
  return "a porosity target sets the " + graded + ", which the " + graded +
         " grading also sets, so the porosity would not be reached: grade the porosity instead "
         "(--grade porosity A B)";
}
}  // namespace

// A polygon region: at least 3 finite corners, a plane, rings that make a band, and for
// mitered rings a simple outline (its straight skeleton needs one).
void require_valid_polygon(const Region& r) {
  if (r.loop.size() < 3) throw InputError("a polygon region needs at least 3 corners");
  for (const auto& q : r.loop)
    if (!std::isfinite(q[0]) || !std::isfinite(q[1]))
      throw InputError("a polygon region's corners must be finite");
  if (!finite(r.u) || !finite(r.v) || norm(r.u) == 0 ||
      norm(cross(r.u, r.v)) <= 1e-12 * norm(r.u) * norm(r.v))
    throw InputError("a polygon region's u and v must be two non-parallel directions");
  if (!std::isfinite(r.inner) || !std::isfinite(r.outer) || !(r.inner + r.outer > 0))
    throw InputError("a polygon region's rings must make a band: inner + outer > 0 mm");
  double area = 0;
  const std::size_t n = r.loop.size();
  for (std::size_t i = 0; i < n; ++i) {
    const auto a = r.loop[i], b = r.loop[(i + 1) % n];
    area += a[0] * b[1] - a[1] * b[0];
  }
  if (area == 0) throw InputError("a polygon region's outline encloses no area");
  if (r.join == RingJoin::Miter && !detail::is_simple_outline(r.loop))
    throw InputError(
        "mitered rings need a simple outline: no edge may cross or touch another (round joins "
        "take any outline)");
}

void require_valid(const LatticeDesign& d) {
  require_valid(static_cast<const TpmsOptions&>(d));
  if (d.structure) {
    require_valid(*d.structure);
    if (!d.grading.empty())
      throw InputError(
          "grading applies to a TPMS, not to a porous structure (grade its "
          "thresholds instead)");
  }
  bool network = d.style == TpmsStyle::Network && !d.custom,
       sheet = d.style == TpmsStyle::Sheet && !d.custom;
  if (d.blends.size() > kMaxBlends)
    throw InputError(std::to_string(d.blends.size()) + " blends: at most " +
                     std::to_string(kMaxBlends) + " (the limit)");
  for (const Blend& b : d.blends) {
    require_valid(b.tpms);
    (b.tpms.style == TpmsStyle::Network ? network : sheet) = true;
    if (!(b.width > 0) || !std::isfinite(b.width))
      throw InputError("a blend's transition width must be a positive number of millimetres");
    if (!(b.peak > 0 && b.peak < 1))
      throw InputError("a Beta transition's peak must be between 0 and 1");
    const Region& r = b.region;
    if (!finite(r.point) || !finite(r.axis) || !std::isfinite(r.size))
      throw InputError("a blend region's point, axis and size must be finite");
    if (r.shape == RegionShape::Polygon) {
      require_valid_polygon(r);
      continue;
    }
    if (r.shape != RegionShape::Sphere && norm(r.axis) == 0)
      throw InputError(std::string("a ") + std::string(region_name(r.shape)) +
                       " region needs a non-zero axis");
    if (r.shape != RegionShape::HalfSpace && !(r.size > 0))
      throw InputError(std::string("a ") + std::string(region_name(r.shape)) +
                       " region needs a positive size (thickness or radius, mm)");
  }
  for (const Grading& g : d.grading) {
    const std::string what(graded_name(g.what));
    int count = 0;
    for (const Grading& h : d.grading) count += h.what == g.what;
    if (count > 1) throw InputError("the " + what + " is graded twice");
    const Ramp& r = g.ramp;
    if (!finite(r.axis) || (r.point && !finite(*r.point)) || !std::isfinite(r.start) ||
        !std::isfinite(r.end) || (r.from && !std::isfinite(*r.from)) ||
        (r.to && !std::isfinite(*r.to)))
      throw InputError("the " + what + " grading has a value or position that is not finite");
    if (r.shape == RampShape::Linear && norm(r.axis) == 0)
      throw InputError("the " + what + " grading's linear ramp needs a non-zero axis");
    if (r.shape == RampShape::Volume) {
      if (!r.volume) throw InputError("the " + what + " grading's volume ramp has no volume");
      require_valid(*r.volume);
      if (!r.volume->has_physical_size())
        throw InputError("the " + what +
                         " grading's volume has no physical size (spacing): it cannot be placed "
                         "in mm");
    }
    if (r.from && r.to && *r.from == *r.to)
      throw InputError("the " + what + " grading's ramp starts and ends at the same place");
    switch (g.what) {
      case Graded::Porosity:
        if (!(r.start > 0 && r.start < 1 && r.end > 0 && r.end < 1))
          throw InputError("graded porosities must be between 0 and 1");
        if (find_grading(d, Graded::Level) || find_grading(d, Graded::Thickness))
          throw InputError("porosity and level or thickness cannot both be graded");
        if (d.unit == LevelUnit::Raw ||
            std::any_of(d.blends.begin(), d.blends.end(),
                        [](const Blend& b) { return b.tpms.unit == LevelUnit::Raw; }))
          throw InputError(
              "a porosity grading solves levels in mm; it cannot grade a lattice with raw "
              "levels C");
        break;
      case Graded::Level:
        if (!network) throw InputError("level grading needs a network lattice");
        if (d.porosity) throw InputError(porosity_and(what));
        break;
      case Graded::Thickness:
        if (!sheet) throw InputError("thickness grading needs a sheet lattice");
        if (d.porosity) throw InputError(porosity_and(what));
        if (!(r.start > 0 && r.end > 0))
          throw InputError("graded sheet thicknesses must be positive");
        break;
      case Graded::Cell:
        if (!(r.start > 0 && r.end > 0)) throw InputError("graded cell sizes must be positive");
        break;
    }
  }
}

// The ramp with its unset positions taken from `model`: linear ramps span the box along their
// axis, radial ones from its centre to its farthest corner, depth 0 to a quarter of its
// smallest side. `what` names the ramp in errors.
Ramp resolve_ramp(Ramp ramp, const Box3& model, const std::string& what) {
  const bool placed = ramp.shape == RampShape::Depth || ramp.shape == RampShape::Volume;
  if ((ramp.point || placed) && ramp.from && ramp.to) return ramp;
  if (model.empty())
    throw InputError("the " + what + " needs explicit positions (no model to span)");
  const Vec3 centre = model.centre(), size = model.size();
  if (!placed) ramp.point = ramp.point.value_or(ramp.shape == RampShape::Radial ? centre : Vec3{});
  ramp.axis = unit(ramp.axis);
  double lo = 0, hi = 0;
  if (ramp.shape == RampShape::Depth) {
    hi = 0.25 * std::fmin(size.x, std::fmin(size.y, size.z));
  } else if (ramp.shape == RampShape::Volume) {
    if (!ramp.volume) throw InputError("the " + what + " has no volume");
    const RampEval e(ramp);
    lo = HUGE_VAL, hi = -HUGE_VAL;
    detail::for_each_box_sample(model, 16, [&](Vec3 p) {
      const double t = e.coordinate(p);
      lo = std::fmin(lo, t), hi = std::fmax(hi, t);
    });
  } else {
    const RampEval e(ramp);
    lo = ramp.shape == RampShape::Radial ? 0 : HUGE_VAL, hi = -HUGE_VAL;
    for (int c = 0; c < 8; ++c) {
      const Vec3 corner{c & 1 ? model.max.x : model.min.x, c & 2 ? model.max.y : model.min.y,
                        c & 4 ? model.max.z : model.min.z};
      const double t = e.coordinate(corner);
      lo = std::fmin(lo, t), hi = std::fmax(hi, t);
    }
  }
  if (!(hi > lo)) hi = lo + 1;  // a flat model along the ramp: any span will do
  ramp.from = ramp.from.value_or(lo);
  ramp.to = ramp.to.value_or(hi);
  if (*ramp.from == *ramp.to)
    throw InputError("the " + what + " starts and ends at the same place");
  return ramp;
}

double ramp_coordinate(const Ramp& ramp, Vec3 p) {
  if (ramp.shape == RampShape::Depth)
    throw InputError(
        "a depth ramp needs the model's occupancy; ramp_coordinate takes linear, radial or "
        "volume");
  if (ramp.shape == RampShape::Volume && !ramp.volume)
    throw InputError("a volume ramp without its volume");
  return RampEval(ramp).coordinate(p);
}

double ramp_value(const Ramp& resolved, Vec3 p) {
  return RampEval(resolved).value(ramp_coordinate(resolved, p));
}

Threshold ramp_threshold(const Ramp& ramp, std::array<double, 3> size, int counts) {
  if (ramp.shape == RampShape::Depth)
    throw InputError(
        "a threshold cannot follow depth: a structure has no surface to be deep "
        "below (use x, y, z or radial)");
  if (counts < 2 || counts > 16) throw InputError("a threshold ramp takes 2 to 16 coefficients");
  for (double l : size)
    if (!(l > 0) || !std::isfinite(l)) throw InputError("a threshold ramp needs a positive size");
  const RampEval e(
      resolve_ramp(ramp, Box3{{0, 0, 0}, {size[0], size[1], size[2]}}, "threshold ramp"));
  constexpr int kSamples = 16;
  std::vector<double> values;
  for (int k = 0; k < kSamples; ++k)
    for (int j = 0; j < kSamples; ++j)
      for (int i = 0; i < kSamples; ++i) {
        const Vec3 p{(i + 0.5) / kSamples * size[0], (j + 0.5) / kSamples * size[1],
                     (k + 0.5) / kSamples * size[2]};
        values.push_back(e.value(e.coordinate(p)));
      }
  const int degree = std::min(3, counts - 1);
  FitOptions o;
  o.degree = degree;
  return {0,
          fit_bspline(values, {kSamples, kSamples, kSamples}, {counts, counts, counts}, o).volume};
}

LatticeDesign resolve_design(const LatticeDesign& design, const Box3& model) {
  require_valid(design);
  LatticeDesign r = design;
  if (r.structure && !r.custom) {
    if (model.empty() && r.structure->placement == Placement::Stretch)
      throw InputError("a porous structure stretched over the model needs the model's box");
    const UnitCubeMap map = unit_cube_map(*r.structure, model);
    if (r.porosity) r.structure = with_porosity(*r.structure, *r.porosity, map.extent);
    r.custom = porous_source(*r.structure, map);
    return r;  // the base TPMS and its grading do not apply
  }
  static_cast<TpmsOptions&>(r) = resolve_porosity(design);
  for (Blend& b : r.blends) b.tpms = resolve_porosity(b.tpms);
  for (Grading& g : r.grading)
    g.ramp = resolve_ramp(g.ramp, model, std::string(graded_name(g.what)) + " grading's ramp");
  return r;
}

// ---- evaluation -------------------------------------------------------------------------------

namespace detail {
namespace {

// The cell-size warp w(p): along the ramp, dw/dt = T_ref/T(t), so the phase is the integral of
// 1/T and no cell is torn. Its Jacobian J maps the gradient in w to the gradient in p.
struct Warp {
  bool on = false;
  RampEval ramp{Ramp{}};
  double reference = 1;  // T_ref, mm
  int axis = -1;         // linear ramp along a world axis: separable
};

// Where a node is, in world and warped coordinates, with what the Jacobian needs.
struct Frame {
  Vec3 p, w;
  Vec3 direction;      // linear: ramp axis; radial: away from the axis
  double stretch = 1;  // dw/dt along `direction`
  double across = 1;   // radial: U(r)/r, the stretch across the ramp
  double scale = 1;    // local cell / reference cell
  double depth = 0;

  Vec3 gradient(const Warp& warp, Vec3 g) const {
    if (!warp.on) return g;
    const double along = dot(direction, g);
    if (warp.ramp.shape == RampShape::Linear) return g + ((stretch - 1) * along) * direction;
    const Vec3 a = warp.ramp.axis;
    const double axial = dot(a, g);
    return across * g + ((stretch - across) * along) * direction + ((1 - across) * axial) * a;
  }
};

Frame make_frame(const Warp& warp, Vec3 p) {
  Frame f;
  f.p = f.w = p;
  if (!warp.on) return f;
  const RampEval& r = warp.ramp;
  if (r.shape == RampShape::Linear) {
    const double t = r.coordinate(p);
    const double u = r.from + warp.reference * r.integral_of_inverse(t);
    f.direction = r.axis;
    f.w = p + (u - t) * r.axis;
    f.scale = r.value(t) / warp.reference;
    f.stretch = 1 / f.scale;
    return f;
  }
  const double radius = r.radius(p, &f.direction);
  const double u = warp.reference * (r.integral_of_inverse(radius) - r.integral_of_inverse(0));
  f.scale = r.value(radius) / warp.reference;
  f.stretch = 1 / f.scale;
  f.across = radius > 0 ? u / radius : f.stretch;
  f.w = p + (u - radius) * f.direction;
  return f;
}

// A TPMS of the design with what its evaluation on one grid needs.
struct PreparedTpms {
  TpmsLayer tpms;
  bool separable;                              // per-axis tables (no rotation, axis warp)
  std::shared_ptr<const CellSamples> samples;  // porosity grading only
  std::vector<AxisTrig> trig[3];               // separable: per node index along each axis
};

// The design on one grid.
class DesignRows {
 public:
  DesignRows(const LatticeDesign& design, const Grid& grid, const Field* depth);

  // φ_L at the needed nodes of rows [first_row, first_row + row_count).
  void rows(std::size_t first_row, std::size_t row_count, float* values,
            const std::uint8_t* need) const;

 private:
  double ramp_t(const RampEval& r, const Frame& f) const {
    return r.shape == RampShape::Depth ? f.depth : r.coordinate(f.p);
  }
  Frame frame(int i, int j, int k) const;
  double layer_value(const PreparedTpms& L, const Frame& f, int i, int j, int k) const;
  void add_layer(const TpmsOptions& o);
  void table_separable_warp();

  Grid grid_;
  const Field* depth_ = nullptr;
  std::vector<Blend> blends_;
  std::vector<detail::RegionDistance> regions_;  // per blend
  RowFunction custom_;                           // the base, when the design has a custom source
  Warp warp_;
  std::vector<PreparedTpms> layers_;  // base first (absent with a custom source), then the blends
  std::optional<RampEval> porosity_, level_, thickness_;
  bool per_node_frame_ = false;  // the warp is not separable for some layer
  bool plain_ = false;  // one separable layer, nothing graded, blended or refined: see rows()
  std::vector<double> stretch_[3], scale_[3];  // separable warp: per node index along its axis
  std::vector<double> warped_;                 // separable warp: warped coordinate along it
};

DesignRows::DesignRows(const LatticeDesign& design, const Grid& grid, const Field* depth)
    : grid_(grid), depth_(depth), blends_(design.blends) {
  for (const Blend& b : blends_) regions_.emplace_back(b.region);
  if (depth && (!(depth->grid == grid) || depth->values.size() != grid.node_count()))
    throw InputError("design_source: the depth field does not match the grid");
  if (const Grading* g = find_grading(design, Graded::Cell)) {
    warp_.on = true;
    warp_.ramp = RampEval(g->ramp);
    warp_.reference = design.cell.x;
    const Vec3 a = warp_.ramp.axis;
    if (g->ramp.shape == RampShape::Linear)
      for (int axis = 0; axis < 3; ++axis)
        if (std::fabs(a[axis]) == 1) warp_.axis = axis;
  }
  auto ramp = [&](Graded what, std::optional<RampEval>& out) {
    if (const Grading* g = find_grading(design, what)) {
      out.emplace(g->ramp);
      if (g->ramp.shape == RampShape::Depth && !depth)
        throw InputError(
            "a depth ramp needs the depth below the model's surface (design_source's depth)");
    }
  };
  ramp(Graded::Porosity, porosity_);
  ramp(Graded::Level, level_);
  ramp(Graded::Thickness, thickness_);

  if (design.custom)
    custom_ = bind_source(design.custom, grid);
  else
    add_layer(design);
  for (const Blend& b : design.blends) add_layer(b.tpms);
  if (warp_.on && warp_.axis >= 0) table_separable_warp();
  for (PreparedTpms& L : layers_)
    if (L.separable)
      for (int axis = 0; axis < 3; ++axis)
        L.trig[axis] = L.tpms.trig_table(grid, axis, axis == warp_.axis ? &warped_ : nullptr);
  plain_ = !custom_ && layers_.size() == 1 && layers_[0].separable && !layers_[0].tpms.refine &&
           !warp_.on && !porosity_ && !level_ && !thickness_ && !depth_;
}

void DesignRows::add_layer(const TpmsOptions& o) {
  PreparedTpms L{TpmsLayer(o), false, nullptr, {}};
  L.separable = !L.tpms.rotated && (!warp_.on || warp_.axis >= 0);
  if (porosity_) L.samples = shared_cell_samples(o);
  per_node_frame_ = per_node_frame_ || (!L.separable && warp_.on);
  layers_.push_back(std::move(L));
}

// A linear warp along a grid axis moves coordinates along that axis only: the warped
// coordinate, stretch and scale are tabled per node index along it.
void DesignRows::table_separable_warp() {
  const int a = warp_.axis;
  for (int n = 0; n < grid_.dims[a]; ++n) {
    Vec3 p{};
    (a == 0 ? p.x : a == 1 ? p.y : p.z) = grid_.coordinate(a, n);
    const Frame f = make_frame(warp_, p);
    warped_.push_back(f.w[a]);
    stretch_[a].push_back(f.stretch);
    scale_[a].push_back(f.scale);
  }
}

Frame DesignRows::frame(int i, int j, int k) const {
  const Vec3 p = grid_.node(i, j, k);
  Frame f;
  if (per_node_frame_) {
    f = make_frame(warp_, p);
  } else {
    f.p = f.w = p;
    if (warp_.on) {
      const int idx[3] = {i, j, k};
      f.scale = scale_[warp_.axis][idx[warp_.axis]];
    }
  }
  if (depth_) f.depth = depth_->values[grid_.index(i, j, k)];
  return f;
}

double DesignRows::layer_value(const PreparedTpms& L, const Frame& f, int i, int j, int k) const {
  const TpmsLayer& t = L.tpms;
  Vec3 g, q;
  FGrad fg;
  if (L.separable) {
    fg = t.formula(L.trig[0][i], L.trig[1][j], L.trig[2][k]);
    g = t.lattice_gradient(fg);
    if (t.refine)
      q = Vec3{warp_.axis == 0 ? warped_[i] : grid_.coordinate(0, i),
               warp_.axis == 1 ? warped_[j] : grid_.coordinate(1, j),
               warp_.axis == 2 ? warped_[k] : grid_.coordinate(2, k)} -
          t.o.origin;
    if (warp_.on) {
      const int idx[3] = {i, j, k};
      const int a = warp_.axis;
      const double s = stretch_[a][idx[a]];
      g = {a == 0 ? s * g.x : g.x, a == 1 ? s * g.y : g.y, a == 2 ? s * g.z : g.z};
    }
  } else {
    fg = t.at(f.w, q);
    g = f.gradient(warp_, t.o.rotation * t.lattice_gradient(fg));
  }
  const bool network = t.o.style == TpmsStyle::Network;
  double v;
  if (porosity_)
    v = level_for_porosity(*L.samples, t.o.style,
                           std::clamp(porosity_->value(ramp_t(*porosity_, f)), 1e-6, 1 - 1e-6)) *
        f.scale;
  else if (network && level_)
    v = level_->value(ramp_t(*level_, f));
  else if (!network && thickness_)
    v = thickness_->value(ramp_t(*thickness_, f));
  else
    v = (network ? t.o.level : t.o.thickness) * (t.o.porosity ? f.scale : 1.0);
  return t.value(fg, g, q, v);
}

void DesignRows::rows(std::size_t first_row, std::size_t row_count, float* values,
                      const std::uint8_t* need) const {
  if (plain_) {
    // The common design (one TPMS at a fixed level): layer_value() with its frame and its
    // gradings left out, the same arithmetic in the same order, so the same bits.
    const PreparedTpms& L = layers_[0];
    const TpmsLayer& t = L.tpms;
    const double v = t.o.style == TpmsStyle::Network ? t.o.level : t.o.thickness;
    for_each_needed_node(
        grid_, first_row, row_count, need, [&](int i, int j, int k, std::size_t n) {
          const FGrad fg = t.formula(L.trig[0][i], L.trig[1][j], L.trig[2][k]);
          values[n] = static_cast<float>(t.value(fg, t.lattice_gradient(fg), Vec3{}, v));
        });
    return;
  }
  // A custom base writes its values first; the blends then read them back.
  if (custom_) custom_(first_row, row_count, values, need);
  const std::size_t first_blend = custom_ ? 0 : 1;
  for_each_needed_node(grid_, first_row, row_count, need, [&](int i, int j, int k, std::size_t n) {
    const Frame f = frame(i, j, k);
    double phi = custom_ ? values[n] : layer_value(layers_[0], f, i, j, k);
    for (std::size_t b = 0; b < blends_.size(); ++b) {
      const double mu = blend_weight(blends_[b], regions_[b], f.p);
      if (mu <= 0) continue;
      const double other = layer_value(layers_[first_blend + b], f, i, j, k);
      phi = mu >= 1 ? other : (1 - mu) * phi + mu * other;
    }
    values[n] = static_cast<float>(phi);
  });
}

// Cell sizes that follow depth or a volume. A warp cannot: its phase is the integral of 1/T
// along one direction, and a field's level sets give it no direction to integrate along (the
// phase would tear). Instead the design is made at a ladder of fixed cell sizes, neighbours
// at most kScaleStep apart, and at each node the two whose sizes bracket the node's cell size
// are mixed linearly in log size: φ = (1 − s) φ_k + s φ_{k+1}. Where the node's size is one of
// the ladder's, φ is that lattice's own field.
constexpr double kScaleStep = 1.2;
constexpr int kMaxScales = 16;

// The resolved design at one cell size: the cell grading dropped, its cells (blends' too)
// scaled. Levels and thicknesses solved from a porosity scale with the cell (f/|∇f| is a
// length), as the warp scales them, so they are scaled rather than solved again.
LatticeDesign at_cell_size(const LatticeDesign& design, double cell) {
  const double factor = cell / design.cell.x;
  auto scale = [factor](TpmsOptions& t) {
    t.cell = factor * t.cell;
    if (t.porosity) t.level *= factor, t.thickness *= factor, t.porosity.reset();
  };
  LatticeDesign d = design;
  std::erase_if(d.grading, [](const Grading& g) { return g.what == Graded::Cell; });
  scale(d);
  for (Blend& b : d.blends) scale(b.tpms);
  return d;
}

// Mixing two lattices thins their walls: (1 − s)φ_k + sφ_{k+1} is negative over less of space
// than either (the femur at 35 mm, 0.7 asked: 72.8 % void against 69.9 % for one cell size).
// Every pair of neighbouring rungs is the first pair scaled, so the offset that gives the mix
// the first rung's solid fraction is found once, at shares s = i/8, on the first pair's base
// lattices (unrotated, unshifted: a statistic of the type, style, cell and level alone) sampled
// over a box six of the larger cells wide; pair k's is that times its size. Kept for the last
// few lattices asked, since point evaluations make a source per point.
using MixOffsets = std::array<double, 9>;

MixOffsets sample_mix_offsets(const TpmsOptions& small, const TpmsOptions& large) {
  constexpr int kNodes = 48;
  const double side = 6 * std::fmax(large.cell.x, std::fmax(large.cell.y, large.cell.z));
  const Grid grid{.origin = {0, 0, 0}, .spacing = side / kNodes, .dims = {kNodes, kNodes, kNodes}};
  const Field a = sample_field(design_source(LatticeDesign{small}), grid);
  const Field b = sample_field(design_source(LatticeDesign{large}), grid);
  const std::size_t n = a.values.size();
  const auto solid = static_cast<std::size_t>(
      std::count_if(a.values.begin(), a.values.end(), [](float v) { return v < 0; }));
  MixOffsets offset{};
  if (solid == 0 || solid == n) return offset;
  std::vector<double> mix(n);
  for (int i = 1; i < 8; ++i) {
    const double t = i / 8.0;
    for (std::size_t k = 0; k < n; ++k) mix[k] = (1 - t) * a.values[k] + t * b.values[k];
    // The solid-th smallest and the one before: the offset puts the zero between them.
    std::nth_element(mix.begin(), mix.begin() + solid, mix.end());
    const double above = mix[solid];
    const double below = *std::max_element(mix.begin(), mix.begin() + solid);
    offset[i] = -0.5 * (above + below);
  }
  return offset;  // 0 at s = 0 and 1: there each rung is its own lattice
}

MixOffsets mix_offsets(const LatticeDesign& design, double small_cell, double large_cell) {
  auto base = [&](double cell) {
    TpmsOptions t = at_cell_size(design, cell);
    t.origin = {0, 0, 0};
    t.rotation = Mat3{};
    return t;
  };
  const TpmsOptions small = base(small_cell), large = base(large_cell);
  auto same = [](const TpmsOptions& x, const TpmsOptions& y) {
    return x.type == y.type && x.terms == y.terms && x.style == y.style && x.cell == y.cell &&
           x.level == y.level && x.thickness == y.thickness && x.unit == y.unit;
  };
  struct Entry {
    TpmsOptions small, large;
    MixOffsets offset;
  };
  static std::mutex mutex;
  static std::deque<Entry> cache;
  {
    const std::lock_guard<std::mutex> lock(mutex);
    for (const Entry& e : cache)
      if (same(e.small, small) && same(e.large, large)) return e.offset;
  }
  const MixOffsets offset = sample_mix_offsets(small, large);
  const std::lock_guard<std::mutex> lock(mutex);
  cache.push_front({small, large, offset});
  if (cache.size() > 8) cache.pop_back();
  return offset;
}

FieldSource cell_ladder_source(const LatticeDesign& design, const Grading& cell,
                               const Field* depth) {
  const double lo = std::fmin(cell.ramp.start, cell.ramp.end);
  const double hi = std::fmax(cell.ramp.start, cell.ramp.end);
  const int sizes =
      std::clamp(static_cast<int>(std::ceil(std::log(hi / lo) / std::log(kScaleStep) - 1e-9)) + 1,
                 1, kMaxScales);
  const double step = sizes > 1 ? std::log(hi / lo) / (sizes - 1) : 1;
  std::vector<FieldSource> ladder;
  double bound = 0;
  for (int k = 0; k < sizes; ++k) {
    ladder.push_back(design_source(at_cell_size(design, lo * std::exp(k * step)), depth));
    bound = std::fmax(bound, ladder.back().bound);
  }
  const RampEval ramp(cell.ramp);
  const MixOffsets offset = sizes > 1 ? mix_offsets(design, lo, lo * std::exp(step)) : MixOffsets{};
  return {
      .on_grid = [ladder, ramp, depth, lo, step, offset](const Grid& grid) -> RowFunction {
        if (ramp.shape == RampShape::Depth && !depth)
          throw InputError(
              "a depth ramp needs the depth below the model's surface (design_source's depth)");
        std::vector<RowFunction> rows;
        for (const FieldSource& s : ladder) rows.push_back(bind_source(s, grid));
        return [rows, ramp, depth, lo, step, offset, grid](
                   std::size_t first, std::size_t count, float* values, const std::uint8_t* need) {
          const std::size_t nodes = count * static_cast<std::size_t>(grid.dims[0]);
          // Per node: the ladder's rung below its cell size and the share of the one above.
          std::vector<std::uint8_t> rung(nodes, 0), wanted(nodes, 0);
          std::vector<double> share(nodes, 0.0), sum(nodes, 0.0);
          const int top = static_cast<int>(rows.size()) - 1;
          for_each_needed_node(grid, first, count, need, [&](int i, int j, int k, std::size_t n) {
            const double t = ramp.shape == RampShape::Depth ? depth->values[grid.index(i, j, k)]
                                                            : ramp.coordinate(grid.node(i, j, k));
            const double at =
                top > 0 ? std::clamp(std::log(ramp.value(t) / lo) / step, 0.0, double(top)) : 0;
            const int below = std::min(static_cast<int>(at), std::max(top - 1, 0));
            rung[n] = static_cast<std::uint8_t>(below);
            share[n] = at - below;
            wanted[n] = 1;
          });
          std::vector<float> phi(nodes);
          std::vector<std::uint8_t> mask(nodes);
          for (int r = 0; r <= top; ++r) {
            bool any = false;
            for (std::size_t n = 0; n < nodes; ++n) {
              const double w = !wanted[n]         ? 0
                               : rung[n] == r     ? 1 - share[n]
                               : rung[n] + 1 == r ? share[n]
                                                  : 0;
              mask[n] = w > 0;
              any = any || mask[n];
            }
            if (!any) continue;
            rows[r](first, count, phi.data(), mask.data());
            for (std::size_t n = 0; n < nodes; ++n)
              if (mask[n]) sum[n] += (rung[n] == r ? 1 - share[n] : share[n]) * phi[n];
          }
          for (std::size_t n = 0; n < nodes; ++n) {
            if (!wanted[n]) continue;
            const double at = 8 * share[n];
            const int i = std::min(static_cast<int>(at), 7);
            const double shift = (1 - (at - i)) * offset[i] + (at - i) * offset[i + 1];
            values[n] = static_cast<float>(sum[n] + std::exp(rung[n] * step) * shift);
          }
        };
      },
      .bound = bound};
}

}  // namespace
}  // namespace detail

FieldSource design_source(const LatticeDesign& design, const Field* depth) {
  const LatticeDesign resolved = resolve_design(design, Box3{});
  if (const Grading* cell = find_grading(resolved, Graded::Cell);
      cell && !resolved.custom &&
      (cell->ramp.shape == RampShape::Depth || cell->ramp.shape == RampShape::Volume))
    return detail::cell_ladder_source(resolved, *cell, depth);
  double bound = resolved.custom ? resolved.custom.bound : 2 * detail::TpmsLayer(resolved).clamp;
  for (const Blend& b : resolved.blends)
    bound = std::fmax(bound, 2 * detail::TpmsLayer(b.tpms).clamp);
  return {.on_grid = [resolved, depth](const Grid& grid) -> RowFunction {
            auto rows = std::make_shared<const detail::DesignRows>(resolved, grid, depth);
            return [rows](std::size_t first, std::size_t count, float* values,
                          const std::uint8_t* need) { rows->rows(first, count, values, need); };
          },
          .bound = bound};
}

}  // namespace tpmsfill
