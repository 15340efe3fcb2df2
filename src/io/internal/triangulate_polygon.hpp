/// @file triangulate_polygon.hpp
/// @brief One polygon to triangles, shared by every reader that meets polygons (OBJ, PLY, OFF,
/// ASCII STL facets with more than three vertices).
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "tpmsfill/types.hpp"

namespace tpmsfill::detail {

/// Appends the triangles of one polygon to `out`: polygon.size() - 2 of them.
///
/// Triangles pass through. Larger polygons are projected onto the plane of their Newell normal
/// and ear-clipped there, so concave and mildly non-planar polygons come out right and every
/// triangle keeps the polygon's winding (its normal has a positive component along the Newell
/// normal). Where ear clipping cannot finish (self-overlapping or degenerate outline, a repeated
/// index, a zero Newell normal, or a polygon so large and concave that clipping would be
/// quadratic for too long) the polygon is fanned from its first corner instead.
///
/// @param[in] points   positions the indices refer to
/// @param[in] polygon  corner indices in winding order; size() >= 3, each < points.size()
/// @param[out] out     receives the triangles
/// @return true if ear clipping (or the pass-through of a triangle) produced the triangles,
///         false if the fan fallback did
bool triangulate_polygon(std::span<const Vec3> points, std::span<const std::uint32_t> polygon,
                         std::vector<Triangle>& out);

}  // namespace tpmsfill::detail
