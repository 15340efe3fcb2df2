/// @file grid.hpp
/// @brief Stage "grid": the sample grid over a model's bounding box, padded so the field is
/// "outside" on every face of the grid and the extracted surface closes.
#pragma once

#include <cstdint>

#include "tpmsfill/types.hpp"

namespace tpmsfill {

struct GridOptions {
  double voxel_size = 0.1;  ///< node spacing a, mm (> 0)
  /// Empty layers of nodes added beyond the bounding box on every side. A job on a model's
  /// field (fill, slice) needs at least 2: one so the outermost nodes are outside, one more so
  /// the band never reaches the grid's faces; a surface cut open at the box needs none.
  int padding = 2;
};

/// The grid whose node (padding, padding, padding) sits on bounds.min and whose nodes cover
/// bounds with `padding` layers to spare on every side. An extent within 10⁻⁹ voxels above a
/// whole number of voxels takes that number (1.1 mm is 11 voxels of 0.1 mm, not 12).
/// @param[in] bounds  non-empty box with finite corners, mm
/// @throws InputError  empty or non-finite bounds, voxel_size <= 0 or not finite,
///                     padding < 0, or more than 2^31 − 1 nodes along an axis
Grid make_grid(const Box3& bounds, const GridOptions& options = {});

/// Nodes make_grid() would create, without creating anything (for memory estimates).
/// Saturates at UINT64_MAX instead of overflowing.
std::uint64_t grid_node_count(const Box3& bounds, const GridOptions& options);

}  // namespace tpmsfill
