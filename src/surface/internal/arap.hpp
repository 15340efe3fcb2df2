/// @file arap.hpp
/// @brief A free-boundary layout as rigid as possible (Liu, Zhang, Xu, Gotsman and Gortler 2008,
/// "A local/global approach to mesh parameterization"), for surfaces that a fixed square
/// squeezes (parameterize.hpp chooses between the two).
///
/// Each triangle's image is pulled towards a rotated copy of itself (local step: the best
/// rotation per triangle, in closed form for 2 × 2), then all points are solved together with
/// the cotangent weights (global step: one sparse Cholesky factor, reused every iteration).
/// A tube's seam stays closed: a seam copy is its original moved by one period P, an unknown
/// solved with the points, so the lattice closes across it after P is turned onto the x axis.
#pragma once

#include <array>
#include <cstdint>
#include <utility>
#include <vector>

#include "tpmsfill/types.hpp"

namespace tpmsfill::detail {

struct ArapLayout {
  std::vector<std::array<double, 2>> xy;  ///< per point, mm
  std::array<double, 2> period{0, 0};     ///< a tube's: xy[copy] = xy[original] + period
  int iterations = 0;                     ///< local/global rounds taken
  int short_steps = 0;                    ///< rounds cut short so no triangle turned over
};

/// Lays `mesh` out from `start` (a layout without flips, mm) by `iterations` local/global
/// rounds at most, stopping early once the energy changes by less than 1e-6 of itself. Each
/// round moves only as far towards its solve as keeps every triangle the right way round, so a
/// start without flips ends without.
/// @param[in] seam  (original, copy) point pairs of a tube cut open; empty for a disk
/// @throws InputError  the system cannot be factored, or tpmsfill was built without Eigen
ArapLayout arap_layout(const TriangleSoup& mesh, const std::vector<std::array<double, 2>>& start,
                       const std::vector<std::pair<std::uint32_t, std::uint32_t>>& seam,
                       int iterations);

}  // namespace tpmsfill::detail
