/// @file self_intersections.hpp
/// @brief Which triangles of an indexed mesh intersect each other, with exact predicates
/// (Epick), for stage "validate": between triangles of the same or 26-adjacent cells of a
/// grid the mesh was made on (marching-cubes output), or through CGAL's general box
/// intersection search (CGAL::box_self_intersection_d). Plain data in and out; CGAL stays in
/// the .cpp.
///
/// A pair counts as PMP::self_intersections decides it with shared corners taken by index:
/// sharing an edge, only if the two overlap (coplanar, opposite corners on the same side);
/// sharing one corner, only if they also meet elsewhere; otherwise if they meet at all.
/// Deterministic: the pairs come sorted, whatever the thread count.
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <vector>

#include "core/stage_progress.hpp"
#include "tpmsfill/types.hpp"

namespace tpmsfill::detail {

/// Two triangle indices, i < j.
using TrianglePair = std::array<std::uint32_t, 2>;

struct SelfIntersections {
  std::vector<TrianglePair> pairs;  ///< every intersecting pair once, sorted
  /// The cell search ran; false without a cell grid, or when some triangle did not lie in its
  /// cell (then the general search ran).
  bool by_cells = false;
};

/// Finds the intersecting pairs of `mesh`'s triangles.
/// @param[in] mesh       indices in range, at most 32-bit many triangles and points
/// @param[in] skip       per triangle: leave it out of the search (the degenerate ones)
/// @param[in] cell_grid  as ValidateOptions::cell_grid: when set, the cell search is tried
///                       first (its answer is the general search's, only faster)
/// @param[in,out] progress  receives one unit per triangle searched
/// @throws Cancelled  progress says so
SelfIntersections find_self_intersections(const TriangleSoup& mesh,
                                          const std::vector<std::uint8_t>& skip,
                                          const std::optional<Grid>& cell_grid,
                                          ProgressCounter& progress);

/// Whether triangles `h` and `g` (indices into `points`) intersect, decided as the search
/// decides a pair (shared corners by index, exact predicates). For one pair at a time (a
/// decimation's new triangles against their neighbours): the points are converted per call.
bool triangle_pair_intersects(const Triangle& h, const Triangle& g,
                              const std::vector<Vec3>& points);

}  // namespace tpmsfill::detail
