// The field seam: sources bound to a grid, sampled by blocks of rows.
#include "tpmsfill/field.hpp"

#include <cmath>
#include <utility>

#include "core/grid_buffer.hpp"
#include "core/parallel.hpp"
#include "core/stage_progress.hpp"
#include "tpmsfill/error.hpp"

namespace tpmsfill {

RowFunction bind_source(const FieldSource& source, const Grid& grid) {
  if (!source) throw InputError("the field source is empty (no on_grid)");
  if (!(source.bound >= 0) || !std::isfinite(source.bound))
    throw InputError("the field source's bound must be a non-negative number of millimetres");
  RowFunction rows = source.on_grid(grid);
  if (!rows) throw InputError("the field source's on_grid returned no row function");
  return rows;
}

FieldSource function_source(std::function<float(Vec3)> at) {
  if (!at) return {};
  return {.on_grid = [at = std::move(at)](const Grid& grid) -> RowFunction {
    return [at, grid](std::size_t first_row, std::size_t row_count, float* values,
                      const std::uint8_t* need) {
      for_each_needed_node(
          grid, first_row, row_count, need,
          [&](int i, int j, int k, std::size_t n) { values[n] = at(grid.node(i, j, k)); });
    };
  }};
}

Field sample_field(const FieldSource& source, const Grid& grid, Progress* progress) {
  const RowFunction rows = bind_source(source, grid);
  Field field{grid, detail::grid_buffer<float>(grid.node_count())};
  const std::size_t nx = static_cast<std::size_t>(grid.dims[0]);
  detail::ProgressCounter counter(progress, "field", grid.row_count());
  detail::parallel_for(grid.row_count(), 16, [&](std::size_t begin, std::size_t end) {
    rows(begin, end - begin, field.values.data() + begin * nx, nullptr);
    counter.add(end - begin);
  });
  counter.finish();
  return field;
}

float field_value(const FieldSource& source, Vec3 p) {
  Grid one;
  one.origin = p;
  one.spacing = 1;
  one.dims = {1, 1, 1};
  float v = 0;
  bind_source(source, one)(0, 1, &v, nullptr);
  return v;
}

}  // namespace tpmsfill
