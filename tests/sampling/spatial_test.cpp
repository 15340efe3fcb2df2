// Stage "spatial": which triangles the index keeps, and what it refuses.
#include <gtest/gtest.h>

#include <random>
#include <tpmsfill/error.hpp>
#include <tpmsfill/grid.hpp>
#include <tpmsfill/mesh/clean.hpp>
#include <tpmsfill/sampling/classify.hpp>
#include <tpmsfill/sampling/distance.hpp>
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

// borrow_points reads an STL-laid-out soup's corners in place: the same triangles, the same
// inside and the same closest points as the copy, near the origin and 300 mm out, with
// degenerate triangles left out and with hole caps after the borrowed ids.
TEST(Spatial, CornersReadInPlaceAnswerAsCopied) {
  std::mt19937 random(7);
  for (const double far : {0.0, 300.0}) {
    const Vec3 at{far, -far, 0.5 * far};
    for (const bool holed : {false, true}) {
      TriangleSoup model =
          holed ? test::make_box_with_hole(at, at + Vec3{4, 3, 2}) : test::make_torus(3, 1, 40, 20);
      if (!holed)
        for (Vec3& p : model.points) p = p + at;
      TriangleSoup soup = test::unshare_points(model);
      // A degenerate triangle (a repeated position) in the middle, laid out as STL does.
      const Vec3 a = soup.points[0], b = soup.points[1];
      soup.triangles.insert(soup.triangles.begin() + 5, Triangle{});
      soup.points.insert(soup.points.begin() + 15, {a, b, a});
      for (std::size_t t = 0; t < soup.triangles.size(); ++t) {
        const auto first = static_cast<std::uint32_t>(3 * t);
        soup.triangles[t] = {first, first + 1, first + 2};
      }
      const CleanResult cleaned = clean_soup(soup);
      const TriangleSoup* caps = holed ? &cleaned.caps : nullptr;
      ASSERT_EQ(holed, caps != nullptr && !cleaned.caps.triangles.empty());
      const MeshIndex copied = build_index(soup, {.hole_caps = caps});
      const MeshIndex borrowed = build_index(soup, {.hole_caps = caps, .borrow_points = true});
      EXPECT_EQ(borrowed.triangle_count(), soup.triangles.size() - 1 + borrowed.cap_count());
      EXPECT_EQ(borrowed.triangle_count(), copied.triangle_count());
      EXPECT_EQ(borrowed.bounds().min, copied.bounds().min);
      EXPECT_EQ(borrowed.bounds().max, copied.bounds().max);

      const Grid grid = make_grid(bounding_box(soup), {.voxel_size = 0.23});
      const Occupancy in_copied = classify_grid(copied, grid);
      const Occupancy in_borrowed = classify_grid(borrowed, grid);
      EXPECT_EQ(in_borrowed.inside.values, in_copied.inside.values);
      EXPECT_GT(std::count(in_borrowed.inside.values.begin(), in_borrowed.inside.values.end(), 1),
                100);

      std::uniform_real_distribution<double> u(-6, 6);
      std::vector<Vec3> points(500);
      for (Vec3& p : points) p = at + Vec3{u(random), u(random), u(random)};
      EXPECT_EQ(closest_points(borrowed, points), closest_points(copied, points));
    }
  }
}

}  // namespace
}  // namespace tpmsfill
