// Stage "grid": node counts from the box size, padded on every side.
#include "tpmsfill/grid.hpp"

#include <cmath>
#include <limits>
#include <string>

#include "tpmsfill/error.hpp"

namespace tpmsfill {
namespace {

void require_valid(const Box3& bounds, const GridOptions& options) {
  if (!(options.voxel_size > 0) || !std::isfinite(options.voxel_size))
    throw InputError("the voxel size must be a positive number of millimetres");
  if (options.padding < 0) throw InputError("the grid padding must not be negative");
  if (bounds.empty() || !std::isfinite(bounds.min.x) || !std::isfinite(bounds.min.y) ||
      !std::isfinite(bounds.min.z) || !std::isfinite(bounds.max.x) ||
      !std::isfinite(bounds.max.y) || !std::isfinite(bounds.max.z))
    throw InputError("the model has no finite bounding box");
}

// Nodes along one axis: enough cells to cover the extent, plus the padding on both sides. The
// quotient's rounding (1.1 / 0.1 = 11.000000000000002) does not add a cell.
double nodes_along(double extent, const GridOptions& options) {
  return std::ceil(extent / options.voxel_size - 1e-9) + 1.0 + 2.0 * options.padding;
}

}  // namespace

std::uint64_t grid_node_count(const Box3& bounds, const GridOptions& options) {
  require_valid(bounds, options);
  const Vec3 size = bounds.size();
  const double n =
      nodes_along(size.x, options) * nodes_along(size.y, options) * nodes_along(size.z, options);
  return n >= 1.8e19 ? std::numeric_limits<std::uint64_t>::max() : static_cast<std::uint64_t>(n);
}

Grid make_grid(const Box3& bounds, const GridOptions& options) {
  require_valid(bounds, options);
  Grid grid;
  grid.spacing = options.voxel_size;
  const double pad = options.padding * options.voxel_size;
  grid.origin = {bounds.min.x - pad, bounds.min.y - pad, bounds.min.z - pad};
  for (int axis = 0; axis < 3; ++axis) {
    const double n = nodes_along(bounds.max[axis] - bounds.min[axis], options);
    if (n > std::numeric_limits<int>::max())
      throw InputError(
          "the grid would have more than 2^31 nodes along one axis; use a larger "
          "voxel size");
    grid.dims[axis] = static_cast<int>(n);
  }
  return grid;
}

}  // namespace tpmsfill
