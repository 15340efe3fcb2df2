// Stage "classify": inside/outside of grid nodes by one exact ray per row.
#include <gtest/gtest.h>

#include <cmath>
#include <tpmsfill/error.hpp>
#include <tpmsfill/sampling/classify.hpp>
#include <tpmsfill/sampling/spatial.hpp>

#include "test_util.hpp"

namespace tpmsfill {
namespace {

// Most tests here pin down the parity rule the method paper uses; the winding rule must agree
// with it on every closed, consistently oriented mesh (WindingAgreesWithParityOnClosedMeshes)
// and is tested on broken meshes in winding_test.cpp.
Occupancy classify(const TriangleSoup& soup, const Grid& grid,
                   InsideRule rule = InsideRule::Parity) {
  return classify_grid(build_index(soup), grid, {.rule = rule});
}

/// Calls f(i, j, k, value) for every node.
template <class F>
void for_each_node(const Mask& mask, const F& f) {
  const Grid& g = mask.grid;
  for (int k = 0; k < g.dims[2]; ++k)
    for (int j = 0; j < g.dims[1]; ++j)
      for (int i = 0; i < g.dims[0]; ++i) f(i, j, k, mask.values[g.index(i, j, k)]);
}

TEST(Classify, SphereNodesInsideIffInsideThePolyhedron) {
  const Vec3 c{0.13, -0.21, 0.37};
  const double r = 5.0;
  const TriangleSoup sphere = test::make_sphere(c, r, 4);  // 5,120 triangles
  const Grid grid = test::grid_around(bounding_box(sphere), 0.2, 0.5);
  const Occupancy occ = classify(sphere, grid);
  // The icosphere is inscribed: it lies inside the sphere and contains the sphere of radius
  // r - 0.02 (its largest sagitta at 4 levels is below 0.01 mm for r = 5).
  std::size_t inside = 0, checked = 0;
  for_each_node(occ.inside, [&](int i, int j, int k, std::uint8_t v) {
    const double d = norm(grid.node(i, j, k) - c);
    inside += v;
    if (d < r - 0.02) {
      EXPECT_EQ(v, 1) << i << " " << j << " " << k;
      ++checked;
    } else if (d > r + 1e-9) {
      EXPECT_EQ(v, 0) << i << " " << j << " " << k;
      ++checked;
    }
  });
  EXPECT_GT(inside, 10000u);
  EXPECT_GT(checked, occ.inside.values.size() * 95 / 100);
  EXPECT_EQ(occ.rows, static_cast<std::uint64_t>(grid.dims[1]) * grid.dims[2]);
  EXPECT_EQ(occ.odd_rows, 0u);
  EXPECT_EQ(occ.crossings % 2, 0u);
  // Rows through the ball cross twice; the rest not at all.
  EXPECT_NEAR(occ.volume, test::signed_volume(sphere), 0.005 * test::signed_volume(sphere));
}

TEST(Classify, CubeOnGridPlanesIsExact) {
  // Faces on grid planes, edges and vertices on grid rows: every ray through the cube's
  // rows at y or z = 0 or 1 passes through edges or vertices of the x faces' triangles.
  const TriangleSoup cube = test::make_box({0, 0, 0}, {1, 1, 1});
  Grid grid;
  grid.origin = {-0.5, -0.5, -0.5};
  grid.spacing = 0.25;
  grid.dims = {9, 9, 9};  // nodes at -0.5, -0.25, ..., 1.5
  for (const TriangleSoup& soup : {cube, test::unshare_points(cube), test::flip(cube)}) {
    const Occupancy occ = classify(soup, grid);
    // Perturbed rows (y + ε, z + ε²): y and z in [0, 1); nodes strictly inside along x.
    for_each_node(occ.inside, [&](int i, int j, int k, std::uint8_t v) {
      const Vec3 p = grid.node(i, j, k);
      const bool expected = p.x > 0 && p.x < 1 && p.y >= 0 && p.y < 1 && p.z >= 0 && p.z < 1;
      EXPECT_EQ(v, expected ? 1 : 0) << p.x << " " << p.y << " " << p.z;
    });
    EXPECT_EQ(occ.odd_rows, 0u);
    EXPECT_EQ(occ.crossings, 2u * 4 * 4);
    EXPECT_EQ(occ.volume, 1.0);
  }
}

TEST(Classify, UnweldedSoupGivesTheSameMask) {
  const TriangleSoup torus = test::make_torus(3, 1, 48, 24);
  const Grid grid = test::grid_around(bounding_box(torus), 0.1, 0.3);
  const Occupancy welded = classify(torus, grid);
  const Occupancy soup = classify(test::unshare_points(torus), grid);
  EXPECT_EQ(welded.inside.values, soup.inside.values);
  EXPECT_EQ(welded.volume, soup.volume);
  EXPECT_EQ(welded.crossings, soup.crossings);
}

TEST(Classify, FlippedFacesDoNotChangeParity) {
  const TriangleSoup sphere = test::make_sphere({0, 0, 0}, 2.0, 3);
  const Grid grid = test::grid_around(bounding_box(sphere), 0.1, 0.2);
  const Occupancy ref = classify(sphere, grid);
  EXPECT_EQ(classify(test::flip(sphere), grid).inside.values, ref.inside.values);
  EXPECT_EQ(classify(test::flip(sphere, 17), grid).inside.values, ref.inside.values);
}

TEST(Classify, TorusHoleIsOutside) {
  const double R = 3, r = 1;
  const TriangleSoup torus = test::make_torus(R, r, 64, 32);
  const Grid grid = test::grid_around(bounding_box(torus), 0.05, 0.25);
  const Occupancy occ = classify(torus, grid);
  for_each_node(occ.inside, [&](int i, int j, int k, std::uint8_t v) {
    const Vec3 p = grid.node(i, j, k);
    const double tube = std::hypot(std::hypot(p.x, p.y) - R, p.z);  // distance to the core
    // The polygonal torus leaves the smooth one on its inner side (chords of the inner
    // equator), so only nodes clear of the surface by the tessellation error are asserted.
    if (tube < r - 0.02) {
      EXPECT_EQ(v, 1) << p.x << " " << p.y << " " << p.z;
    }
    if (tube > r + 0.02) {
      EXPECT_EQ(v, 0) << p.x << " " << p.y << " " << p.z;
    }
  });
  EXPECT_EQ(occ.odd_rows, 0u);
  EXPECT_NEAR(occ.volume, test::signed_volume(torus), 0.01 * test::signed_volume(torus));
}

TEST(Classify, BoxWithAHoleHasOddRays) {
  const TriangleSoup open = test::make_box_with_hole({0, 0, 0}, {1, 1, 1});
  Grid grid;
  grid.origin = {-0.55, -0.55, -0.55};
  grid.spacing = 0.1;
  grid.dims = {22, 22, 22};
  const Occupancy occ = classify(open, grid);
  EXPECT_GT(occ.odd_rows, 0u);
  // Each odd row has one crossing (the -x face) and keeps nothing of it.
  EXPECT_EQ(occ.crossings, occ.odd_rows);
  EXPECT_EQ(occ.volume, 0.0);
}

TEST(Classify, TwoDisjointSpheres) {
  const Vec3 c1{-3, 0, 0}, c2{3.5, 0.5, 0};
  const TriangleSoup two =
      test::concat(test::make_sphere(c1, 2.0, 4), test::make_sphere(c2, 2.5, 4));
  const Grid grid = test::grid_around(bounding_box(two), 0.1, 0.3);
  const Occupancy occ = classify(two, grid);
  for_each_node(occ.inside, [&](int i, int j, int k, std::uint8_t v) {
    const Vec3 p = grid.node(i, j, k);
    const double d1 = norm(p - c1) - 2.0, d2 = norm(p - c2) - 2.5;
    if (d1 < -0.01 || d2 < -0.01) {
      EXPECT_EQ(v, 1);
    }
    if (d1 > 1e-9 && d2 > 1e-9) {  // the spheres are inscribed; nodes on a vertex may go either way
      EXPECT_EQ(v, 0);
    }
  });
  EXPECT_NEAR(occ.volume, test::signed_volume(two), 0.005 * test::signed_volume(two));
}

TEST(Classify, GridSmallerThanTheModelStillCountsCrossingsOutsideIt) {
  // Rows are whole lines: a grid inside the box is all inside.
  const TriangleSoup cube = test::make_box({0, 0, 0}, {4, 4, 4});
  Grid grid;
  grid.origin = {1.05, 1.05, 1.05};
  grid.spacing = 0.5;
  grid.dims = {4, 4, 4};
  const Occupancy occ = classify(cube, grid);
  for (std::uint8_t v : occ.inside.values) EXPECT_EQ(v, 1);
  EXPECT_DOUBLE_EQ(occ.volume, 16 * 1.5 * 0.25);
}

TEST(Classify, WindingAgreesWithParityOnClosedMeshes) {
  // Closed and outward: J is 0 or 1 everywhere, so both rules give the same nodes and volume.
  const TriangleSoup cube = test::make_box({0, 0, 0}, {1, 1, 1});
  Grid cube_grid;
  cube_grid.origin = {-0.5, -0.5, -0.5};
  cube_grid.spacing = 0.25;
  cube_grid.dims = {9, 9, 9};  // faces, edges and vertices on grid rows
  const TriangleSoup hollow =  // a ball with a cavity: the inner shell faces inward
      test::concat(test::make_sphere({0, 0, 0}, 3.0, 4),
                   test::flip(test::make_sphere({0.2, 0, 0}, 1.5, 3)));
  const std::vector<std::pair<TriangleSoup, Grid>> cases = {
      {cube, cube_grid},
      {test::unshare_points(cube), cube_grid},
      {test::make_torus(3, 1, 64, 32), test::grid_around({{-4, -4, -1}, {4, 4, 1}}, 0.1, 0.2)},
      {hollow, test::grid_around(bounding_box(hollow), 0.1, 0.2)},
      {test::make_sphere({0.3, 0.1, 0}, 3.0, 6),
       test::grid_around({{-3, -3, -3}, {3, 3, 3}}, 0.05, 0.1)},
  };
  for (const auto& [soup, grid] : cases) {
    const Occupancy parity = classify(soup, grid, InsideRule::Parity);
    const Occupancy winding = classify(soup, grid, InsideRule::Winding);
    EXPECT_EQ(winding.inside.values, parity.inside.values);
    EXPECT_EQ(winding.volume, parity.volume);
    EXPECT_EQ(winding.parity_disagreements, 0u);
    EXPECT_EQ(winding.overlap_rows, 0u);
    EXPECT_EQ(winding.cap_evaluations, 0u);
  }
}

TEST(Classify, WindingCountsOverlappingShellsInside) {
  // Two interpenetrating spheres: parity calls the lens where they overlap outside.
  const Vec3 c1{-1, 0, 0}, c2{1, 0.2, 0};
  const TriangleSoup two =
      test::concat(test::make_sphere(c1, 2.0, 4), test::make_sphere(c2, 2.0, 4));
  const Grid grid = test::grid_around(bounding_box(two), 0.1, 0.2);
  const Occupancy winding = classify(two, grid, InsideRule::Winding);
  const Occupancy parity = classify(two, grid, InsideRule::Parity);
  std::size_t lens = 0;
  for_each_node(winding.inside, [&](int i, int j, int k, std::uint8_t v) {
    const Vec3 p = grid.node(i, j, k);
    const double d1 = norm(p - c1) - 2.0, d2 = norm(p - c2) - 2.0;
    if (d1 < -0.01 && d2 < -0.01) {
      EXPECT_EQ(v, 1);
      EXPECT_EQ(parity.inside.values[grid.index(i, j, k)], 0);
      ++lens;
    }
  });
  EXPECT_GT(lens, 1000u);
  EXPECT_GT(winding.overlap_rows, 0u);
  EXPECT_GE(winding.parity_disagreements, lens);
}

TEST(Classify, DeterministicAcrossRuns) {
  const TriangleSoup sphere = test::make_sphere({0.3, 0.1, 0}, 3.0, 6);  // 81,920: two trees
  const Grid grid = test::grid_around(bounding_box(sphere), 0.05, 0.1);
  const Occupancy a = classify(sphere, grid), b = classify(sphere, grid);
  EXPECT_EQ(a.inside.values, b.inside.values);
  EXPECT_EQ(a.volume, b.volume);
}

TEST(Classify, CancelledByProgress) {
  struct Stop : Progress {
    bool report(double) override { return false; }
  } stop;
  const TriangleSoup sphere = test::make_sphere({0, 0, 0}, 3.0, 3);
  const Grid grid = test::grid_around(bounding_box(sphere), 0.05, 0.1);
  EXPECT_THROW(classify_grid(build_index(sphere), grid, {.progress = &stop}), Cancelled);
}

}  // namespace
}  // namespace tpmsfill
