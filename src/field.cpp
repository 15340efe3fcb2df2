// The field seam: sources bound to a grid, sampled by blocks of rows.
#include "tpmsfill/field.hpp"

#include <utility>

#include "detail/parallel.hpp"
#include "detail/stage_progress.hpp"
#include "tpmsfill/error.hpp"

namespace tpmsfill {
namespace {

RowFunction bind(const FieldSource& source, const Grid& grid, const char* caller) {
  if (!source) throw InputError(std::string(caller) + ": the field source is empty");
  RowFunction rows = source.on_grid(grid);
  if (!rows) throw InputError(std::string(caller) + ": the field source gave no row function");
  return rows;
}

}  // namespace

FieldSource function_source(std::function<float(Vec3)> at) {
  if (!at) return {};
  return {.on_grid = [at = std::move(at)](const Grid& grid) -> RowFunction {
    return [at, grid](std::size_t first_row, std::size_t row_count, float* values,
                      const std::uint8_t* need) {
      const int nx = grid.dims[0];
      for (std::size_t r = 0; r < row_count; ++r) {
        const std::size_t row = first_row + r;
        const int j = static_cast<int>(row % static_cast<std::size_t>(grid.dims[1]));
        const int k = static_cast<int>(row / static_cast<std::size_t>(grid.dims[1]));
        float* out = values + r * static_cast<std::size_t>(nx);
        const std::uint8_t* wanted = need ? need + r * static_cast<std::size_t>(nx) : nullptr;
        for (int i = 0; i < nx; ++i)
          if (!wanted || wanted[i]) out[i] = at(grid.node(i, j, k));
      }
    };
  }};
}

Field sample_field(const FieldSource& source, const Grid& grid, Progress* progress) {
  const RowFunction rows = bind(source, grid, "sample_field");
  Field field{grid, std::vector<float>(grid.node_count())};
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
  bind(source, one, "field_value")(0, 1, &v, nullptr);
  return v;
}

}  // namespace tpmsfill
