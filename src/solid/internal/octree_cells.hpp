/// @file octree_cells.hpp
/// @brief The small rules about octree cells that the octree, the bases, the model file and
/// the slicer share: their order, their children and a key for hashing them.
#pragma once

#include <array>
#include <cstdint>
#include <tuple>

#include "tpmsfill/solid/cube_octree.hpp"

namespace tpmsfill::detail {

/// Cells in the order octrees and bases list them: level, then k, j, i.
inline bool cell_less(const OctreeCell& a, const OctreeCell& b) {
  return std::tie(a.level, a.index[2], a.index[1], a.index[0]) <
         std::tie(b.level, b.index[2], b.index[1], b.index[0]);
}

/// Child `octant` of a cell: bit 0 the upper half along u, bit 1 along v, bit 2 along w.
inline OctreeCell child_cell(const OctreeCell& c, int octant) {
  return {c.level + 1,
          {2 * c.index[0] + (octant & 1), 2 * c.index[1] + (octant >> 1 & 1),
           2 * c.index[2] + (octant >> 2 & 1)}};
}

/// (level, i, j, k) in one integer: 18 bits per index (spans ≤ 2^16, functions ≤ 2^16 + 3).
inline std::uint64_t cell_key(int level, std::array<std::uint32_t, 3> index) {
  return std::uint64_t(level) << 54 | std::uint64_t(index[2]) << 36 |
         std::uint64_t(index[1]) << 18 | index[0];
}

}  // namespace tpmsfill::detail
