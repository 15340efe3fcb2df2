// The region a set of possibly self-overlapping, possibly turned-over polygons covers, as
// simple contours (Clipper's exact integer sweep, Debian's libpolyclipping: the library most
// slicers use for this). Only src/layers/covered_region.cpp sees Clipper.
#pragma once

#include <vector>

#include "tpmsfill/slice.hpp"

namespace tpmsfill::detail {

/// The region where Σ over `paths` of each closed path's winding number is not zero, as
/// contours: outer ones counter-clockwise, holes clockwise, none crossing another, each with
/// its signed area. Vertices are snapped to a grid of about 2⁻²⁹ of the paths' extent.
std::vector<Contour> nonzero_region(const std::vector<std::vector<Vec2>>& paths);

}  // namespace tpmsfill::detail
