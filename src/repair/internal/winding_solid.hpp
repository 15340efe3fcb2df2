// Repair's volumetric route (src/repair/repair_volume.cpp): the surface of a soup's winding-number
// solid, remade by marching cubes. Plain data in and out; no CGAL in the header.
#pragma once

#include <cstdint>

#include "tpmsfill/grid.hpp"
#include "tpmsfill/io.hpp"
#include "tpmsfill/progress.hpp"
#include "tpmsfill/types.hpp"

namespace tpmsfill::detail {

/// Grids larger than this are not sampled (about 100 bytes a node at the peak: mask, band
/// and field).
constexpr std::uint64_t kMaxWindingSolidNodes = std::uint64_t{1} << 26;

/// The boundary of {w ≥ ½}, w the generalized winding number of `soup` with its holes closed
/// by clean_soup()'s caps (overlapping shells united, self-intersections resolved, flipped
/// faces turned), as marching cubes extracts it from the signed distance to the soup sampled at
/// `voxel`: the sign from the winding rule (classify_grid), the magnitude exact on the band
/// (band_distances). Valid by construction (marching_cubes.hpp's guarantees), rounded as
/// `rounding` says; within about a voxel of the soup where the solid's boundary follows it, and
/// parts thinner than a voxel may be lost.
/// @throws InputError     no triangle has three distinct corners, or no node is inside
/// @throws ResourceError  the grid would have more than kMaxWindingSolidNodes nodes
/// @throws Cancelled      progress said so
TriangleSoup winding_solid_surface(const TriangleSoup& soup, double voxel,
                                   CoordinateRounding rounding, Progress* progress);

/// The volume of the same solid {w ≥ ½}, mm³, measured along one ray per row of `grid`
/// (Occupancy::volume: exact along each row, the midpoint rule across rows). Where shells
/// overlap or nest, the summed signed volume of the triangles counts the shared part twice;
/// this does not. Two soups measured on one grid share its sampling: where their surfaces
/// coincide, so do their figures.
/// @throws InputError  no triangle has three distinct corners
/// @throws Cancelled   progress said so
double winding_solid_volume(const TriangleSoup& soup, const Grid& grid, Progress* progress);

}  // namespace tpmsfill::detail
