// Stage "spatial": which triangles the index keeps, and what it refuses.
#include <gtest/gtest.h>

#include <tpmsfill/error.hpp>
#include <tpmsfill/sampling/spatial.hpp>

#include "test_util.hpp"

namespace tpmsfill {
namespace {

TEST(Spatial, KeepsEveryProperTriangleOfASphere) {
  const TriangleSoup sphere = test::make_sphere({1, 2, 3}, 4.0, 3);
  const MeshIndex index = build_index(sphere);
  EXPECT_EQ(index.triangle_count(), sphere.triangles.size());
  const Box3 box = index.bounds();
  EXPECT_EQ(box.min, bounding_box(sphere).min);
  EXPECT_EQ(box.max, bounding_box(sphere).max);
}

TEST(Spatial, LeavesOutTrianglesWithARepeatedCorner) {
  TriangleSoup box = test::make_box({0, 0, 0}, {1, 1, 1});
  box.triangles.push_back({0, 0, 1});  // repeated index
  box.triangles.push_back({3, 5, 5});
  box.points.push_back({1, 1, 0});     // a copy of point 3, as STL repeats points
  box.triangles.push_back({3, 8, 6});  // repeated position
  box.triangles.push_back({0, 3, 5});  // proper (if inside the box): kept
  box.points.push_back({0.5, 0.5, 0});
  box.triangles.push_back({0, 9, 3});  // collinear corners: kept (rays and distances cope)
  const MeshIndex index = build_index(box);
  EXPECT_EQ(index.triangle_count(), 12u + 2u);
}

TEST(Spatial, UnsharedPointsGiveTheSameCount) {
  const TriangleSoup torus = test::make_torus(3, 1, 40, 20);
  EXPECT_EQ(build_index(test::unshare_points(torus)).triangle_count(), torus.triangles.size());
}

TEST(Spatial, LargeSoupsAreSplitIntoTwoTreesButCountedOnce) {
  const TriangleSoup sphere = test::make_sphere({0, 0, 0}, 1.0, 6);  // 81,920 triangles
  EXPECT_EQ(build_index(sphere).triangle_count(), sphere.triangles.size());
}

TEST(Spatial, EmptyOrDegenerateOnlySoupIsAnInputError) {
  EXPECT_THROW(build_index(TriangleSoup{}), InputError);
  TriangleSoup degenerate;
  degenerate.points = {{0, 0, 0}, {1, 0, 0}, {1, 0, 0}};
  degenerate.triangles = {{0, 0, 1}, {0, 1, 2}, {2, 2, 2}};
  EXPECT_THROW(build_index(degenerate), InputError);
}

TEST(Spatial, IndexOutOfRangeIsAnInputError) {
  TriangleSoup box = test::make_box({0, 0, 0}, {1, 1, 1});
  box.triangles.push_back({0, 1, 8});
  EXPECT_THROW(build_index(box), InputError);
}

TEST(Spatial, IndexOutlivesTheSoupAndMoves) {
  MeshIndex index = [] { return build_index(test::make_box({0, 0, 0}, {2, 1, 1})); }();
  MeshIndex moved = std::move(index);
  EXPECT_EQ(moved.triangle_count(), 12u);
  EXPECT_EQ(moved.bounds().max, (Vec3{2, 1, 1}));
}

}  // namespace
}  // namespace tpmsfill
