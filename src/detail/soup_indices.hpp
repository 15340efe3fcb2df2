// The one precondition every stage that takes a TriangleSoup shares: indices in range.
#pragma once

#include <string>

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

}  // namespace tpmsfill::detail
