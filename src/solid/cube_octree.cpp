// The adaptive octree over the parameter cube (cube_octree.hpp).
#include "tpmsfill/solid/cube_octree.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <string>
#include <tuple>

#include "solid/internal/octree_cells.hpp"
#include "tpmsfill/error.hpp"

namespace tpmsfill {

namespace {

using Cell = OctreeCell;

// Leaves in the order the result lists them: level, then k, j, i.
struct CellOrder {
  bool operator()(const Cell& a, const Cell& b) const { return detail::cell_less(a, b); }
};

using Leaves = std::map<Cell, std::vector<std::uint32_t>, CellOrder>;

std::uint32_t cell_index(double x, int level) {
  const double n = std::ldexp(1.0, level);
  return static_cast<std::uint32_t>(
      std::clamp(std::floor(std::clamp(x, 0.0, 1.0) * n), 0.0, n - 1));
}

// Replaces a leaf by its eight children, its points shared among them.
void split(Leaves& leaves, Leaves::iterator leaf,
           const std::vector<std::array<double, 3>>& points) {
  const Cell cell = leaf->first;
  const std::vector<std::uint32_t> held = std::move(leaf->second);
  leaves.erase(leaf);
  std::array<std::vector<std::uint32_t>, 8> parts;
  for (std::uint32_t p : held) {
    int octant = 0;
    for (int a = 0; a < 3; ++a)
      octant |= static_cast<int>(cell_index(points[p][a], cell.level + 1) & 1) << a;
    parts[octant].push_back(p);
  }
  for (int o = 0; o < 8; ++o) leaves.emplace(detail::child_cell(cell, o), std::move(parts[o]));
}

// Splits a leaf at the deepest level until its neighbours differ by at most one level; one
// pass over the leaves, true when something was split.
bool balance_pass(Leaves& leaves, const std::vector<std::array<double, 3>>& points,
                  std::uint64_t& splits) {
  std::vector<Cell> cells;
  for (const auto& [cell, held] : leaves) cells.push_back(cell);
  bool changed = false;
  for (const Cell& c : cells) {
    if (c.level < 2) continue;
    const std::int64_t n = std::int64_t{1} << c.level;
    for (int d = 0; d < 27; ++d) {
      const std::int64_t at[3] = {c.index[0] + d % 3 - 1, c.index[1] + d / 3 % 3 - 1,
                                  c.index[2] + d / 9 - 1};
      if (d == 13 || std::min({at[0], at[1], at[2]}) < 0 || std::max({at[0], at[1], at[2]}) >= n)
        continue;
      for (int m = 0; m + 1 < c.level; ++m) {  // a leaf two or more levels above?
        const int shift = c.level - m;
        const Cell coarse{
            m,
            {static_cast<std::uint32_t>(at[0] >> shift), static_cast<std::uint32_t>(at[1] >> shift),
             static_cast<std::uint32_t>(at[2] >> shift)}};
        const auto found = leaves.find(coarse);
        if (found == leaves.end()) continue;
        split(leaves, found, points);
        ++splits;
        changed = true;
        break;
      }
    }
  }
  return changed;
}

// Balances (when asked) and lists the leaves.
CubeOctree finish(Leaves& leaves, const std::vector<std::array<double, 3>>& points,
                  const CubeOctreeOptions& options, std::uint64_t balance_splits) {
  CubeOctree octree;
  octree.balance_splits = balance_splits;
  if (options.balance)
    while (balance_pass(leaves, points, octree.balance_splits)) {
    }
  for (const auto& [cell, held] : leaves) {
    octree.leaves.push_back(cell);
    octree.points_per_leaf.push_back(static_cast<std::uint32_t>(held.size()));
    octree.deepest = std::max(octree.deepest, cell.level);
    octree.overfull += static_cast<int>(held.size()) > options.max_per_cell;
  }
  return octree;
}

}  // namespace

std::vector<std::array<double, 3>> tet_centroids(const TetMesh& mesh, const CubeMap& map) {
  std::vector<std::array<double, 3>> centroids(mesh.tets.size());
  for (std::size_t t = 0; t < mesh.tets.size(); ++t)
    for (int a = 0; a < 3; ++a) {
      double sum = 0;
      for (std::uint32_t v : mesh.tets[t]) sum += map.uvw[v][a];
      centroids[t][a] = sum / 4;
    }
  return centroids;
}

CubeOctree build_cube_octree(const std::vector<std::array<double, 3>>& points,
                             const CubeOctreeOptions& options) {
  if (options.max_level < 0 || options.max_level > 16)
    throw InputError("the octree's deepest level must be 0 to 16");
  if (options.initial_level < 0 || options.initial_level > options.max_level)
    throw InputError("the octree's initial level must be 0 to its deepest level (" +
                     std::to_string(options.max_level) + ")");
  if (options.max_per_cell < 1) throw InputError("the octree's tets per cell must be at least 1");
  Leaves leaves;
  const std::uint32_t n = 1u << options.initial_level;
  for (std::uint32_t k = 0; k < n; ++k)
    for (std::uint32_t j = 0; j < n; ++j)
      for (std::uint32_t i = 0; i < n; ++i)
        leaves.emplace(Cell{options.initial_level, {i, j, k}}, std::vector<std::uint32_t>{});
  for (std::uint32_t p = 0; p < points.size(); ++p) {
    const Cell c{options.initial_level,
                 {cell_index(points[p][0], options.initial_level),
                  cell_index(points[p][1], options.initial_level),
                  cell_index(points[p][2], options.initial_level)}};
    leaves[c].push_back(p);
  }
  // Split by count, coarse to fine: the map's order visits every level before the next.
  for (auto it = leaves.begin(); it != leaves.end();) {
    if (static_cast<int>(it->second.size()) > options.max_per_cell &&
        it->first.level < options.max_level) {
      const Cell cell = it->first;
      split(leaves, it, points);
      it = leaves.upper_bound(cell);  // the children sort after every cell of cell's level
    } else {
      ++it;
    }
  }
  return finish(leaves, points, options, 0);
}

CubeOctree split_octree_leaves(const CubeOctree& octree, const std::vector<std::size_t>& chosen,
                               const std::vector<std::array<double, 3>>& points,
                               const CubeOctreeOptions& options) {
  Leaves leaves;
  for (const Cell& leaf : octree.leaves) leaves.emplace(leaf, std::vector<std::uint32_t>{});
  for (std::uint32_t p = 0; p < points.size(); ++p)
    leaves[octree.leaves[octree_leaf_at(octree, points[p])]].push_back(p);
  for (std::size_t s : chosen) {
    if (s >= octree.leaves.size())
      throw InputError("leaf " + std::to_string(s) + " to split is past the octree's " +
                       std::to_string(octree.leaves.size()) + " leaves");
    const auto leaf = leaves.find(octree.leaves[s]);
    if (leaf != leaves.end() && leaf->first.level < options.max_level)
      split(leaves, leaf, points);  // (not found: listed twice, split already)
  }
  return finish(leaves, points, options, octree.balance_splits);
}

std::size_t octree_leaf_at(const CubeOctree& octree, std::array<double, 3> uvw) {
  for (int level = 0; level <= octree.deepest; ++level) {
    const Cell c{level,
                 {cell_index(uvw[0], level), cell_index(uvw[1], level), cell_index(uvw[2], level)}};
    const auto found = std::lower_bound(octree.leaves.begin(), octree.leaves.end(), c, CellOrder{});
    if (found != octree.leaves.end() && *found == c)
      return static_cast<std::size_t>(found - octree.leaves.begin());
  }
  return octree.leaves.size();  // unreachable: the leaves tile the cube
}

}  // namespace tpmsfill
