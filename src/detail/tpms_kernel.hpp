/// @file tpms_kernel.hpp
/// @brief The separable TPMS evaluation shared by tpms_field, tpms_value and compose: per-axis
/// trigonometry once per grid line (AxisTrig), then a few multiply-adds per sample.
#pragma once

#include <cmath>
#include <vector>

#include "detail/parallel.hpp"

#include "tpmsfill/tpms.hpp"

namespace tpmsfill::detail {

/// cos/sin of X = 2π(x − origin)/T at one coordinate along one axis.
struct AxisTrig {
  double c = 1, s = 0;
};

inline AxisTrig axis_trig(double x, double origin, double cell) {
  const double X = 2.0 * M_PI * (x - origin) / cell;
  return {std::cos(X), std::sin(X)};
}

/// f and ∂f/∂X, ∂f/∂Y, ∂f/∂Z (dimensionless) from the per-axis values. One row per Lattice.
struct FGrad {
  double f, gx, gy, gz;
};

inline FGrad tpms_f(Lattice type, AxisTrig x, AxisTrig y, AxisTrig z) {
  switch (type) {
    case Lattice::Gyroid:  // cos X sin Y + cos Y sin Z + cos Z sin X
      return {x.c * y.s + y.c * z.s + z.c * x.s, -x.s * y.s + z.c * x.c, x.c * y.c - y.s * z.s,
              y.c * z.c - z.s * x.s};
    case Lattice::Primitive:  // cos X + cos Y + cos Z
      return {x.c + y.c + z.c, -x.s, -y.s, -z.s};
    case Lattice::Diamond:  // cos X cos Y cos Z − sin X sin Y sin Z
      return {x.c * y.c * z.c - x.s * y.s * z.s, -x.s * y.c * z.c - x.c * y.s * z.s,
              -x.c * y.s * z.c - x.s * y.c * z.s, -x.c * y.c * z.s - x.s * y.s * z.c};
  }
  return {0, 0, 0, 0};
}

/// Evaluates φ_TPMS (mm) from per-axis trigonometry; holds the per-options constants.
class TpmsKernel {
 public:
  explicit TpmsKernel(const TpmsOptions& o)
      : o_(o),
        kx_(2.0 * M_PI / o.cell.x),
        ky_(2.0 * M_PI / o.cell.y),
        kz_(2.0 * M_PI / o.cell.z),
        clamp_(std::fmax(o.cell.x, std::fmax(o.cell.y, o.cell.z))) {}

  AxisTrig trig(int axis, double coordinate) const {
    return axis_trig(coordinate, o_.origin[axis], o_.cell[axis]);
  }

  float operator()(AxisTrig x, AxisTrig y, AxisTrig z) const {
    const FGrad g = tpms_f(o_.type, x, y, z);
    const double gx = kx_ * g.gx, gy = ky_ * g.gy, gz = kz_ * g.gz;
    const double grad = std::sqrt(gx * gx + gy * gy + gz * gz);
    // f/|∇f| is a distance near the surface; where |∇f| vanishes (away from it) the ratio
    // blows up, and only its sign matters there, so clamp to ± the largest cell size.
    double d = std::fabs(g.f) >= clamp_ * grad ? std::copysign(clamp_, g.f) : g.f / grad;
    if (o_.style == LatticeStyle::Network) return static_cast<float>(d + o_.level);
    return static_cast<float>(std::fabs(d) - 0.5 * o_.thickness);
  }

  double clamp() const { return clamp_; }

 private:
  TpmsOptions o_;
  double kx_, ky_, kz_;
  double clamp_;
};

/// Per-axis trigonometry for every node coordinate of `grid` along `axis`.
inline std::vector<AxisTrig> grid_trig(const TpmsKernel& kernel, const Grid& grid, int axis) {
  std::vector<AxisTrig> t(static_cast<std::size_t>(grid.dims[axis]));
  for (int i = 0; i < grid.dims[axis]; ++i) t[i] = kernel.trig(axis, grid.coordinate(axis, i));
  return t;
}

/// A Field on `grid` filled row by row in parallel: body(row, out, x, y, z, kernel) writes the
/// dims[0] values of row (j, k) to out, with x the per-node trigonometry along the row and
/// y, z that of the row itself. Serves tpms_field and compose_field alike.
template <class RowBody>
Field evaluate_rows(const Grid& grid, const TpmsOptions& lattice, Progress* progress,
                    const char* stage, const RowBody& body) {
  validate(lattice);
  const TpmsKernel kernel(lattice);
  const auto tx = grid_trig(kernel, grid, 0);
  const auto ty = grid_trig(kernel, grid, 1);
  const auto tz = grid_trig(kernel, grid, 2);
  Field field{grid, std::vector<float>(grid.node_count())};
  const std::size_t rows = static_cast<std::size_t>(grid.dims[1]) * grid.dims[2];
  ProgressCounter counter(progress, stage, rows);
  parallel_for(rows, 64, [&](std::size_t begin, std::size_t end) {
    for (std::size_t row = begin; row < end; ++row) {
      const std::size_t j = row % grid.dims[1], k = row / grid.dims[1];
      body(row, field.values.data() + row * grid.dims[0], tx, ty[j], tz[k], kernel);
    }
    counter.add(end - begin);
  });
  counter.finish();
  return field;
}

}  // namespace tpmsfill::detail
