// Stage "clean": merging, dropping, orienting and capping, checked through the geometric
// facts they must establish (closedness of soup + caps, volumes, orientation).
#include <gtest/gtest.h>

#include <tpmsfill/check.hpp>
#include <tpmsfill/error.hpp>
#include <tpmsfill/mesh/clean.hpp>

#include "test_util.hpp"

namespace tpmsfill {
namespace {

/// The cleaned soup and its caps as one soup (caps carry copies of the border's points, so
/// check_mesh merges them with the soup's).
TriangleSoup closed_up(const CleanResult& c) {
  return test::concat(c.soup, c.caps);
}

TEST(Clean, ClosedOutwardMeshIsUnchanged) {
  const TriangleSoup torus = test::make_torus(3, 1, 32, 16);
  const CleanResult c = clean_soup(torus);
  EXPECT_TRUE(c.report.unchanged());
  EXPECT_EQ(c.report.holes, 0u);
  EXPECT_EQ(c.report.pieces, 1u);
  EXPECT_TRUE(c.caps.triangles.empty());
  EXPECT_EQ(c.soup.triangles, torus.triangles);
  EXPECT_EQ(c.soup.points.size(), torus.points.size());
}

TEST(Clean, InsideOutMeshIsReversed) {
  const TriangleSoup sphere = test::make_sphere({1, 2, 3}, 2.0, 3);
  const CleanResult c = clean_soup(test::flip(sphere));
  EXPECT_EQ(c.report.reversed_pieces, 1u);
  EXPECT_EQ(c.report.flipped_triangles, 0u);
  EXPECT_NEAR(test::signed_volume(c.soup), test::signed_volume(sphere), 1e-9);
}

TEST(Clean, ScatteredFlipsFollowTheMajority) {
  const TriangleSoup sphere = test::make_sphere({0, 0, 0}, 2.0, 3);
  TriangleSoup broken = sphere;
  for (long t = 0; t < 1280; t += 37) broken = test::flip(broken, t);
  const CleanResult c = clean_soup(broken);
  EXPECT_EQ(c.report.flipped_triangles, 35u);
  EXPECT_EQ(c.report.reversed_pieces, 0u);
  const MeshCheck check = check_mesh(c.soup);
  EXPECT_TRUE(check.valid()) << check.problems().front();
}

TEST(Clean, CavityWallStaysInward) {
  const TriangleSoup outer = test::make_sphere({0, 0, 0}, 3.0, 3);
  const TriangleSoup inner = test::flip(test::make_sphere({0.3, 0, 0}, 1.0, 3));
  const CleanResult c = clean_soup(test::concat(outer, inner));
  EXPECT_EQ(c.report.nested_pieces, 1u);
  EXPECT_EQ(c.report.reversed_pieces, 0u);
  EXPECT_NEAR(test::signed_volume(c.soup), test::signed_volume(outer) + test::signed_volume(inner),
              1e-9);
  // The same file inside out throughout: both shells turn, the cavity stays a cavity.
  const CleanResult d = clean_soup(test::flip(test::concat(outer, inner)));
  EXPECT_EQ(d.report.reversed_pieces, 2u);
  EXPECT_NEAR(test::signed_volume(d.soup), test::signed_volume(c.soup), 1e-9);
}

TEST(Clean, DuplicatesVoteAndCancel) {
  TriangleSoup sphere = test::make_sphere({0, 0, 0}, 2.0, 2);
  const std::size_t n = sphere.triangles.size();
  const Triangle a = sphere.triangles[5], b = sphere.triangles[6];
  sphere.triangles.push_back(a);                   // same orientation: one copy stays
  sphere.triangles.push_back({b[0], b[2], b[1]});  // opposite: the pair cancels
  sphere.triangles.push_back({a[0], a[1], a[1]});  // repeated corner
  const CleanResult c = clean_soup(sphere);
  EXPECT_EQ(c.report.duplicate_triangles, 1u);
  EXPECT_EQ(c.report.cancelled_triangles, 2u);
  EXPECT_EQ(c.report.repeated_corner_triangles, 1u);
  EXPECT_EQ(c.soup.triangles.size(), n - 1);
  EXPECT_EQ(c.report.holes, 1u);  // where triangle 6 was
  EXPECT_EQ(c.caps.triangles.size(), 1u);
}

TEST(Clean, CapsCloseEveryHole) {
  // Soup + caps is closed and bounds about the intact volume, for holes of many shapes.
  const TriangleSoup sphere = test::make_sphere({0, 0, 0}, 2.0, 4);
  TriangleSoup holes;
  holes.points = sphere.points;
  for (const Triangle& t : sphere.triangles) {
    const Vec3 p = sphere.points[t[0]];
    if (p.z > 1.85 || p.x < -1.85 || (p.y > 1.5 && p.x > 0.9)) continue;
    holes.triangles.push_back(t);
  }
  const CleanResult c = clean_soup(holes);
  EXPECT_EQ(c.report.holes, 3u);
  EXPECT_GT(c.report.border_edges, 0u);
  const MeshCheck check = check_mesh(closed_up(c), {.self_intersections = false});
  EXPECT_EQ(check.border_edges, 0u);
  EXPECT_TRUE(check.consistently_oriented());
  EXPECT_GT(test::signed_volume(closed_up(c)), 0.97 * test::signed_volume(sphere));
  EXPECT_LT(test::signed_volume(closed_up(c)), test::signed_volume(sphere));
  // The box with a missing face: one square hole, four border edges.
  const CleanResult box = clean_soup(test::make_box_with_hole({0, 0, 0}, {1, 1, 1}));
  EXPECT_EQ(box.report.holes, 1u);
  EXPECT_EQ(box.report.border_edges, 4u);
  EXPECT_NEAR(test::signed_volume(closed_up(box)), 1.0, 1e-12);
}

TEST(Clean, NonManifoldEdgesStillCloseUp) {
  // Three boxes sharing an edge pairwise and a bow-tie: the border chain stays closed.
  const TriangleSoup a = test::make_box({0, 0, 0}, {1, 1, 1});
  const TriangleSoup b = test::make_box({1, 1, 0}, {2, 2, 1});  // shares the edge x=y=1
  const CleanResult c = clean_soup(test::concat(test::concat(a, b), test::make_bow_tie()));
  const MeshCheck check = check_mesh(closed_up(c), {.self_intersections = false});
  EXPECT_EQ(check.border_edges, 0u);
  EXPECT_EQ(c.report.reversed_pieces, 0u);
}

TEST(Clean, RejectsIndicesOutOfRange) {
  TriangleSoup bad;
  bad.points = {{0, 0, 0}};
  bad.triangles = {{0, 1, 2}};
  EXPECT_THROW(clean_soup(bad), InputError);
}

TEST(Clean, EmptySoupGivesEmptyResult) {
  const CleanResult c = clean_soup(TriangleSoup{});
  EXPECT_TRUE(c.soup.triangles.empty());
  EXPECT_TRUE(c.caps.triangles.empty());
}

}  // namespace
}  // namespace tpmsfill
