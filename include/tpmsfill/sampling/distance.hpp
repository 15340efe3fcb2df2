/// @file distance.hpp
/// @brief Stage "distance": the model's signed distance φ_model (paper eq. 8–9), by the AABB
/// tree's closest-point query, on the band only, or on every node (the --full-field
/// reference the paper compares against).
///
/// The magnitude is the exact-as-double Euclidean distance to the nearest triangle; the sign
/// comes from the occupancy mask (negative inside), so sign and classification always agree.
#pragma once

#include <cstdint>
#include <vector>

#include "tpmsfill/progress.hpp"
#include "tpmsfill/sampling/spatial.hpp"
#include "tpmsfill/types.hpp"

namespace tpmsfill {

struct DistanceOptions {
  /// Start each closest-point query from the previous node's answer (nodes are visited in
  /// index order per chunk, so neighbours are near): same result, fewer tree nodes visited.
  bool reuse_hints = true;
  Progress* progress = nullptr;  ///< reports per chunk; may cancel
};

/// Signed distances (mm) at band.nodes, in the same order.
/// @param[in] inside  occupancy on the band's grid (1 = inside → negative distance)
/// @throws InputError  the band's grid and the mask's grid differ
/// @throws Cancelled   when options.progress says so
std::vector<float> band_distances(const MeshIndex& index, const Mask& inside, const Band& band,
                                  const DistanceOptions& options = {});

/// Per point, its nearest point on the index's triangles (caps included): the same walk and
/// formula as the distances, so the answer is the one triangle that attains the minimum (the
/// lowest id among ties) whatever the thread count.
/// @throws InputError  a point that is not finite
std::vector<Vec3> closest_points(const MeshIndex& index, const std::vector<Vec3>& points);

/// Signed distance at every node of inside.grid: dims[0]·dims[1]·dims[2] queries.
/// @throws Cancelled  when options.progress says so
Field signed_distance_field(const MeshIndex& index, const Mask& inside,
                            const DistanceOptions& options = {});

}  // namespace tpmsfill
