// Seed 003's structures: the fitted C and its thresholds as a field in mm, and porosity.
#include "tpmsfill/scan/porous.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "core/names.hpp"
#include "tpmsfill/error.hpp"

namespace tpmsfill {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

void require_valid_spline(const BSplineVolume& s, const std::string& what) {
  if (s.degree < 1 || s.degree > 7) throw InputError(what + ": the degree must be 1 to 7");
  std::size_t count = 1;
  for (int a = 0; a < 3; ++a) {
    if (s.counts[a] <= s.degree)
      throw InputError(what + ": " + std::to_string(s.counts[a]) +
                       " coefficients along an axis, not more than the degree " +
                       std::to_string(s.degree));
    const std::vector<double>& k = s.knots[a];
    if (k.size() != std::size_t(s.counts[a] + s.degree + 1))
      throw InputError(what + ": the knot vector does not match the coefficient count");
    for (std::size_t i = 0; i < k.size(); ++i)
      if (!std::isfinite(k[i]) || (i > 0 && k[i] < k[i - 1]))
        throw InputError(what + ": the knots are not finite and non-decreasing");
    for (int i = 0; i <= s.degree; ++i)
      if (k[i] != 0 || k[k.size() - 1 - i] != 1)
        throw InputError(what + ": the knots are not clamped to [0, 1]");
    count *= std::size_t(s.counts[a]);
  }
  if (s.coefficients.size() != count)
    throw InputError(what + ": " + std::to_string(s.coefficients.size()) +
                     " coefficients where the counts need " + std::to_string(count));
  for (double c : s.coefficients)
    if (!std::isfinite(c)) throw InputError(what + ": a coefficient is not finite");
}

// A threshold along one row of nodes (u[n], v, w).
void threshold_line(const Threshold& t, const std::vector<double>& u, double v, double w,
                    double* out) {
  if (t.spline)
    bspline_line(*t.spline, u, v, w, out);
  else
    std::fill(out, out + u.size(), t.constant);
}

double unit_coordinate(const UnitCubeMap& map, int axis, double x) {
  const double t = (x - map.origin[axis]) / map.extent[axis];
  return map.tile ? t - std::floor(t) : t;
}

// φ from C, |∇C| in mm and the thresholds at one point (see porous.hpp).
double structure_phi(const PorousStructure& s, double c, double gradient, double t_low,
                     double t_high, double bound) {
  double numerator = 0;
  if (s.type == StructureType::Solid)
    numerator = std::max(t_low - c, c - t_high);
  else if (s.sheet_thickness > 0)
    numerator = std::fabs(c - t_low) - 0.5 * s.sheet_thickness * gradient;
  else
    numerator = c - t_low;
  const double phi = gradient > 0 ? numerator / gradient : std::copysign(bound, numerator);
  return std::clamp(phi, -bound, bound);
}

// C, |∇C| in mm and the thresholds at the centres of samples³ cells of the unit cube, as φ's
// numerators need them: one entry per sample, each holding {C, |∇C|, t_low, t_high}.
std::vector<std::array<double, 4>> cube_samples(const PorousStructure& s,
                                                std::array<double, 3> extent, int samples) {
  std::vector<double> u(static_cast<std::size_t>(samples));
  for (int i = 0; i < samples; ++i) u[i] = (i + 0.5) / samples;
  std::vector<std::array<double, 4>> out(u.size() * u.size() * u.size());
  std::vector<double> c(u.size()), lo(u.size()), hi(u.size());
  std::vector<std::array<double, 3>> g(u.size());
  const bool solid = s.type == StructureType::Solid;
  for (int k = 0; k < samples; ++k)
    for (int j = 0; j < samples; ++j) {
      bspline_line(s.field, u, u[j], u[k], c.data(), g.data());
      threshold_line(solid ? s.t1 : s.t0, u, u[j], u[k], lo.data());
      threshold_line(solid ? s.t2 : s.t0, u, u[j], u[k], hi.data());
      for (int i = 0; i < samples; ++i) {
        const double gx = g[i][0] / extent[0], gy = g[i][1] / extent[1], gz = g[i][2] / extent[2];
        out[i + u.size() * (j + u.size() * k)] = {c[i], std::sqrt(gx * gx + gy * gy + gz * gz),
                                                  lo[i], hi[i]};
      }
    }
  return out;
}

}  // namespace

Threshold fitted_threshold(const ScalarVolume& grid, std::array<int, 3> counts) {
  require_valid(grid);
  FitOptions o;
  o.degree = std::min({3, counts[0] - 1, counts[1] - 1, counts[2] - 1});
  if (o.degree < 1) throw InputError("a threshold field needs at least 2 coefficients per axis");
  for (int a = 0; a < 3; ++a) counts[a] = std::min(counts[a], grid.dims[a]);
  return {0, fit_bspline(grid.values, grid.dims, counts, o).volume};
}

double threshold_value(const Threshold& t, double u, double v, double w) {
  return t.spline ? bspline_value(*t.spline, u, v, w) : t.constant;
}

void require_valid(const PorousStructure& s) {
  require_valid_spline(s.field, "the field C");
  for (const Threshold* t : {&s.t0, &s.t1, &s.t2})
    if (t->spline) require_valid_spline(*t->spline, "a threshold field");
  auto finite_or_spline = [](const Threshold& t) { return t.spline || std::isfinite(t.constant); };
  if (s.type == StructureType::Solid) {
    if (!s.t1.spline && !s.t2.spline && !(s.t1.constant <= s.t2.constant))
      throw InputError("a solid needs t1 <= t2, not " + std::to_string(s.t1.constant) + " > " +
                       std::to_string(s.t2.constant));
    if (!finite_or_spline(s.t1) && !finite_or_spline(s.t2))
      throw InputError("a solid needs a finite t1 or t2 (t1 <= C <= t2 would be everything)");
    if ((!s.t2.spline && s.t2.constant == -kInf) || (!s.t1.spline && s.t1.constant == kInf) ||
        std::isnan(s.t1.constant) || std::isnan(s.t2.constant))
      throw InputError("a solid with t2 = -infinity or t1 = +infinity is empty");
  } else {
    if (!finite_or_spline(s.t0)) throw InputError("a surface needs a finite t0");
    if (!(s.sheet_thickness >= 0) || !std::isfinite(s.sheet_thickness))
      throw InputError("a sheet thickness must be >= 0 and finite");
  }
  const int given = int(s.size[0] > 0) + int(s.size[1] > 0) + int(s.size[2] > 0);
  for (double l : s.size)
    if (!(l >= 0) || !std::isfinite(l))
      throw InputError("the structure's size must be >= 0 and finite, mm");
  if (given != 0 && given != 3)
    throw InputError("the structure's size must be given on all three axes or none");
  if (s.placement == Placement::Tile && given == 0)
    throw InputError("tiling needs the structure's size (the cell), mm");
}

UnitCubeMap unit_cube_map(const PorousStructure& s, const Box3& model) {
  UnitCubeMap map;
  map.origin = model.min;
  if (s.placement == Placement::Tile) {
    map.extent = s.size;
    map.tile = true;
  } else {
    for (int a = 0; a < 3; ++a) map.extent[a] = std::max(model.max[a] - model.min[a], 1e-9);
  }
  return map;
}

FieldSource porous_source(const PorousStructure& s, const UnitCubeMap& map) {
  require_valid(s);
  double bound = 0;  // twice the largest knot span, mm
  for (int a = 0; a < 3; ++a)
    bound = std::max(bound, 2 * map.extent[a] / (s.field.counts[a] - s.field.degree));
  FieldSource source;
  source.bound = bound;
  source.on_grid = [s, map, bound](const Grid& grid) -> RowFunction {
    std::vector<double> u(static_cast<std::size_t>(grid.dims[0]));
    for (int i = 0; i < grid.dims[0]; ++i) u[i] = unit_coordinate(map, 0, grid.node(i, 0, 0).x);
    return [s, map, bound, u, grid](std::size_t first_row, std::size_t row_count, float* values,
                                    const std::uint8_t* need) {
      const std::size_t nx = u.size();
      std::vector<double> c(nx), lo(nx), hi(nx);
      std::vector<std::array<double, 3>> g(nx);
      const bool solid = s.type == StructureType::Solid;
      for (std::size_t r = 0; r < row_count; ++r) {
        const std::size_t offset = r * nx;
        if (need && std::none_of(need + offset, need + offset + nx, [](auto b) { return b != 0; }))
          continue;
        const std::size_t row = first_row + r;
        const Vec3 p = grid.node(0, static_cast<int>(row % grid.dims[1]),
                                 static_cast<int>(row / grid.dims[1]));
        const double v = unit_coordinate(map, 1, p.y), w = unit_coordinate(map, 2, p.z);
        bspline_line(s.field, u, v, w, c.data(), g.data());
        threshold_line(solid ? s.t1 : s.t0, u, v, w, lo.data());
        threshold_line(solid ? s.t2 : s.t0, u, v, w, hi.data());
        for (std::size_t i = 0; i < nx; ++i) {
          const double gx = g[i][0] / map.extent[0], gy = g[i][1] / map.extent[1],
                       gz = g[i][2] / map.extent[2];
          values[offset + i] = static_cast<float>(
              structure_phi(s, c[i], std::sqrt(gx * gx + gy * gy + gz * gz), lo[i], hi[i], bound));
        }
      }
    };
  };
  return source;
}

double porous_solid_share(const PorousStructure& s, std::array<double, 3> extent, int samples) {
  require_valid(s);
  if (s.type == StructureType::Surface && s.sheet_thickness == 0) return 0;
  std::size_t solid = 0;
  const std::vector<std::array<double, 4>> all = cube_samples(s, extent, samples);
  for (const auto& x : all) solid += structure_phi(s, x[0], x[1], x[2], x[3], kInf) <= 0;
  return static_cast<double>(solid) / static_cast<double>(all.size());
}

PorousStructure with_porosity(const PorousStructure& s, double porosity,
                              std::array<double, 3> extent, int samples) {
  require_valid(s);
  if (!(porosity > 0 && porosity < 1))
    throw InputError("a porosity must be between 0 and 1 (exclusive), not " +
                     std::to_string(porosity));
  const std::vector<std::array<double, 4>> all = cube_samples(s, extent, samples);
  // The offset each sample needs to be solid; the (1 − porosity) quantile makes that share so.
  std::vector<double> need(all.size());
  for (std::size_t n = 0; n < all.size(); ++n) {
    const auto& [c, gradient, lo, hi] = all[n];
    need[n] = s.type == StructureType::Solid
                  ? std::max(lo - c, c - hi)
                  : (gradient > 0 ? 2 * std::fabs(c - lo) / gradient : kInf);
  }
  const std::size_t keep = static_cast<std::size_t>(std::llround((1 - porosity) * need.size()));
  const std::size_t at = std::clamp<std::size_t>(keep, 1, need.size()) - 1;
  std::nth_element(need.begin(), need.begin() + static_cast<std::ptrdiff_t>(at), need.end());
  const double delta = need[at];
  if (!std::isfinite(delta))
    throw InputError("no threshold reaches a porosity of " + std::to_string(porosity) +
                     ": the field is flat over too much of the cube");
  PorousStructure out = s;
  if (s.type == StructureType::Surface) {
    out.sheet_thickness = std::max(delta, 0.0);
    return out;
  }
  for (Threshold* t : {&out.t1, &out.t2}) {
    const double shift = t == &out.t1 ? -delta : delta;
    if (t->spline)
      for (double& c : t->spline->coefficients) c += shift;  // partition of unity: t + shift
    else if (std::isfinite(t->constant))
      t->constant += shift;
  }
  return out;
}

std::string structure_label(const PorousStructure& s) {
  auto value = [](const Threshold& t) {
    if (t.spline) return std::string("a field");
    char b[32];
    std::snprintf(b, sizeof b, "%.4g", t.constant);
    return std::string(b);
  };
  std::string label = "scanned-field ";
  if (s.type == StructureType::Solid) {
    const bool open_low = !s.t1.spline && std::isinf(s.t1.constant);
    label += open_low ? "solid C <= t2 (t2 = " + value(s.t2)
                      : "solid t1 <= C <= t2 (t1 = " + value(s.t1) + ", t2 = " + value(s.t2);
  } else {
    char b[32];
    std::snprintf(b, sizeof b, "%.4g", s.sheet_thickness);
    label += s.sheet_thickness > 0
                 ? "sheet |C - t0| <= " + std::string(b) + " mm / 2 (t0 = " + value(s.t0)
                 : "surface C = t0 (t0 = " + value(s.t0);
  }
  const auto& c = s.field.counts;
  return label + "; " + std::to_string(c[0]) + "x" + std::to_string(c[1]) + "x" +
         std::to_string(c[2]) + " coefficients of degree " + std::to_string(s.field.degree) + ")";
}

constexpr detail::Named<StructureType> kStructureTypes[] = {{StructureType::Solid, "solid"},
                                                            {StructureType::Surface, "surface"}};
constexpr detail::Named<Placement> kPlacements[] = {{Placement::Stretch, "stretch"},
                                                    {Placement::Tile, "tile"}};

std::string_view structure_type_name(StructureType type) {
  return detail::name_of(kStructureTypes, type);
}
std::string_view placement_name(Placement placement) {
  return detail::name_of(kPlacements, placement);
}
StructureType structure_type_from_name(std::string_view name) {
  return detail::from_name(kStructureTypes, name, "structure type");
}
Placement placement_from_name(std::string_view name) {
  return detail::from_name(kPlacements, name, "placement");
}

}  // namespace tpmsfill
