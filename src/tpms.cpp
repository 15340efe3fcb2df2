// Stage "tpms": names, validation, porosity by bisection over a sampled cell. The field itself
// is evaluated by the lattice design's row evaluator (detail/lattice_rows.hpp), of which a
// plain TPMS is the simplest case.
#include "tpmsfill/tpms.hpp"

#include <tbb/parallel_sort.h>

#include <algorithm>
#include <cmath>
#include <deque>
#include <memory>
#include <mutex>
#include <string>

#include "detail/names.hpp"
#include "detail/parallel.hpp"
#include "detail/tpms_kernel.hpp"
#include "tpmsfill/error.hpp"
#include "tpmsfill/lattice.hpp"

namespace tpmsfill {

namespace {

// Each type's first entry is its name; the later ones are aliases from_name accepts.
constexpr detail::Named<Lattice> kLatticeNames[] = {{Lattice::Primitive, "primitive"},
                                                    {Lattice::Gyroid, "gyroid"},
                                                    {Lattice::Diamond, "diamond"},
                                                    {Lattice::Iwp, "iwp"},
                                                    {Lattice::Neovius, "neovius"},
                                                    {Lattice::Frd, "frd"},
                                                    {Lattice::Lidinoid, "lidinoid"},
                                                    {Lattice::SplitP, "splitp"},
                                                    {Lattice::Primitive, "schwarz-p"},
                                                    {Lattice::Diamond, "schwarz-d"},
                                                    {Lattice::Iwp, "i-wp"},
                                                    {Lattice::SplitP, "split-p"}};
constexpr detail::Named<LatticeStyle> kStyleNames[] = {{LatticeStyle::Network, "network"},
                                                       {LatticeStyle::Sheet, "sheet"}};

}  // namespace

std::string_view lattice_name(Lattice type) {
  return detail::name_of(kLatticeNames, type);
}

Lattice lattice_from_name(std::string_view name) {
  return detail::from_name(kLatticeNames, name, "lattice");
}

std::string_view lattice_style_name(LatticeStyle style) {
  return detail::name_of(kStyleNames, style);
}

LatticeStyle lattice_style_from_name(std::string_view name) {
  return detail::from_name(kStyleNames, name, "lattice style");
}

std::string lattice_label(const TpmsOptions& o) {
  return std::string(lattice_name(o.type)) + " " + std::string(lattice_style_name(o.style));
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

void validate(const TpmsOptions& o) {
  for (int axis = 0; axis < 3; ++axis)
    if (!(o.cell[axis] > 0) || !std::isfinite(o.cell[axis]))
      throw InputError("the cell size must be a positive number of millimetres");
  if (!std::isfinite(o.level)) throw InputError("the level must be a finite number of millimetres");
  if (o.style == LatticeStyle::Sheet && (!(o.thickness > 0) || !std::isfinite(o.thickness)))
    throw InputError("the sheet thickness must be a positive number of millimetres");
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

float tpms_value(Vec3 p, const TpmsOptions& options) {
  return lattice_value(p, LatticeDesign{options});
}

FieldRange tpms_range(const TpmsOptions& options) {
  const double c = std::fmax(options.cell.x, std::fmax(options.cell.y, options.cell.z));
  if (options.style == LatticeStyle::Network)
    return {static_cast<float>(-c + options.level), static_cast<float>(c + options.level)};
  return {static_cast<float>(-0.5 * options.thickness),
          static_cast<float>(c - 0.5 * options.thickness)};
}

Field tpms_field(const Grid& grid, const TpmsOptions& options, Progress* progress) {
  return lattice_field(grid, LatticeDesign{options}, nullptr, progress);
}

namespace {

// f̃ at samples³ cell-centred points of one unit cell (rotation and origin do not matter).
std::vector<float> cell_values(const TpmsOptions& options, int samples) {
  validate(options);
  if (samples < 2) throw InputError("sample_cell: at least 2 samples per axis");
  std::vector<detail::AxisTrig> t[3];
  for (int axis = 0; axis < 3; ++axis)
    for (int i = 0; i < samples; ++i)
      t[axis].push_back(detail::axis_trig(2 * M_PI * (i + 0.5) / samples));
  const double k[3] = {2 * M_PI / options.cell.x, 2 * M_PI / options.cell.y,
                       2 * M_PI / options.cell.z};
  const double clamp = std::fmax(options.cell.x, std::fmax(options.cell.y, options.cell.z));
  const bool refine = detail::refines(options);
  const std::size_t n = static_cast<std::size_t>(samples);
  std::vector<float> values(n * n * n);
  detail::parallel_for(n * n, 16, [&](std::size_t begin, std::size_t end) {
    for (std::size_t jk = begin; jk < end; ++jk)
      for (std::size_t i = 0; i < n; ++i) {
        const detail::FGrad g = detail::tpms_f(options.type, t[0][i], t[1][jk % n], t[2][jk / n]);
        double d = detail::tpms_distance(g.f, k[0] * g.gx, k[1] * g.gy, k[2] * g.gz, clamp);
        if (refine) {  // as LatticeRows does for sheets
          const double q[3] = {options.cell.x * (i + 0.5) / samples,
                               options.cell.y * ((jk % n) + 0.5) / samples,
                               options.cell.z * ((jk / n) + 0.5) / samples};
          const double gq[3] = {k[0] * g.gx, k[1] * g.gy, k[2] * g.gz};
          d = detail::refined_distance(options.type, k, q, g.f, gq);
        }
        values[jk * n + i] = static_cast<float>(d);
      }
  });
  return values;
}

}  // namespace

static CellSamples sample_cell_uncached(const TpmsOptions& options, int samples) {
  CellSamples cell{cell_values(options, samples), {}};
  cell.absolute.resize(cell.values.size());
  std::transform(cell.values.begin(), cell.values.end(), cell.absolute.begin(),
                 [](float v) { return std::fabs(v); });
  tbb::parallel_sort(cell.values.begin(), cell.values.end());
  tbb::parallel_sort(cell.absolute.begin(), cell.absolute.end());
  return cell;
}

namespace detail {

std::shared_ptr<const CellSamples> shared_cell_samples(const TpmsOptions& options, int samples) {
  validate(options);
  // Solving a porosity needs the sorted cell (tens of ms); point evaluations and repeated
  // resolution ask for the same few cells again, so the last ones are kept, and shared
  // rather than copied (7 MB each at 96³).
  struct Entry {
    Lattice type;
    LatticeStyle style;
    Vec3 cell;
    int samples;
    std::shared_ptr<const CellSamples> value;
  };
  static std::mutex mutex;
  static std::deque<Entry> cache;
  {
    const std::lock_guard<std::mutex> lock(mutex);
    for (const Entry& e : cache)
      if (e.type == options.type && e.style == options.style && e.cell == options.cell &&
          e.samples == samples)
        return e.value;
  }
  auto value = std::make_shared<const CellSamples>(sample_cell_uncached(options, samples));
  const std::lock_guard<std::mutex> lock(mutex);
  cache.push_front({options.type, options.style, options.cell, samples, value});
  if (cache.size() > 4) cache.pop_back();
  return value;
}

}  // namespace detail

CellSamples sample_cell(const TpmsOptions& options, int samples) {
  return *detail::shared_cell_samples(options, samples);
}

double level_for_porosity(const CellSamples& cell, LatticeStyle style, double porosity) {
  if (!(porosity > 0 && porosity < 1))
    throw InputError("the porosity must be between 0 and 1 (e.g. 0.7 for 70 % void)");
  // The solid fraction is the share of samples below a threshold: the threshold that leaves
  // (1 − porosity)·n samples below it lies between two neighbours of the sorted samples.
  const std::vector<float>& s = style == LatticeStyle::Network ? cell.values : cell.absolute;
  const double n = static_cast<double>(s.size());
  const std::size_t below = static_cast<std::size_t>(
      std::clamp(std::llround((1 - porosity) * n), 1LL, static_cast<long long>(s.size()) - 1));
  const double threshold = 0.5 * (static_cast<double>(s[below - 1]) + s[below]);
  return style == LatticeStyle::Network ? -threshold : 2 * threshold;
}

TpmsOptions resolve_porosity(const TpmsOptions& options) {
  if (!options.porosity) return options;
  validate(options);
  TpmsOptions r = options;
  const double v =
      level_for_porosity(*detail::shared_cell_samples(options), options.style, *options.porosity);
  (options.style == LatticeStyle::Network ? r.level : r.thickness) = v;
  return r;
}

double lattice_solid_fraction(const TpmsOptions& options, int samples) {
  const TpmsOptions o = resolve_porosity(options);
  const std::vector<float> values = cell_values(o, samples);
  const bool network = o.style == LatticeStyle::Network;
  const float threshold = static_cast<float>(network ? -o.level : 0.5 * o.thickness);
  const std::size_t solid =
      static_cast<std::size_t>(std::count_if(values.begin(), values.end(), [&](float v) {
        return (network ? v : std::fabs(v)) < threshold;
      }));
  return static_cast<double>(solid) / static_cast<double>(values.size());
}

}  // namespace tpmsfill
