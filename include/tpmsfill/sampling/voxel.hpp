/// @file voxel.hpp
/// @brief Stage "voxel": 26-neighbour morphology on occupancy masks and the narrow band on
/// which the model's distance is computed (paper eq. 6–7). Pure byte-grid code, no CGAL.
///
/// Nodes beyond the grid count as unset. Two nodes are 26-neighbours when they differ by at
/// most one in every index (Chebyshev distance 1).
#pragma once

#include <cstdint>
#include <vector>

#include "tpmsfill/types.hpp"

namespace tpmsfill {

/// Nodes within `voxels` 26-steps of a set node (the set nodes included).
/// Separable: a box structuring element is a pass along x, then y, then z. Values are ORed bit by
/// bit, so bits 0 and 1 of a byte dilate as two masks at once (band_voxels dilates inside and
/// outside in one pass); values above 3 are not supported.
/// @throws InputError  voxels < 0, or mask.values does not match mask.grid
Mask dilate(const Mask& mask, int voxels = 1);

struct BandOptions {
  /// Half-width in voxels. 1 is the paper's band: inside nodes with an outside 26-neighbour
  /// (bw(I)) and outside nodes with an inside 26-neighbour. k > 1 widens both sides to k
  /// 26-steps.
  int width = 1;
};

/// The band B on which φ_model is computed exactly: (I ∧ dilate(¬I, k)) ∪ (¬I ∧ dilate(I, k)).
/// For k = 1 this contains the paper's bw(I) ∪ bw(dil(I)) and, in addition, outside nodes
/// enclosed by inside ones (a gap one voxel wide), which bw(dil(I)) misses. Every cell that has
/// both inside and outside corners has all eight corners in the band, so the surface that
/// marching cubes extracts near the model's boundary is always computed from true distances.
/// @throws InputError  width < 1, or inside.values does not match inside.grid
Band band_voxels(const Mask& inside, const BandOptions& options = {});

/// Connected regions of a mask's set nodes (26-connected unless asked otherwise), stored as
/// runs along x.
struct Regions {
  struct Run {
    int begin = 0, end = 0;  ///< x range [begin, end) of set nodes in one row
    std::uint32_t region = 0;
  };
  Grid grid;
  std::vector<std::uint64_t>
      row_start;  ///< runs of row (j, k) are runs[row_start[r] .. row_start[r+1])
  std::vector<Run> runs;
  std::uint32_t count = 0;  ///< regions, numbered 0.. in order of their first node

  /// Region of node (i, j, k), or UINT32_MAX when the node is not set.
  std::uint32_t region_at(int i, int j, int k) const;
};
/// Which neighbours join a region: the 6 face neighbours, or all 26 (faces, edges, corners).
/// Solid and void pair them: where solid joins across edges and corners (26), void joins only
/// across faces (6), so two void nodes touching at an edge stay apart.
enum class Connectivity { Face, Vertex };
Regions label_regions(const Mask& mask, Connectivity connectivity = Connectivity::Vertex);

/// Appends the runs of `planes`' set nodes to `runs` (region 0, unlabelled): a job that goes
/// slab by slab keeps a mask this way, in far less memory than a byte per node. runs.grid is
/// the whole grid; `planes` must be its next planes (Grid::z_offset = the planes it holds).
/// @throws InputError  they are not, or there are 2^32 runs or more
void append_runs(Regions& runs, const Mask& planes);

/// Labels runs (append_runs over every plane of runs.grid) as label_regions labels a mask.
/// @throws InputError  the runs do not cover the grid's rows
Regions label_runs(Regions runs, Connectivity connectivity = Connectivity::Vertex);

/// Euclidean distance, mm (grid.spacing units), from every node to the nearest node where
/// `mask` is unset; 0 at unset nodes. Exact on the nodes: separable squared EDT
/// (Felzenszwalb & Huttenlocher 2012 / Saito & Toriwaki), a pass along x, y, then z,
/// parallel over rows, deterministic. Node-to-node distances: a surface that lies between
/// nodes is up to one voxel nearer than the unset node beyond it (measure.hpp corrects this).
/// @param beyond_grid_set  whether nodes beyond the grid count as set (true) or unset (false).
///                         With false every distance is at most the distance to just beyond
///                         the grid's faces; with true the grid's border is ignored, and a
///                         mask with no unset node gives +infinity everywhere.
/// @throws InputError  mask.values does not match mask.grid, or the grid is too large for
///                     squared distances in 32 bits (Σ (dims + 1)² >= 2³², e.g. a cube of
///                     37,000 nodes a side)
Field distance_transform(const Mask& mask, bool beyond_grid_set = false);

}  // namespace tpmsfill
