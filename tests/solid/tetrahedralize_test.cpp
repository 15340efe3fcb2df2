// Stage "tetrahedralize" (tetrahedralize.hpp): closed surfaces filled with positive tets whose
// boundary stays within the asked distance of the surface, keeping its topology.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <tpmsfill/error.hpp>
#include <tpmsfill/io.hpp>
#include <tpmsfill/solid/cube_map.hpp>
#include <tpmsfill/solid/tetrahedralize.hpp>

#include "test_util.hpp"

namespace tpmsfill {
namespace {

double surface_area(const TriangleSoup& soup) {
  double area = 0;
  for (const Triangle& t : soup.triangles)
    area +=
        norm(cross(soup.points[t[1]] - soup.points[t[0]], soup.points[t[2]] - soup.points[t[0]])) /
        2;
  return area;
}

TEST(Tetrahedralize, SphereBecomesABallOfTheSameVolume) {
  const TriangleSoup sphere = test::make_sphere({1, 2, 3}, 5, 4);
  const TetrahedralizeOptions options{.cell_size = 1.0, .facet_distance = 0.05};
  const TetMesh ball = tetrahedralize(sphere, options);
  const TetMeshReport r = check_tet_mesh(ball);
  EXPECT_FALSE(ball_problem(r)) << *ball_problem(r);
  EXPECT_EQ(r.negative_tets, 0u);
  EXPECT_EQ(r.unused_points, 0u);
  EXPECT_GT(r.tets, 500u);
  // Boundary triangles lie within facet_distance of the surface (at their centres; their
  // corners lie on it), so the volumes differ by at most about area × distance.
  const double expected = test::signed_volume(sphere);
  EXPECT_NEAR(r.volume, expected, surface_area(sphere) * options.facet_distance);
  // And it maps onto the cube.
  const CubeMap map = map_to_cube(ball);
  EXPECT_EQ(map.flipped_boundary_faces, 0u);
}

TEST(Tetrahedralize, PartsThinnerThanTheCellsGetSmallerTets) {
  // A lentil: a sphere of radius 10 flattened to 1.2 thick at its middle, meshed with cells of
  // 3. Mesh_3 keeps a tet only where its circumcentre is inside, so tets as large as the cell
  // lose much of a part this thin (4.8 %); sized by the local thickness they keep all but
  // 1.5 % (1,924 and 12,791 tets).
  TriangleSoup lentil = test::make_sphere({0, 0, 0}, 10, 5);
  for (Vec3& p : lentil.points) p.z *= 0.06;
  const double volume = test::signed_volume(lentil);
  const TetMesh uniform = tetrahedralize(lentil, {.cell_size = 3, .cells_across_thin_parts = 0});
  const TetMesh sized = tetrahedralize(lentil, {.cell_size = 3});
  const TetMeshReport u = check_tet_mesh(uniform), s = check_tet_mesh(sized);
  EXPECT_FALSE(ball_problem(s)) << *ball_problem(s);
  EXPECT_NEAR(s.volume / volume, 1, 0.02);
  EXPECT_LT(u.volume / volume, 0.97);  // what the sizing is for
}

// A finer region gets tets of its size inside and leaves the rest as it was: the tets whose
// centroid lies inside the ball (radius 3 at (3, 0, 0) in a sphere of radius 5, cells of 1.5)
// have edges under 0.4 mm × 2.5 on average, those well outside keep the cell's.
TEST(Tetrahedralize, FinerRegionsGetSmallerTetsThere) {
  const TriangleSoup sphere = test::make_sphere({0, 0, 0}, 5, 4);
  const FinerRegion region{{3, 0, 0}, 3, 0.4};
  const TetMesh coarse = tetrahedralize(sphere, {.cell_size = 1.5});
  const TetMesh fine = tetrahedralize(sphere, {.cell_size = 1.5, .finer = {region}});
  EXPECT_FALSE(ball_problem(check_tet_mesh(fine)));
  // Mean edge length of the tets with their centroid within (or beyond) a distance of the
  // region's centre.
  auto mean_edge = [&](const TetMesh& m, bool inside, double distance) {
    double sum = 0;
    int n = 0;
    for (const Tet& t : m.tets) {
      const Vec3 c = 0.25 * (m.points[t[0]] + m.points[t[1]] + m.points[t[2]] + m.points[t[3]]);
      if ((norm(c - region.centre) < distance) != inside) continue;
      for (int k = 0; k < 4; ++k)
        for (int l = k + 1; l < 4; ++l) sum += norm(m.points[t[k]] - m.points[t[l]]), ++n;
    }
    return n > 0 ? sum / n : 0.0;
  };
  const double inside = mean_edge(fine, true, 2.5), outside = mean_edge(fine, false, 5);
  EXPECT_LT(inside, 2.5 * region.size);
  EXPECT_GT(outside, 0.5 * 1.5);
  EXPECT_LT(inside, 0.5 * mean_edge(coarse, true, 2.5));
  EXPECT_NEAR(outside, mean_edge(coarse, false, 5), 0.25 * outside);
  EXPECT_GT(fine.tets.size(), 2 * coarse.tets.size());
  EXPECT_THROW(tetrahedralize(sphere, {.cell_size = 1.5, .finer = {{{0, 0, 0}, 1, 0}}}),
               InputError);
}

TEST(Tetrahedralize, MesherStopsAtItsVertexBudgetWithARefusal) {
  // The lentil above sized by its thickness makes about 280 times the 46 tets its volume asks
  // for; with max_tets 100 its budget is 20 vertices, which it passes: refused, not run on.
  TriangleSoup lentil = test::make_sphere({0, 0, 0}, 10, 5);
  for (Vec3& p : lentil.points) p.z *= 0.06;
  try {
    tetrahedralize(lentil, {.cell_size = 3, .max_tets = 100});
    FAIL() << "the mesher ran past its vertex budget";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("stopped at 20 vertices"), std::string::npos) << e.what();
  }
  // By default the budget leaves the thin part its 280 times (more than 100 times the estimate).
  EXPECT_GT(check_tet_mesh(tetrahedralize(lentil, {.cell_size = 3})).tets, 4600u);
}

TEST(Tetrahedralize, TorusKeepsItsHandleAndTheCubeRefusesIt) {
  const TetMesh ring = tetrahedralize(test::make_torus(4, 1.5, 48, 24), {.cell_size = 0.8});
  const TetMeshReport r = check_tet_mesh(ring);
  ASSERT_TRUE(r.genus);
  EXPECT_EQ(*r.genus, 1);
  EXPECT_THROW(map_to_cube(ring), InputError);
}

TEST(Tetrahedralize, SameSurfaceSameTets) {
  const TriangleSoup sphere = test::make_sphere({0, 0, 0}, 3, 3);
  const TetMesh a = tetrahedralize(sphere, {.cell_size = 0.6});
  const TetMesh b = tetrahedralize(sphere, {.cell_size = 0.6});
  EXPECT_EQ(a.points, b.points);
  EXPECT_EQ(a.tets, b.tets);
}

TEST(Tetrahedralize, OpenAndNonManifoldSurfacesAreRefused) {
  const TriangleSoup box = test::make_box({0, 0, 0}, {1, 1, 1});
  try {
    tetrahedralize(test::without_triangles(box, [](const Vec3& c) { return c.z > 0.99; }));
    FAIL() << "an open box was accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("not closed"), std::string::npos) << e.what();
  }
  EXPECT_THROW(tetrahedralize(test::make_bow_tie()), InputError);
  // Two boxes through each other: closed and manifold, but no inside to fill.
  try {
    tetrahedralize(test::concat(box, test::make_box({0.5, 0.5, 0.5}, {1.5, 1.5, 1.5})));
    FAIL() << "a self-intersecting surface was accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("intersects itself"), std::string::npos) << e.what();
  }
  EXPECT_THROW(tetrahedralize(TriangleSoup{}), InputError);
  EXPECT_THROW(tetrahedralize(box, {.cell_size = -1}), InputError);
  EXPECT_THROW(tetrahedralize(box, {.cells_across_thin_parts = -1}), InputError);
  try {  // 5 / 1e-9 tets: refused at once, with the cell that would do
    tetrahedralize(box, {.cell_size = 0.001});
    FAIL() << "a cell of 1 um in a 1 mm box was accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("use a cell of at least"), std::string::npos) << e.what();
  }
}

TEST(Tetrahedralize, InwardSurfaceGivesTheSameSolid) {
  const TriangleSoup box = test::make_box({0, 0, 0}, {2, 1, 1});
  const TetMesh out = tetrahedralize(box, {.cell_size = 0.3});
  const TetMesh in = tetrahedralize(test::flip(box), {.cell_size = 0.3});
  // As an STL stores it: three points per triangle, merged by their equal coordinates.
  const TetMesh soup = tetrahedralize(test::unshare_points(box), {.cell_size = 0.3});
  EXPECT_NEAR(check_tet_mesh(soup).volume, 2.0, 1e-9);
  EXPECT_NEAR(check_tet_mesh(out).volume, 2.0, 1e-9);
  EXPECT_NEAR(check_tet_mesh(in).volume, 2.0, 1e-9);
}

// Mesh_3 stops on an assertion where protecting triceratops's edges sharper than 60° meets a
// point twice, and dumps its triangulation into the working directory first: the job is an
// InputError saying what to change, and nothing is left behind.
TEST(Tetrahedralize, MesherFailureIsARefusalWithoutLeftovers) {
  const TriangleSoup surface =
      read_mesh(std::filesystem::path(TPMSFILL_CGAL_MESHES) / "triceratops.off");
  const std::filesystem::path here = std::filesystem::current_path();
  const std::filesystem::path scratch =
      std::filesystem::temp_directory_path() / "tpmsfill-mesher-failure";
  std::filesystem::create_directories(scratch);
  std::filesystem::current_path(scratch);
  try {
    tetrahedralize(surface, {.feature_angle = 60});  // cells of the diagonal / 30
    ADD_FAILURE() << "Mesh_3 did not stop (then this test no longer tests the refusal)";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("feature angle of 180"), std::string::npos) << e.what();
  }
  EXPECT_TRUE(std::filesystem::is_empty(scratch));
  std::filesystem::current_path(here);
  std::filesystem::remove_all(scratch);
}

}  // namespace
}  // namespace tpmsfill
