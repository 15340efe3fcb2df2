/// @file surface_deviation.hpp
/// @brief How far one surface lies from another: distances from sample points of one
/// triangle soup to the nearest point of another (CGAL's AABB tree), as max and 95th
/// percentile. Plain data in and out; CGAL stays in the .cpp.
#pragma once

#include <cstddef>
#include <cstdint>

#include "tpmsfill/types.hpp"

namespace tpmsfill::detail {

struct DistanceStats {
  double max = 0, p95 = 0;    ///< mm
  std::uint64_t samples = 0;  ///< points measured
};

/// Distances from samples of `from` to the surface of `to` (its non-degenerate triangles).
/// The samples of a triangle are the points of its barycentric grid of order `grid` (grid 1:
/// the corners; grid n: the points with barycentric coordinates in multiples of 1/n) and its
/// centroid, on every triangle or, where that would exceed `max_samples` points, on every
/// k-th triangle (evenly thinned). With `skip_inside`, samples off `to`'s surface and inside
/// it (odd crossings of a ray; `to` closed) are left out: surface a union removed from inside
/// a solid is not a lost feature. With `buried_in`, the samples of `from`'s triangles buried in
/// that solid are left out: those whose outer side (just off the sample along the normal)
/// lies inside it by the winding rule (signed crossings of a ray; the solid closed), as faces
/// of overlapping shells do inside the union, while the walls of a cavity do not; judged per
/// sample, a ten-thousandth of the triangle's size off it).
/// Deterministic and parallel. Zero samples when either side has no triangle.
DistanceStats surface_distances(const TriangleSoup& from, const TriangleSoup& to,
                                bool skip_inside = false, int grid = 1,
                                std::size_t max_samples = 600000,
                                const TriangleSoup* buried_in = nullptr);

}  // namespace tpmsfill::detail
