// The tet mesh's checks and boundary (tet_mesh.hpp): counts, orientation, topology, genus.
#include <gtest/gtest.h>

#include <algorithm>
#include <set>
#include <tpmsfill/solid/tet_mesh.hpp>
#include <utility>

#include "test_util.hpp"

namespace tpmsfill {
namespace {

using test::make_tet_grid;

TEST(TetMesh, BoxIsABallWithTheBoxsVolumeAndSurface) {
  const TetMesh box = make_tet_grid({0, 0, 0}, {3, 2, 1}, {6, 4, 2}, 0.1);
  const TetMeshReport r = check_tet_mesh(box);
  EXPECT_EQ(r.tets, 6u * 6 * 4 * 2);
  EXPECT_EQ(r.points, 7u * 5 * 3);
  EXPECT_EQ(r.negative_tets + r.flat_tets + r.repeated_corner_tets, 0u);
  // Each side's cubes are split into two triangles.
  EXPECT_EQ(r.boundary_faces, 2u * 2 * (6 * 4 + 4 * 2 + 2 * 6));
  EXPECT_EQ(r.open_edges + r.pinched_vertices + r.overfull_faces, 0u);
  EXPECT_EQ(r.components, 1u);
  EXPECT_EQ(r.boundary_shells, 1u);
  EXPECT_EQ(r.euler_characteristic, 2);
  ASSERT_TRUE(r.genus);
  EXPECT_EQ(*r.genus, 0);
  EXPECT_NEAR(r.volume, 6.0, 1e-12);  // jittered inside, the box outside
  EXPECT_EQ(r.bounds.min, (Vec3{0, 0, 0}));
  EXPECT_EQ(r.bounds.max, (Vec3{3, 2, 1}));
  EXPECT_FALSE(ball_problem(r));
}

TEST(TetMesh, BoundaryIsOutwardAndEnclosesTheVolume) {
  const TetMesh box = make_tet_grid({-1, 0, 2}, {1, 1, 4}, {3, 3, 3}, 0.15);
  const TriangleSoup boundary = tet_boundary(box);
  EXPECT_EQ(boundary.triangles.size(), check_tet_mesh(box).boundary_faces);
  EXPECT_NEAR(test::signed_volume(boundary), 4.0, 1e-12);
}

TEST(TetMesh, AllNegativeTetsAreTheOtherConventionAndTurned) {
  TetMesh box = make_tet_grid({0, 0, 0}, {1, 1, 1}, {2, 2, 2});
  for (Tet& t : box.tets) std::swap(t[0], t[1]);
  const TetMeshReport r = check_tet_mesh(box);
  EXPECT_EQ(r.negative_tets, r.tets);
  EXPECT_FALSE(ball_problem(r));
  const TetMesh turned = with_positive_tets(box, r);
  const TetMeshReport after = check_tet_mesh(turned);
  EXPECT_EQ(after.negative_tets, 0u);
  EXPECT_NEAR(after.volume, 1.0, 1e-12);
  EXPECT_NEAR(test::signed_volume(tet_boundary(turned)), 1.0, 1e-12);
}

TEST(TetMesh, OneInvertedTetIsNamed) {
  TetMesh box = make_tet_grid({0, 0, 0}, {1, 1, 1}, {2, 2, 2});
  std::swap(box.tets[7][0], box.tets[7][1]);
  const TetMeshReport r = check_tet_mesh(box);
  EXPECT_EQ(r.negative_tets, 1u);
  ASSERT_TRUE(r.first_negative_tet);
  EXPECT_EQ(*r.first_negative_tet, 7u);
  const auto problem = ball_problem(r);
  ASSERT_TRUE(problem);
  EXPECT_NE(problem->find("1 tet is inverted"), std::string::npos) << *problem;
  EXPECT_NE(problem->find("tet 7"), std::string::npos) << *problem;
}

TEST(TetMesh, FlatTetAndRepeatedCornerAreRefused) {
  TetMesh box = make_tet_grid({0, 0, 0}, {1, 1, 1}, {1, 1, 1});
  TetMesh flat = box;
  flat.points.push_back({0.5, 0.5, 0});  // in the plane z = 0 with points 0, 1, 2
  flat.tets.push_back({0, 1, 2, static_cast<std::uint32_t>(flat.points.size() - 1)});
  const TetMeshReport r = check_tet_mesh(flat);
  EXPECT_EQ(r.flat_tets, 1u);
  EXPECT_NE(ball_problem(r)->find("no volume"), std::string::npos);

  TetMesh repeated = box;
  repeated.tets[0][3] = repeated.tets[0][0];
  EXPECT_EQ(check_tet_mesh(repeated).repeated_corner_tets, 1u);
  EXPECT_NE(ball_problem(check_tet_mesh(repeated))->find("repeats a corner"), std::string::npos);
}

TEST(TetMesh, ThroughHoleIsGenusOne) {
  // A 3 × 3 × 2 block without its middle column: a thick ring.
  const TetMesh ring = make_tet_grid({0, 0, 0}, {3, 3, 2}, {3, 3, 2}, 0,
                                     [](int i, int j, int) { return !(i == 1 && j == 1); });
  const TetMeshReport r = check_tet_mesh(ring);
  ASSERT_TRUE(r.genus);
  EXPECT_EQ(*r.genus, 1);
  EXPECT_EQ(r.euler_characteristic, 0);
  EXPECT_NEAR(r.volume, 16.0, 1e-12);
  const auto problem = ball_problem(r);
  ASSERT_TRUE(problem);
  EXPECT_NE(problem->find("genus 1"), std::string::npos) << *problem;
}

TEST(TetMesh, CavityIsASecondShell) {
  const TetMesh hollow = make_tet_grid({0, 0, 0}, {3, 3, 3}, {3, 3, 3}, 0, [](int i, int j, int k) {
    return !(i == 1 && j == 1 && k == 1);
  });
  const TetMeshReport r = check_tet_mesh(hollow);
  EXPECT_EQ(r.boundary_shells, 2u);
  EXPECT_EQ(r.euler_characteristic, 4);
  EXPECT_FALSE(r.genus);
  EXPECT_NE(ball_problem(r)->find("cavity"), std::string::npos);
}

TEST(TetMesh, PiecesAndPinchesAreFound) {
  // Two cubes of a 2 × 2 × 1 block on a diagonal: they share one edge of the boundary.
  const TetMesh diagonal =
      make_tet_grid({0, 0, 0}, {2, 2, 1}, {2, 2, 1}, 0, [](int i, int j, int) { return i == j; });
  const TetMeshReport r = check_tet_mesh(diagonal);
  EXPECT_EQ(r.components, 2u);
  EXPECT_GT(r.open_edges, 0u);  // the shared edge is in four boundary faces
  EXPECT_NE(ball_problem(r)->find("2 pieces"), std::string::npos);

  // Two cubes meeting at one corner only.
  const TetMesh corner = make_tet_grid({0, 0, 0}, {2, 2, 2}, {2, 2, 2}, 0,
                                       [](int i, int j, int k) { return i == j && j == k; });
  const TetMeshReport c = check_tet_mesh(corner);
  EXPECT_EQ(c.pinched_vertices, 1u);
  EXPECT_EQ(c.open_edges, 0u);
}

TEST(TetMesh, FaceInThreeTetsIsOverfull) {
  TetMesh mesh;
  mesh.points = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}, {0, 0, -1}, {0.2, 0.2, 2}};
  mesh.tets = {{0, 1, 2, 3}, {0, 2, 1, 4}, {0, 1, 2, 5}};
  const TetMeshReport r = check_tet_mesh(mesh);
  EXPECT_EQ(r.overfull_faces, 1u);
  EXPECT_NE(ball_problem(r)->find("more than two tets"), std::string::npos);
}

TEST(TetMesh, MaterialRangeAndNonFiniteValues) {
  TetMesh box = make_tet_grid({0, 0, 0}, {1, 1, 1}, {1, 1, 1});
  for (const Vec3& p : box.points) box.material.push_back(2 * p.x - p.z);
  TetMeshReport r = check_tet_mesh(box);
  EXPECT_TRUE(r.has_material);
  EXPECT_EQ(r.material_min, -1);
  EXPECT_EQ(r.material_max, 2);
  box.material[3] = std::numeric_limits<double>::quiet_NaN();
  r = check_tet_mesh(box);
  EXPECT_EQ(r.non_finite_material, 1u);
  EXPECT_NE(ball_problem(r)->find("not finite"), std::string::npos);
}

TEST(TetMesh, UnusedPointsAreCountedNotRefused) {
  TetMesh box = make_tet_grid({0, 0, 0}, {1, 1, 1}, {1, 1, 1});
  box.points.push_back({9, 9, 9});
  const TetMeshReport r = check_tet_mesh(box);
  EXPECT_EQ(r.unused_points, 1u);
  EXPECT_EQ(r.bounds.max, (Vec3{1, 1, 1}));
  EXPECT_FALSE(ball_problem(r));
}

// A slab one cell thick has every point on its boundary: each cube's inner diagonal (and the
// faces' diagonals between two slabs' cubes) is a chord. Split, none is left, and the solid,
// its boundary and a linear material are what they were.
TEST(TetMesh, ChordsAreSplitKeepingTheBoundaryVolumeAndMaterial) {
  TetMesh slab = make_tet_grid({0, 0, 0}, {3, 2, 1}, {3, 2, 1});
  auto linear = [](Vec3 p) { return p.x + 2 * p.y - p.z; };
  for (const Vec3& p : slab.points) slab.material.push_back(linear(p));
  const TetMeshReport before = check_tet_mesh(slab);
  const TetMesh split = with_chords_split(slab);
  const TetMeshReport after = check_tet_mesh(split);
  EXPECT_GT(split.points.size(), slab.points.size());
  EXPECT_GT(split.tets.size(), slab.tets.size());
  EXPECT_EQ(after.negative_tets + after.flat_tets + after.repeated_corner_tets, 0u);
  EXPECT_FALSE(ball_problem(after)) << *ball_problem(after);
  EXPECT_NEAR(after.volume, before.volume, 1e-12);
  // The boundary is the same triangles of the same points (new points are appended).
  auto sorted = [](std::vector<Triangle> t) {
    for (Triangle& f : t) std::rotate(f.begin(), std::min_element(f.begin(), f.end()), f.end());
    std::sort(t.begin(), t.end());
    return t;
  };
  EXPECT_EQ(sorted(tet_boundary(split).triangles), sorted(tet_boundary(slab).triangles));
  for (std::size_t v = 0; v < split.points.size(); ++v)
    EXPECT_NEAR(split.material[v], linear(split.points[v]), 1e-12);
  // No edge inside the solid has both ends on the boundary.
  std::vector<char> on_boundary(split.points.size(), 0);
  std::set<std::pair<std::uint32_t, std::uint32_t>> boundary_edges;
  for (const Triangle& f : tet_boundary(split).triangles)
    for (int i = 0; i < 3; ++i) {
      on_boundary[f[i]] = 1;
      boundary_edges.insert(std::minmax(f[i], f[(i + 1) % 3]));
    }
  std::size_t chords = 0;
  for (const Tet& t : split.tets)
    for (int i = 0; i < 4; ++i)
      for (int j = i + 1; j < 4; ++j)
        chords += on_boundary[t[i]] && on_boundary[t[j]] &&
                  !boundary_edges.count(std::minmax(t[i], t[j]));
  EXPECT_EQ(chords, 0u);
  // Splitting again changes nothing.
  const TetMesh again = with_chords_split(split);
  EXPECT_EQ(again.points.size(), split.points.size());
  EXPECT_EQ(again.tets, split.tets);
}

}  // namespace
}  // namespace tpmsfill
