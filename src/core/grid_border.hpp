/// @file grid_border.hpp
/// @brief The nodes on a grid's six faces, visited without touching the inside.
#pragma once

#include <cstddef>

#include "tpmsfill/types.hpp"

namespace tpmsfill::detail {

/// Calls f(node index) for every node of plane k on the grid's six faces, each once, in index
/// order: whole rows on the bottom, top and side faces, the two end nodes of every other row.
template <class F>
void for_each_border_node_of_plane(const Grid& g, int k, const F& f) {
  const int nx = g.dims[0], ny = g.dims[1], nz = g.dims[2];
  for (int j = 0; j < ny; ++j) {
    const bool face = k == 0 || k == nz - 1 || j == 0 || j == ny - 1;
    for (int i = 0; i < nx; i += face || i == nx - 1 ? 1 : nx - 1) f(g.index(i, j, k));
  }
}

/// for_each_border_node_of_plane() on every plane, bottom to top.
template <class F>
void for_each_border_node(const Grid& g, const F& f) {
  for (int k = 0; k < g.dims[2]; ++k) for_each_border_node_of_plane(g, k, f);
}

}  // namespace tpmsfill::detail
