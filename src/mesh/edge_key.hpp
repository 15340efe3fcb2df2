// One key per undirected edge of an indexed mesh, for sorting and hashing edges: the smaller
// index in the high 32 bits, so (a, b) and (b, a) are the same edge.
#pragma once

#include <algorithm>
#include <cstdint>

namespace tpmsfill::detail {

inline std::uint64_t edge_key(std::uint32_t a, std::uint32_t b) {
  return (std::uint64_t{std::min(a, b)} << 32) | std::max(a, b);
}

}  // namespace tpmsfill::detail
