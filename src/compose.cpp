// Stage "compose": one row kernel serves the band (eq. 10) and full-field paths.
#include "tpmsfill/compose.hpp"

#include <algorithm>
#include <limits>

#include "detail/parallel.hpp"
#include "detail/tpms_kernel.hpp"
#include "tpmsfill/error.hpp"

namespace tpmsfill {

FieldRange off_band_values(const TpmsOptions& lattice) {
  const FieldRange r = tpms_range(lattice);
  return {r.low - 1.0f - (r.high - r.low), r.high + 1.0f + (r.high - r.low)};
}

namespace {

// Calls model_row(row, float* out) to get φ_model along each grid row, then takes the max
// with φ_TPMS where the TPMS can win, and moves exact zeros off the iso-value.
template <class ModelRow>
Field compose_rows(const Grid& grid, const TpmsOptions& lattice, Progress* progress,
                   const ModelRow& model_row) {
  const float tpms_high = tpms_range(lattice).high;
  return detail::evaluate_rows(
      grid, lattice, progress, "compose",
      [&](std::size_t row, float* out, const std::vector<detail::AxisTrig>& x, detail::AxisTrig y,
          detail::AxisTrig z, const detail::TpmsKernel& kernel) {
        model_row(row, out);
        for (int i = 0; i < grid.dims[0]; ++i) {
          float v = out[i];
          if (v < tpms_high) v = std::max(v, kernel(x[i], y, z));
          out[i] = v == 0.0f ? std::numeric_limits<float>::min() : v;
        }
      });
}

}  // namespace

Field compose_field(const Mask& inside, const Band& band, const std::vector<float>& band_distance,
                    const TpmsOptions& lattice, Progress* progress) {
  const Grid& g = inside.grid;
  if (inside.values.size() != g.node_count() || !(band.grid == g) ||
      band.nodes.size() != band_distance.size())
    throw InputError("compose_field: mask, band and distances do not describe the same grid");
  const FieldRange off = off_band_values(lattice);
  const std::size_t nx = g.dims[0];
  return compose_rows(g, lattice, progress, [&](std::size_t row, float* out) {
    const std::size_t first = row * nx;
    const std::uint8_t* in = inside.values.data() + first;
    for (std::size_t i = 0; i < nx; ++i) out[i] = in[i] ? off.low : off.high;
    auto it = std::lower_bound(band.nodes.begin(), band.nodes.end(), first);
    for (; it != band.nodes.end() && *it < first + nx; ++it)
      out[*it - first] = band_distance[static_cast<std::size_t>(it - band.nodes.begin())];
  });
}

Field compose_field(const Field& model_distance, const TpmsOptions& lattice, Progress* progress) {
  const Grid& g = model_distance.grid;
  if (model_distance.values.size() != g.node_count())
    throw InputError("compose_field: field size does not match its grid");
  const std::size_t nx = g.dims[0];
  return compose_rows(g, lattice, progress, [&](std::size_t row, float* out) {
    std::copy_n(model_distance.values.data() + row * nx, nx, out);
  });
}

}  // namespace tpmsfill
