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
  validate(lattice);
  const detail::TpmsKernel kernel(lattice);
  const auto tx = detail::grid_trig(kernel, grid, 0);
  const auto ty = detail::grid_trig(kernel, grid, 1);
  const auto tz = detail::grid_trig(kernel, grid, 2);
  const float tpms_high = tpms_range(lattice).high;
  Field phi{grid, std::vector<float>(grid.node_count())};
  const std::size_t rows = static_cast<std::size_t>(grid.dims[1]) * grid.dims[2];
  detail::ProgressCounter counter(progress, "compose", rows);
  detail::parallel_for(rows, 64, [&](std::size_t begin, std::size_t end) {
    for (std::size_t row = begin; row < end; ++row) {
      const int j = static_cast<int>(row % grid.dims[1]);
      const int k = static_cast<int>(row / grid.dims[1]);
      float* out = phi.values.data() + row * grid.dims[0];
      model_row(row, out);
      for (int i = 0; i < grid.dims[0]; ++i) {
        float v = out[i];
        if (v < tpms_high) v = std::max(v, kernel(tx[i], ty[j], tz[k]));
        out[i] = v == 0.0f ? std::numeric_limits<float>::min() : v;
      }
    }
    counter.add(end - begin);
  });
  counter.finish();
  return phi;
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
