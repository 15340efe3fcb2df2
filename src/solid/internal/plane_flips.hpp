// Internal: a plane triangulation's turned-over triangles mended by edge flips (a slice's
// section, solid_slice.cpp).
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "tpmsfill/types.hpp"

namespace tpmsfill::detail {

/// Flips edges of the triangles that turn clockwise seen from +z (their points' x and y, by
/// exact orientation) until none does or no flip helps, and returns how many still do. A flip
/// replaces the two triangles on an edge by the two on the quad's other diagonal when fewer of
/// those are clockwise or flat, the diagonal being no edge already. The quad's border is kept,
/// so the winding number of every point of the plane (triangles over it counter-clockwise
/// minus clockwise), the border edges and the points are unchanged.
/// Precondition: each directed edge belongs to one triangle at most (an oriented 2-manifold
/// with boundary); z is ignored.
std::size_t flip_turned_triangles(const std::vector<Vec3>& points,
                                  std::vector<std::array<std::uint32_t, 3>>& triangles);

}  // namespace tpmsfill::detail
