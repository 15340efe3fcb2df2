// Stage "compose": one row loop serves the band (eq. 10) and full-field paths.
#include "tpmsfill/lattice/compose.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "core/grid_buffer.hpp"
#include "core/parallel.hpp"
#include "core/stage_progress.hpp"
#include "tpmsfill/error.hpp"

namespace tpmsfill {

void require_valid(const ComposeOptions& o) {
  if (!(o.skin >= 0) || !std::isfinite(o.skin))
    throw InputError("the skin thickness must be a non-negative number of millimetres");
}

int skin_band_width(double skin, double spacing) {
  return skin > 0 ? static_cast<int>(std::ceil(skin / spacing)) + 2 : 1;
}

namespace {

// What φ_model is at a node: outside the band on either side, or known.
enum Known : std::uint8_t { kOutside = 0, kInside = 1, kDistance = 2 };

// model_row(row, out, known) writes φ_model (where known) and the kind of every node of a row;
// the lattice is then evaluated where it can matter and combined.
template <class ModelRow>
Field compose_rows(const Grid& grid, const FieldSource& source, const ComposeOptions& o,
                   const ModelRow& model_row) {
  require_valid(o);
  const RowFunction lattice = bind_source(source, grid);
  // Any positive value serves outside the band: no cell there has a corner with φ < 0. One
  // like a distance keeps the measures' gradients there plausible.
  const float outside = static_cast<float>(1 + o.skin + source.bound);
  const float skin = static_cast<float>(o.skin);
  const std::size_t nx = static_cast<std::size_t>(grid.dims[0]);
  const std::size_t rows = grid.row_count();
  Field field{grid, detail::grid_buffer<float>(grid.node_count())};
  detail::ProgressCounter counter(o.progress, "compose", rows);
  detail::parallel_for(rows, 16, [&](std::size_t begin, std::size_t end) {
    std::vector<std::uint8_t> known(nx);
    std::vector<float> lat(nx);
    for (std::size_t row = begin; row < end; ++row) {
      float* out = field.values.data() + row * nx;
      model_row(row, out, known.data());
      lattice(row, 1, lat.data(), known.data());
      for (std::size_t i = 0; i < nx; ++i) {
        float v;
        if (known[i] == kOutside) {
          v = outside;
        } else if (known[i] == kInside) {
          v = lat[i];
        } else {
          const float d = out[i];
          float shell = lat[i];
          if (skin > 0)
            shell = std::min(shell,
                             o.skin_windows ? std::max(-d - skin, shell - 0.5f * skin) : -d - skin);
          v = std::max(d, shell);
        }
        out[i] = v == 0.0f ? std::numeric_limits<float>::min() : v;
      }
    }
    counter.add(end - begin);
  });
  counter.finish();
  return field;
}

}  // namespace

Field compose_field(const Mask& inside, const Band& band, const std::vector<float>& band_distance,
                    const FieldSource& lattice, const ComposeOptions& options) {
  const Grid& g = inside.grid;
  if (inside.values.size() != g.node_count() || !(band.grid == g) ||
      band.nodes.size() != band_distance.size())
    throw InputError("compose_field: mask, band and distances do not describe the same grid");
  const std::size_t nx = g.dims[0];
  return compose_rows(g, lattice, options, [&](std::size_t row, float* out, std::uint8_t* known) {
    const std::size_t first = row * nx;
    const std::uint8_t* in = inside.values.data() + first;
    for (std::size_t i = 0; i < nx; ++i) known[i] = in[i] ? kInside : kOutside;
    auto it = std::lower_bound(band.nodes.begin(), band.nodes.end(), first);
    for (; it != band.nodes.end() && *it < first + nx; ++it) {
      out[*it - first] = band_distance[static_cast<std::size_t>(it - band.nodes.begin())];
      known[*it - first] = kDistance;
    }
  });
}

Field compose_field(const Field& model_distance, const FieldSource& lattice,
                    const ComposeOptions& options) {
  const Grid& g = model_distance.grid;
  if (model_distance.values.size() != g.node_count())
    throw InputError("compose_field: field size does not match its grid");
  const std::size_t nx = g.dims[0];
  return compose_rows(g, lattice, options, [&](std::size_t row, float* out, std::uint8_t* known) {
    std::copy_n(model_distance.values.data() + row * nx, nx, out);
    std::fill_n(known, nx, kDistance);
  });
}

}  // namespace tpmsfill
