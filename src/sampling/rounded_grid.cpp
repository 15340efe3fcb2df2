#include "sampling/rounded_grid.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <string>

#include "tpmsfill/error.hpp"

namespace tpmsfill::detail {
namespace {

constexpr double kMicrometre = 1e-3;   // 3MF's step, mm
constexpr double kSixDecimals = 1e-6;  // the layer files' text's step, mm
constexpr int kStepsPerVoxel = 4;

// The gap between the float nearest `x` and the next float away from zero.
double float_step(double x) {
  const float f = std::fabs(static_cast<float>(x));
  return static_cast<double>(std::nextafter(f, std::numeric_limits<float>::infinity())) -
         static_cast<double>(f);
}

// The next held value above (up) or below `r`, itself held. A 3MF value stands on a whole
// micrometre as lib3mf truncates it (six decimals on a whole 1e-6 mm), so the search steps by
// those (or floats, where those are coarser) until rounding leaves r behind.
double held_neighbour(CoordinateRounding rounding, double r, bool up) {
  const double direction = up ? 1.0 : -1.0;
  if (rounding == CoordinateRounding::Float)
    return static_cast<double>(std::nextafter(  // both floats: the float overload
        static_cast<float>(r),
        static_cast<float>(direction) * std::numeric_limits<float>::infinity()));
  const double step = held_step(rounding, r);
  for (int k = 1; k <= 16; ++k) {
    const double q = held(rounding, r + direction * k * step);
    if (up ? q > r : q < r) return q;
  }
  return r;  // none found: the caller's range check refuses the grid
}

const char* held_format(CoordinateRounding rounding, HeldFile file) {
  switch (rounding) {
    case CoordinateRounding::ThreeMf:
      return "3MF (micrometres, as lib3mf writes floats)";
    case CoordinateRounding::SixDecimals:
      return "ASCII CLI or SVG (six decimals)";
    default:
      return file == HeldFile::Layers ? "binary CLI (32-bit floats)" : "STL (32-bit floats)";
  }
}

[[noreturn]] void refuse(CoordinateRounding rounding, HeldFile file, double magnitude,
                         double voxel) {
  char text[600];
  std::snprintf(text, sizeof text,
                "the grid reaches %.6g mm from the origin, where %s holds a coordinate only "
                "every %.3g mm: too coarse for a %.6g mm voxel (a voxel must span at least %d of "
                "those steps); move the part nearer the origin, use a voxel of at least %.3g mm, "
                "or write %s",
                magnitude, held_format(rounding, file), held_step(rounding, magnitude), voxel,
                kStepsPerVoxel, finest_held_voxel(rounding, magnitude),
                file == HeldFile::Layers ? "ASCII CLI or SVG, which hold six decimals"
                                         : "PLY, OBJ or OFF, which hold doubles");
  throw InputError(text);
}

// The largest |coordinate| of the grid's nodes along `axis`.
double reach(const Grid& grid, int axis) {
  return std::max(std::fabs(grid.coordinate(axis, 0)),
                  std::fabs(grid.coordinate(axis, grid.dims[axis] - 1)));
}

}  // namespace

double held_step(CoordinateRounding rounding, double magnitude) {
  switch (rounding) {
    case CoordinateRounding::None:
      return 0;
    case CoordinateRounding::Float:
      return float_step(magnitude);
    case CoordinateRounding::ThreeMf:
      return std::max(kMicrometre, float_step(magnitude));
    case CoordinateRounding::SixDecimals:
      return std::max(kSixDecimals, std::nextafter(std::fabs(magnitude),
                                                   std::numeric_limits<double>::infinity()) -
                                        std::fabs(magnitude));
  }
  return 0;
}

double finest_held_voxel(CoordinateRounding rounding, double magnitude) {
  return kStepsPerVoxel * held_step(rounding, magnitude);
}

void require_held_grid(const Grid& grid, CoordinateRounding rounding, HeldFile file) {
  if (rounding == CoordinateRounding::None) return;
  for (int a = 0; a < 3; ++a) {
    const double m = reach(grid, a);
    if (!(grid.spacing >= finest_held_voxel(rounding, m))) refuse(rounding, file, m, grid.spacing);
  }
}

RoundedGrid::RoundedGrid(const Grid& grid, CoordinateRounding rounding, HeldFile file)
    : grid_(grid), rounding_(rounding) {
  if (rounding == CoordinateRounding::None) return;
  require_held_grid(grid, rounding, file);
  for (int a = 0; a < 3; ++a) {
    const auto n = static_cast<std::size_t>(grid.dims[a]);
    node_[a].resize(n);
    low_[a].resize(n);
    high_[a].resize(n);
    for (std::size_t i = 0; i < n; ++i)
      node_[a][i] = held(rounding, grid.coordinate(a, static_cast<int>(i)));
    for (std::size_t i = 0; i + 1 < n; ++i) {
      low_[a][i] = held_neighbour(rounding, node_[a][i], true);
      high_[a][i] = held_neighbour(rounding, node_[a][i + 1], false);
      // Four steps a voxel leave room; this guards the rounding's own irregularities.
      if (!(node_[a][i] < low_[a][i] && low_[a][i] <= high_[a][i] && high_[a][i] < node_[a][i + 1]))
        refuse(rounding, file, reach(grid, a), grid.spacing);
    }
  }
}

}  // namespace tpmsfill::detail
