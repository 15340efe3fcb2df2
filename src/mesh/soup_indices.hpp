// What every stage that takes a TriangleSoup asks of its indices: that they are in range,
// that they fit the 32-bit numbering of corners, and which points they reference.
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "core/index_limits.hpp"
#include "tpmsfill/error.hpp"
#include "tpmsfill/types.hpp"

namespace tpmsfill::detail {

/// Throws InputError("<context>triangle T refers to point V, but there are only N points")
/// for the first out-of-range index; `context` prefixes the message (e.g. "cannot write f: ").
inline void require_indices_in_range(const TriangleSoup& soup, const std::string& context = {}) {
  const std::size_t n = soup.points.size();
  for (std::size_t t = 0; t < soup.triangles.size(); ++t)
    for (const std::uint32_t v : soup.triangles[t])
      if (v >= n)
        throw InputError(context + "triangle " + std::to_string(t) + " refers to point " +
                         std::to_string(v) + ", but there are only " + std::to_string(n) +
                         " points");
}

/// Most triangles whose corner slots (3 per triangle) have 32-bit numbers: 1431655765.
inline constexpr std::uint64_t kMaxSlotTriangles = 0xffffffffu / 3;

/// Indices in range (as above), corner slots numbered with 32 bits and point ids below
/// kNoIndex; else InputError("too many triangles or points to <verb> ...").
inline void require_32bit_mesh(const TriangleSoup& soup, const std::string& verb) {
  require_indices_in_range(soup);
  if (soup.triangles.size() > kMaxSlotTriangles || !fits_32bit_ids(soup.points.size()))
    throw InputError("too many triangles or points to " + verb + " (at most 1431655765 triangles)");
}

/// Two of the triangle's corners are the same index (point, vertex or polygon corner).
template <class Index>
constexpr bool repeated_corner(const std::array<Index, 3>& t) {
  return t[0] == t[1] || t[1] == t[2] || t[0] == t[2];
}

/// Per point: 1 when some triangle uses it. Precondition: indices in range.
inline std::vector<std::uint8_t> used_points(const TriangleSoup& soup) {
  std::vector<std::uint8_t> used(soup.points.size(), 0);
  for (const Triangle& t : soup.triangles)
    for (std::uint32_t v : t) used[v] = 1;
  return used;
}

}  // namespace tpmsfill::detail
