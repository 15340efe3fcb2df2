/// @file index_limits.hpp
/// @brief 32-bit ids for points, triangles, regions and runs: the one "no index" value and
/// the one guard that a count can be numbered with ids that never reach it.
#pragma once

#include <cstddef>
#include <cstdint>
#include <limits>

namespace tpmsfill::detail {

/// "No point / triangle / region here": never a valid 32-bit id.
inline constexpr std::uint32_t kNoIndex = std::numeric_limits<std::uint32_t>::max();

/// Whether `count` items can be numbered 0 .. count − 1 with 32-bit ids, none of them kNoIndex
/// (at most 2^32 − 1 items). Every reader, index and stage guards its counts with this.
constexpr bool fits_32bit_ids(std::uint64_t count) {
  return count <= kNoIndex;
}

}  // namespace tpmsfill::detail
