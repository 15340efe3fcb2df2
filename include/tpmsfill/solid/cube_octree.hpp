/// @file cube_octree.hpp
/// @brief The adaptive octree over the parameter cube on which a heterogeneous solid's splines
/// live (Li & Fu 2021, §2.3.1): start from a uniform level, split every cell that holds more
/// than a few tets (Li & Fu use 5) until none does or the deepest level is reached, then split
/// until neighbouring cells differ by at most one level (2:1 balance, which keeps every spline
/// basis function's support a few cells wide).
///
/// A tet is counted in the cell that holds its parametric centroid (the mean of its corners'
/// (u, v, w)). Cell (level, i, j, k) is [i, i + 1] × [j, j + 1] × [k, k + 1] / 2^level.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "tpmsfill/solid/cube_map.hpp"
#include "tpmsfill/solid/tet_mesh.hpp"

namespace tpmsfill {

struct OctreeCell {
  int level = 0;
  std::array<std::uint32_t, 3> index{};  ///< i, j, k at that level
  friend bool operator==(const OctreeCell&, const OctreeCell&) = default;
};

struct CubeOctreeOptions {
  int initial_level = 2;  ///< uniform start: 2^level cells per axis (Li & Fu 2021: 1 for slicing)
  int max_per_cell = 5;   ///< split while a cell holds more tets than this (as in Li & Fu 2021)
  int max_level = 8;      ///< never split below this level (256 cells per axis)
  bool balance = true;    ///< 2:1 balance across faces, edges and corners
};

struct CubeOctree {
  /// The leaves, tiling the cube, ordered by level, then k, j, i.
  std::vector<OctreeCell> leaves;
  /// Per leaf, how many of the points (tet centroids) it holds.
  std::vector<std::uint32_t> points_per_leaf;
  int deepest = 0;                   ///< deepest level of a leaf
  std::uint64_t overfull = 0;        ///< leaves at max_level still holding more than max_per_cell
  std::uint64_t balance_splits = 0;  ///< cells split only for the 2:1 balance
};

/// The parametric centroid of every tet: the mean of its corners' (u, v, w).
std::vector<std::array<double, 3>> tet_centroids(const TetMesh& mesh, const CubeMap& map);

/// Builds the octree over `points` (parametric centroids, clamped onto the cube).
/// @throws InputError  initial_level outside 0..max_level, max_level outside 0..16,
///                     max_per_cell < 1
CubeOctree build_cube_octree(const std::vector<std::array<double, 3>>& points,
                             const CubeOctreeOptions& options = {});

/// `octree` with the leaves numbered in `chosen` split into their eight children (those already
/// at options.max_level are kept), then balanced when options.balance says so; `points` (the
/// points the octree was built over) are counted again. For progressive refinement.
/// @throws InputError  a leaf number past octree.leaves
CubeOctree split_octree_leaves(const CubeOctree& octree, const std::vector<std::size_t>& chosen,
                               const std::vector<std::array<double, 3>>& points,
                               const CubeOctreeOptions& options = {});

/// The leaf of `octree` that holds (u, v, w) (a point on a shared face goes to the cell above
/// it along each axis; 1 goes to the last cell).
std::size_t octree_leaf_at(const CubeOctree& octree, std::array<double, 3> uvw);

}  // namespace tpmsfill
