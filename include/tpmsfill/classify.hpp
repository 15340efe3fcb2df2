/// @file classify.hpp
/// @brief Stage "classify": which grid nodes are inside the model (the occupancy I of the
/// paper), by one ray per grid row through the AABB tree.
///
/// For each row (j, k) one ray runs along +x. Its crossings with the triangles are decided
/// with exact predicates (CGAL Epick 2D orientation of the row against the triangle's
/// projection on the yz plane) and a fixed tie-break (symbolic perturbation of the row to
/// (y + ε, z + ε²)), so a ray through an edge or a vertex counts it exactly once and a
/// triangle seen edge-on never counts. The crossing positions (floating point) are sorted and
/// the nodes between odd and even crossings are inside (parity rule). Never one ray per node.
#pragma once

#include <cstdint>

#include "tpmsfill/progress.hpp"
#include "tpmsfill/spatial.hpp"
#include "tpmsfill/types.hpp"

namespace tpmsfill {

struct ClassifyOptions {
  Progress* progress = nullptr;  ///< reports per row chunk; may cancel
};

struct Occupancy {
  Mask inside;  ///< 1 = node inside the model
  /// Volume enclosed by the model, mm^3, measured along the rays: the summed lengths of the
  /// inside spans times spacing² (exact along x, midpoint rule across rows).
  double volume = 0;
  std::uint64_t rays = 0;       ///< rows cast (dims[1]·dims[2])
  std::uint64_t crossings = 0;  ///< ray/triangle crossings counted
  /// Rows whose crossing count was odd (the mesh is not closed along them); their last
  /// crossing is ignored. Non-zero means the input has holes.
  std::uint64_t odd_rays = 0;
};

/// Classifies every node of `grid`. A node exactly on a crossing counts as outside.
/// @param[in] index  AABB tree of the model
/// @param[in] grid   sample grid (make_grid); rays cover its whole x extent
/// @throws Cancelled  when options.progress says so
Occupancy classify_grid(const MeshIndex& index, const Grid& grid,
                        const ClassifyOptions& options = {});

}  // namespace tpmsfill
