// Stage "tpms": names, validation, one TPMS as a field source, porosity by bisection over a
// sampled cell. The design (design.cpp) evaluates its layers with the same TpmsLayer.
#include "tpmsfill/lattice/tpms.hpp"

#include <tbb/parallel_sort.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <deque>
#include <memory>
#include <mutex>
#include <string>

#include "core/names.hpp"
#include "core/parallel.hpp"
#include "lattice/internal/tpms_kernel.hpp"
#include "tpmsfill/error.hpp"

namespace tpmsfill {

namespace {

// Each type's first entry is its name; the later ones are aliases from_name accepts.
constexpr detail::Named<TpmsType> kTypeNames[] = {
    {TpmsType::Primitive, "primitive"}, {TpmsType::Gyroid, "gyroid"},
    {TpmsType::Diamond, "diamond"},     {TpmsType::Iwp, "iwp"},
    {TpmsType::Neovius, "neovius"},     {TpmsType::Frd, "frd"},
    {TpmsType::Lidinoid, "lidinoid"},   {TpmsType::SplitP, "splitp"},
    {TpmsType::Fourier, "fourier"},     {TpmsType::Primitive, "schwarz-p"},
    {TpmsType::Diamond, "schwarz-d"},   {TpmsType::Iwp, "i-wp"},
    {TpmsType::SplitP, "split-p"}};
constexpr detail::Named<TpmsStyle> kStyleNames[] = {{TpmsStyle::Network, "network"},
                                                    {TpmsStyle::Sheet, "sheet"}};

}  // namespace

std::string_view tpms_type_name(TpmsType type) {
  return detail::name_of(kTypeNames, type);
}

TpmsType tpms_type_from_name(std::string_view name) {
  return detail::from_name(kTypeNames, name, "lattice");
}

std::string_view tpms_style_name(TpmsStyle style) {
  return detail::name_of(kStyleNames, style);
}

TpmsStyle tpms_style_from_name(std::string_view name) {
  return detail::from_name(kStyleNames, name, "lattice style");
}

std::string tpms_label(const TpmsOptions& o) {
  const bool raw = o.unit == LevelUnit::Raw;
  char b[96];
  std::string label(tpms_type_name(o.type));
  if (o.type == TpmsType::Fourier) {
    std::snprintf(b, sizeof b, " (%zu term%s)", o.terms.size(), o.terms.size() == 1 ? "" : "s");
    label += b;
  }
  label += ' ';
  label += tpms_style_name(o.style);
  if (o.style == TpmsStyle::Sheet && o.level != 0) {  // walls between two levels
    std::snprintf(b, sizeof b, " between levels %.4g and %.4g %s", -o.level - 0.5 * o.thickness,
                  -o.level + 0.5 * o.thickness, raw ? "(raw C)" : "mm");
    label += b;
  } else if (raw) {
    std::snprintf(b, sizeof b, o.style == TpmsStyle::Network ? " at C = %.4g" : " of |f| < %.4g",
                  o.style == TpmsStyle::Network ? o.level : 0.5 * o.thickness);
    label += b;
  }
  return label;
}

namespace {

// Sums of f's terms, and products of sums by cos a cos b = ½(cos(a + b) + cos(a − b)), so a
// named type's Fourier terms read as its formula does.
using Terms = std::vector<FourierTerm>;

Terms operator+(Terms a, const Terms& b) {
  a.insert(a.end(), b.begin(), b.end());
  return a;
}

Terms operator*(double k, Terms a) {
  for (FourierTerm& t : a) t.amplitude *= k;
  return a;
}

Terms operator*(const Terms& a, const Terms& b) {
  Terms r;
  for (const FourierTerm& s : a)
    for (const FourierTerm& t : b) {
      const double half = 0.5 * s.amplitude * t.amplitude;
      const std::array<int, 3> sum = {s.wave[0] + t.wave[0], s.wave[1] + t.wave[1],
                                      s.wave[2] + t.wave[2]},
                               difference = {s.wave[0] - t.wave[0], s.wave[1] - t.wave[1],
                                             s.wave[2] - t.wave[2]};
      r.push_back({half, sum, s.phase + t.phase});
      r.push_back({half, difference, s.phase - t.phase});
    }
  return r;
}

// cos(n·θ_axis) and sin(n·θ_axis).
Terms cos_of(int axis, int n = 1) {
  std::array<int, 3> w = {0, 0, 0};
  w[axis] = n;
  return {{1, w, 0}};
}

Terms sin_of(int axis, int n = 1) {
  std::array<int, 3> w = {0, 0, 0};
  w[axis] = n;
  return {{1, w, -M_PI / 2}};
}

Terms constant(double c) {
  return {{c, {0, 0, 0}, 0}};
}

}  // namespace

std::vector<FourierTerm> fourier_terms(const TpmsOptions& o) {
  // X, Y, Z's single and double angles; sums over the cyclic permutations as in tpms_kernel.hpp.
  const Terms cX = cos_of(0), cY = cos_of(1), cZ = cos_of(2), sX = sin_of(0), sY = sin_of(1),
              sZ = sin_of(2), c2X = cos_of(0, 2), c2Y = cos_of(1, 2), c2Z = cos_of(2, 2),
              s2X = sin_of(0, 2), s2Y = sin_of(1, 2), s2Z = sin_of(2, 2);
  const Terms pairs_c2 = c2X * c2Y + c2Y * c2Z + c2Z * c2X;
  switch (o.type) {
    case TpmsType::Gyroid:
      return cX * sY + cY * sZ + cZ * sX;
    case TpmsType::Primitive:
      return cX + cY + cZ;
    case TpmsType::Diamond:
      return cX * cY * cZ + (-1.0) * (sX * sY * sZ);
    case TpmsType::Iwp:
      return 2.0 * (cX * cY + cY * cZ + cZ * cX) + (-1.0) * (c2X + c2Y + c2Z);
    case TpmsType::Neovius:
      return 3.0 * (cX + cY + cZ) + 4.0 * (cX * cY * cZ);
    case TpmsType::Frd:
      return 4.0 * (cX * cY * cZ) + (-1.0) * pairs_c2;
    case TpmsType::Lidinoid:
      return 0.5 * (s2X * cY * sZ + s2Y * cZ * sX + s2Z * cX * sY) + (-0.5) * pairs_c2 +
             constant(0.15);
    case TpmsType::SplitP:
      return 1.1 * (s2X * sZ * cY + s2Y * sX * cZ + s2Z * sY * cX) + (-0.2) * pairs_c2 +
             (-0.4) * (c2X + c2Y + c2Z);
    case TpmsType::Fourier:
      return o.terms;
  }
  return {};
}

Mat3 rotation_from_euler(Vec3 degrees) {
  const double k = M_PI / 180.0;
  const double cx = std::cos(k * degrees.x), sx = std::sin(k * degrees.x);
  const double cy = std::cos(k * degrees.y), sy = std::sin(k * degrees.y);
  const double cz = std::cos(k * degrees.z), sz = std::sin(k * degrees.z);
  const Mat3 rx{{1, 0, 0, 0, cx, -sx, 0, sx, cx}};
  const Mat3 ry{{cy, 0, sy, 0, 1, 0, -sy, 0, cy}};
  const Mat3 rz{{cz, -sz, 0, sz, cz, 0, 0, 0, 1}};
  return rz * ry * rx;
}

Vec3 euler_from_rotation(const Mat3& r) {
  // R = Rz·Ry·Rx: R[2][0] = −sin y, R[2][1] = cos y sin x, R[1][0] = cos y sin z.
  // Degrees to 1e-9, so that 30° given reads back as 30, not 29.999999999999996.
  auto deg = [](double radians) {
    return std::round(radians * (180.0 / M_PI) * 1e9) / 1e9 + 0.0;  // + 0.0: no −0
  };
  const double* m = r.m.data();
  const double y = std::asin(std::clamp(-m[6], -1.0, 1.0));
  if (std::fabs(m[6]) > 1 - 1e-12)  // gimbal lock: x and z turn about one axis; all in z
    return {0, deg(y), deg(std::atan2(-m[1], m[4]))};
  return {deg(std::atan2(m[7], m[8])), deg(y), deg(std::atan2(m[3], m[0]))};
}

void require_valid(const TpmsOptions& o) {
  if (o.type != TpmsType::Fourier && !o.terms.empty())
    throw InputError("Fourier terms are for the fourier lattice type, not " +
                     std::string(tpms_type_name(o.type)) + " (its own formula is fixed)");
  if (o.type == TpmsType::Fourier) {
    if (o.terms.empty() || o.terms.size() > kMaxFourierTerms)
      throw InputError("a fourier lattice needs 1 to " + std::to_string(kMaxFourierTerms) +
                       " terms, not " + std::to_string(o.terms.size()));
    bool varies = false;
    for (std::size_t i = 0; i < o.terms.size(); ++i) {
      const FourierTerm& t = o.terms[i];
      const std::string which = "fourier term " + std::to_string(i + 1);
      if (!std::isfinite(t.amplitude) || !std::isfinite(t.phase))
        throw InputError(which + ": its amplitude and phase must be finite");
      for (int w : t.wave)
        if (std::abs(w) > kMaxFourierWave)
          throw InputError(which + ": " + std::to_string(w) +
                           " periods a cell along an axis; at most " +
                           std::to_string(kMaxFourierWave) + " (the limit)");
      varies = varies || (t.amplitude != 0 && t.wave != std::array<int, 3>{0, 0, 0});
    }
    if (!varies)
      throw InputError(
          "a fourier lattice needs a term with a non-zero amplitude and wave: a constant has no "
          "surface");
  }
  if (o.unit == LevelUnit::Raw && o.porosity)
    throw InputError(
        "a porosity target solves the level in mm; give a raw level C or a porosity, not both");
  for (int axis = 0; axis < 3; ++axis)
    if (!(o.cell[axis] > 0) || !std::isfinite(o.cell[axis]))
      throw InputError("the cell size must be a positive number of millimetres");
  if (!std::isfinite(o.level)) throw InputError("the level must be a finite number of millimetres");
  if (o.style == TpmsStyle::Sheet && (!(o.thickness > 0) || !std::isfinite(o.thickness)))
    throw InputError("the sheet thickness must be a positive number of millimetres");
  if (o.style == TpmsStyle::Sheet && o.level != 0 && o.porosity)
    throw InputError(
        "a porosity target solves a centred sheet's thickness; a sheet between two "
        "levels has its thickness already (C2 - C1)");
  if (!std::isfinite(o.origin.x) || !std::isfinite(o.origin.y) || !std::isfinite(o.origin.z))
    throw InputError("the lattice origin must be finite");
  const Mat3 rrt = o.rotation * o.rotation.transposed();
  const auto& r = o.rotation.m;
  const double det = r[0] * (r[4] * r[8] - r[5] * r[7]) - r[1] * (r[3] * r[8] - r[5] * r[6]) +
                     r[2] * (r[3] * r[7] - r[4] * r[6]);
  bool rotation = std::fabs(det - 1) <= 1e-6;
  for (int i = 0; i < 9; ++i) rotation = rotation && std::fabs(rrt.m[i] - Mat3{}.m[i]) <= 1e-6;
  if (!rotation)
    throw InputError(
        "the lattice rotation is not a rotation matrix (orthonormal with determinant +1)");
  if (o.porosity && !(*o.porosity > 0 && *o.porosity < 1))
    throw InputError("the porosity must be between 0 and 1 (e.g. 0.7 for 70 % void)");
}

namespace {

// One TPMS on one grid: per-axis trigonometry tabled when it is not rotated.
struct TpmsRows {
  detail::TpmsLayer layer;
  Grid grid;
  double value;                           // level (network) or thickness (sheet), mm
  std::vector<detail::AxisTrig> trig[3];  // not rotated: per node index along each axis

  TpmsRows(const TpmsOptions& o, const Grid& g)
      : layer(o), grid(g), value(o.style == TpmsStyle::Network ? o.level : o.thickness) {
    if (!layer.rotated)
      for (int axis = 0; axis < 3; ++axis) trig[axis] = layer.trig_table(grid, axis);
  }

  double at(int i, int j, int k) const {
    const detail::TpmsLayer& L = layer;
    detail::FGrad fg;
    Vec3 g, q;
    if (!L.rotated) {
      fg = L.formula(trig[0][i], trig[1][j], trig[2][k]);
      g = L.lattice_gradient(fg);
      if (L.refine) q = grid.node(i, j, k) - L.o.origin;
    } else {
      fg = L.at(grid.node(i, j, k), q);
      g = L.o.rotation * L.lattice_gradient(fg);
    }
    return L.value(fg, g, q, value);
  }

  void rows(std::size_t first_row, std::size_t row_count, float* values,
            const std::uint8_t* need) const {
    for_each_needed_node(grid, first_row, row_count, need, [&](int i, int j, int k, std::size_t n) {
      values[n] = static_cast<float>(at(i, j, k));
    });
  }
};

}  // namespace

FieldSource tpms_source(const TpmsOptions& options) {
  const TpmsOptions o = resolve_porosity(options);
  require_valid(o);
  const double bound = 2 * detail::TpmsLayer(o).clamp;
  return {.on_grid = [o](const Grid& grid) -> RowFunction {
            auto rows = std::make_shared<const TpmsRows>(o, grid);
            return [rows](std::size_t first, std::size_t count, float* values,
                          const std::uint8_t* need) { rows->rows(first, count, values, need); };
          },
          .bound = bound};
}

namespace {

// fn(index, f and its gradient, q) at samples³ cell-centred points q of one unit cell (index
// x fastest), in parallel; the per-axis trigonometry is tabled once. Rotation and origin do not
// change what a cell holds, so they are left out.
template <class F>
void for_each_cell_sample(const detail::TpmsLayer& L, int samples, const F& fn) {
  if (samples < 2) throw InputError("a unit cell needs at least 2 samples per axis");
  std::vector<detail::AxisTrig> t[3];
  for (int axis = 0; axis < 3; ++axis)
    for (int i = 0; i < samples; ++i)
      t[axis].push_back(detail::axis_trig(2 * M_PI * (i + 0.5) / samples));
  const std::size_t n = static_cast<std::size_t>(samples);
  const Vec3 cell = L.o.cell;
  detail::parallel_for(n * n, 16, [&](std::size_t begin, std::size_t end) {
    for (std::size_t jk = begin; jk < end; ++jk)
      for (std::size_t i = 0; i < n; ++i) {
        const std::size_t j = jk % n, k = jk / n;
        const Vec3 q{cell.x * (i + 0.5) / samples, cell.y * (j + 0.5) / samples,
                     cell.z * (k + 0.5) / samples};
        fn(jk * n + i, L.formula(t[0][i], t[1][j], t[2][k]), q);
      }
  });
}

// f̃ (f for raw levels) at samples³ cell-centred points of one unit cell.
std::vector<float> cell_values(const TpmsOptions& options, int samples) {
  require_valid(options);
  const detail::TpmsLayer L(options);
  const std::size_t n = static_cast<std::size_t>(std::max(samples, 0));
  std::vector<float> values(n * n * n);
  for_each_cell_sample(L, samples, [&](std::size_t at, const detail::FGrad& g, Vec3 q) {
    if (options.unit == LevelUnit::Raw) {  // raw levels are read off f itself
      values[at] = static_cast<float>(g.f);
      return;
    }
    double d = detail::tpms_distance(g.f, L.k[0] * g.gx, L.k[1] * g.gy, L.k[2] * g.gz, L.clamp);
    if (L.refine) {  // sheets, as TpmsLayer::distance refines them
      const double qq[3] = {q.x, q.y, q.z};
      const double gq[3] = {L.k[0] * g.gx, L.k[1] * g.gy, L.k[2] * g.gz};
      d = detail::refined_distance(L.formula, L.k, qq, g.f, gq);
    }
    values[at] = static_cast<float>(d);
  });
  return values;
}

CellSamples sample_cell_uncached(const TpmsOptions& options, int samples) {
  CellSamples cell{cell_values(options, samples), {}};
  cell.absolute.resize(cell.values.size());
  std::transform(cell.values.begin(), cell.values.end(), cell.absolute.begin(),
                 [](float v) { return std::fabs(v); });
  tbb::parallel_sort(cell.values.begin(), cell.values.end());
  tbb::parallel_sort(cell.absolute.begin(), cell.absolute.end());
  return cell;
}

}  // namespace

namespace detail {

std::shared_ptr<const CellSamples> shared_cell_samples(const TpmsOptions& options, int samples) {
  require_valid(options);
  // Solving a porosity needs the sorted cell (tens of ms); point evaluations and repeated
  // resolution ask for the same few cells again, so the last ones are kept, and shared
  // rather than copied (7 MB each at 96³).
  struct Entry {
    TpmsType type;
    std::vector<FourierTerm> terms;
    TpmsStyle style;
    Vec3 cell;
    LevelUnit unit;
    int samples;
    std::shared_ptr<const CellSamples> value;
  };
  static std::mutex mutex;
  static std::deque<Entry> cache;
  {
    const std::lock_guard<std::mutex> lock(mutex);
    for (const Entry& e : cache)
      if (e.type == options.type && e.terms == options.terms && e.style == options.style &&
          e.cell == options.cell && e.unit == options.unit && e.samples == samples)
        return e.value;
  }
  auto value = std::make_shared<const CellSamples>(sample_cell_uncached(options, samples));
  const std::lock_guard<std::mutex> lock(mutex);
  cache.push_front(
      {options.type, options.terms, options.style, options.cell, options.unit, samples, value});
  if (cache.size() > 4) cache.pop_back();
  return value;
}

}  // namespace detail

CellSamples sample_cell(const TpmsOptions& options, int samples) {
  return *detail::shared_cell_samples(options, samples);
}

double level_for_porosity(const CellSamples& cell, TpmsStyle style, double porosity) {
  if (!(porosity > 0 && porosity < 1))
    throw InputError("the porosity must be between 0 and 1 (e.g. 0.7 for 70 % void)");
  // The solid fraction is the share of samples below a threshold: the threshold that leaves
  // (1 − porosity)·n samples below it lies between two neighbours of the sorted samples.
  const std::vector<float>& s = style == TpmsStyle::Network ? cell.values : cell.absolute;
  const double n = static_cast<double>(s.size());
  const std::size_t below = static_cast<std::size_t>(
      std::clamp(std::llround((1 - porosity) * n), 1LL, static_cast<long long>(s.size()) - 1));
  const double threshold = 0.5 * (static_cast<double>(s[below - 1]) + s[below]);
  return style == TpmsStyle::Network ? -threshold : 2 * threshold;
}

TpmsOptions resolve_porosity(const TpmsOptions& options) {
  if (!options.porosity) return options;
  require_valid(options);
  TpmsOptions r = options;
  const double v =
      level_for_porosity(*detail::shared_cell_samples(options), options.style, *options.porosity);
  (options.style == TpmsStyle::Network ? r.level : r.thickness) = v;
  return r;
}

double tpms_solid_fraction(const TpmsOptions& options, int samples) {
  const TpmsOptions o = resolve_porosity(options);
  require_valid(o);
  // φ itself at the cell's samples, in whichever unit the levels are.
  const detail::TpmsLayer L(o);
  const double v = o.style == TpmsStyle::Network ? o.level : o.thickness;
  const std::size_t n = static_cast<std::size_t>(std::max(samples, 0));
  std::vector<std::uint8_t> solid(n * n * n, 0);
  for_each_cell_sample(L, samples, [&](std::size_t at, const detail::FGrad& fg, Vec3 q) {
    solid[at] = L.value(fg, L.lattice_gradient(fg), q, v) < 0;
  });
  return static_cast<double>(std::count(solid.begin(), solid.end(), std::uint8_t{1})) /
         static_cast<double>(n * n * n);
}

}  // namespace tpmsfill
