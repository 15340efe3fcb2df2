// Stage "tpms": the lattice field, evaluated separably (detail/tpms_kernel.hpp).
#include "tpmsfill/tpms.hpp"

#include <cmath>
#include <string>

#include "detail/parallel.hpp"
#include "detail/tpms_kernel.hpp"
#include "tpmsfill/error.hpp"

namespace tpmsfill {

std::string_view lattice_name(Lattice type) {
  switch (type) {
    case Lattice::Gyroid:
      return "gyroid";
    case Lattice::Primitive:
      return "primitive";
    case Lattice::Diamond:
      return "diamond";
  }
  return "unknown";
}

Lattice lattice_from_name(std::string_view name) {
  for (Lattice t : {Lattice::Gyroid, Lattice::Primitive, Lattice::Diamond})
    if (name == lattice_name(t)) return t;
  if (name == "schwarz-p") return Lattice::Primitive;
  throw InputError("unknown lattice '" + std::string(name) +
                   "' (known: gyroid, primitive, diamond)");
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
}

float tpms_value(Vec3 p, const TpmsOptions& options) {
  const detail::TpmsKernel kernel(options);
  return kernel(kernel.trig(0, p.x), kernel.trig(1, p.y), kernel.trig(2, p.z));
}

FieldRange tpms_range(const TpmsOptions& options) {
  const double c = detail::TpmsKernel(options).clamp();
  if (options.style == LatticeStyle::Network)
    return {static_cast<float>(-c + options.level), static_cast<float>(c + options.level)};
  return {static_cast<float>(-0.5 * options.thickness),
          static_cast<float>(c - 0.5 * options.thickness)};
}

Field tpms_field(const Grid& grid, const TpmsOptions& options, Progress* progress) {
  return detail::evaluate_rows(
      grid, options, progress, "tpms",
      [&](std::size_t, float* out, const std::vector<detail::AxisTrig>& x, detail::AxisTrig y,
          detail::AxisTrig z, const detail::TpmsKernel& kernel) {
        for (int i = 0; i < grid.dims[0]; ++i) out[i] = kernel(x[i], y, z);
      });
}

double lattice_solid_fraction(const TpmsOptions& options, int samples) {
  validate(options);
  const detail::TpmsKernel kernel(options);
  std::vector<detail::AxisTrig> t[3];
  for (int axis = 0; axis < 3; ++axis)
    for (int i = 0; i < samples; ++i)
      t[axis].push_back(
          kernel.trig(axis, options.origin[axis] + options.cell[axis] * (i + 0.5) / samples));
  const std::size_t n = static_cast<std::size_t>(samples) * samples;
  const double solid = detail::deterministic_sum(n, 64, [&](std::size_t jk) {
    const std::size_t j = jk % samples, k = jk / samples;
    int count = 0;
    for (int i = 0; i < samples; ++i) count += kernel(t[0][i], t[1][j], t[2][k]) < 0;
    return static_cast<double>(count);
  });
  return solid / (static_cast<double>(n) * samples);
}

}  // namespace tpmsfill
