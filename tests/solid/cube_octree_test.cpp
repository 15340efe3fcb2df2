// The adaptive octree over the parameter cube (cube_octree.hpp): leaves tile the cube, hold at
// most max_per_cell points unless at the deepest level, and neighbours differ by one level.
#include <gtest/gtest.h>

#include <cmath>
#include <tpmsfill/error.hpp>
#include <tpmsfill/solid/cube_octree.hpp>

#include "test_util.hpp"

namespace tpmsfill {
namespace {

std::vector<std::array<double, 3>> random_points(std::size_t n, double scale, std::uint64_t seed) {
  std::vector<std::array<double, 3>> points(n);
  test::Random random{seed};
  for (auto& p : points)
    for (double& x : p) x = scale * random.next();
  return points;
}

double volume(const OctreeCell& c) {
  return std::ldexp(1.0, -3 * c.level);
}

// The largest level gap between a leaf and the leaves beside it (faces, edges, corners).
int worst_neighbour_gap(const CubeOctree& octree) {
  int worst = 0;
  for (const OctreeCell& c : octree.leaves) {
    const double size = std::ldexp(1.0, -c.level);
    for (int d = 0; d < 27; ++d) {
      const std::array<double, 3> centre{(c.index[0] + 0.5 + d % 3 - 1) * size,
                                         (c.index[1] + 0.5 + d / 3 % 3 - 1) * size,
                                         (c.index[2] + 0.5 + d / 9 - 1) * size};
      if (d == 13 || *std::min_element(centre.begin(), centre.end()) < 0 ||
          *std::max_element(centre.begin(), centre.end()) > 1)
        continue;
      worst = std::max(worst, c.level - octree.leaves[octree_leaf_at(octree, centre)].level);
    }
  }
  return worst;
}

void expect_tiling(const CubeOctree& octree, const std::vector<std::array<double, 3>>& points) {
  double total = 0;
  std::uint64_t held = 0;
  for (std::size_t l = 0; l < octree.leaves.size(); ++l) {
    total += volume(octree.leaves[l]);
    held += octree.points_per_leaf[l];
  }
  EXPECT_NEAR(total, 1.0, 1e-12);
  EXPECT_EQ(held, points.size());
  // Each point's leaf holds it: counting points by octree_leaf_at gives the same counts.
  std::vector<std::uint32_t> counted(octree.leaves.size(), 0);
  for (const auto& p : points) ++counted[octree_leaf_at(octree, p)];
  EXPECT_EQ(counted, octree.points_per_leaf);
}

TEST(CubeOctree, UniformPointsSplitEvenly) {
  const auto points = random_points(4000, 1.0, 7);
  const CubeOctree octree = build_cube_octree(points);
  expect_tiling(octree, points);
  for (std::size_t l = 0; l < octree.leaves.size(); ++l) EXPECT_LE(octree.points_per_leaf[l], 5u);
  EXPECT_EQ(octree.overfull, 0u);
  EXPECT_LE(worst_neighbour_gap(octree), 1);
  EXPECT_GE(octree.leaves.size(), 4000u / 5);
}

TEST(CubeOctree, ClusterIsDeepThereAndBalanced) {
  const auto points = random_points(3000, 0.05, 11);  // all within the corner's 1/20
  const CubeOctree balanced = build_cube_octree(points);
  expect_tiling(balanced, points);
  EXPECT_LE(worst_neighbour_gap(balanced), 1);
  EXPECT_GT(balanced.balance_splits, 0u);
  EXPECT_GE(balanced.deepest, 7);
  const CubeOctree raw = build_cube_octree(points, {.balance = false});
  expect_tiling(raw, points);
  EXPECT_GT(worst_neighbour_gap(raw), 1);  // what the balance is for
  EXPECT_LT(raw.leaves.size(), balanced.leaves.size());
}

TEST(CubeOctree, NoPointsIsTheUniformStartAndRepeatsStopAtTheDeepestLevel) {
  EXPECT_EQ(build_cube_octree({}).leaves.size(), 64u);
  EXPECT_EQ(build_cube_octree({}, {.initial_level = 1}).leaves.size(), 8u);
  const std::vector<std::array<double, 3>> same(9, {0.3, 0.3, 0.3});
  const CubeOctree octree = build_cube_octree(same, {.max_level = 5});
  EXPECT_EQ(octree.deepest, 5);
  EXPECT_EQ(octree.overfull, 1u);
  expect_tiling(octree, same);
  EXPECT_THROW(build_cube_octree({}, {.initial_level = 9, .max_level = 8}), InputError);
  EXPECT_THROW(build_cube_octree({}, {.max_per_cell = 0}), InputError);
  EXPECT_THROW(build_cube_octree({}, {.max_level = 17}), InputError);
}

TEST(CubeOctree, TetCentroidsOfAMappedBox) {
  const TetMesh box = test::make_tet_grid({0, 0, 0}, {2, 1, 1}, {8, 4, 4}, 0.1);
  const CubeMap map = map_to_cube(box);
  const auto centroids = tet_centroids(box, map);
  ASSERT_EQ(centroids.size(), box.tets.size());
  const CubeOctree octree = build_cube_octree(centroids);
  expect_tiling(octree, centroids);
  EXPECT_EQ(octree.overfull, 0u);
}

}  // namespace
}  // namespace tpmsfill
