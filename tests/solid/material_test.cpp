// Stage "material" (material.hpp): each material function against the values it must give.
#include <gtest/gtest.h>

#include <cmath>
#include <tpmsfill/error.hpp>
#include <tpmsfill/material.hpp>

#include "test_util.hpp"

namespace tpmsfill {
namespace {

using test::make_tet_grid;

TEST(Material, DistanceToAPoint) {
  const TetMesh box = make_tet_grid({0, 0, 0}, {2, 1, 1}, {4, 2, 2}, 0.1);
  const Vec3 centre{0.3, 0.2, 0.9};
  const std::vector<double> m = distance_material(box, centre);
  ASSERT_EQ(m.size(), box.points.size());
  for (std::size_t v = 0; v < m.size(); ++v) EXPECT_EQ(m[v], norm(box.points[v] - centre));
}

TEST(Material, LinearRampSpansTheMeshByDefault) {
  const TetMesh box = make_tet_grid({1, 0, 0}, {4, 1, 1}, {6, 2, 2}, 0.1);
  const std::vector<double> m =
      ramp_material(box, {.shape = RampShape::Linear, .axis = {1, 0, 0}, .start = 2, .end = 5});
  for (std::size_t v = 0; v < m.size(); ++v)
    EXPECT_NEAR(m[v], 2 + (box.points[v].x - 1), 1e-12);  // 2 at x = 1 to 5 at x = 4
  EXPECT_THROW(ramp_material(box, {.shape = RampShape::Depth}), InputError);
  EXPECT_THROW(ramp_material(box, {.axis = {0, 0, 0}}), InputError);
}

TEST(Material, VolumeIsTrilinearAndReproducesLinearFunctions) {
  ScalarVolume ct;
  ct.dims = {5, 4, 3};
  ct.spacing = {0.5, 0.5, 0.5};
  ct.origin = {-0.25, -0.25, -0.25};
  auto linear = [](Vec3 p) { return 2 * p.x + 3 * p.y - p.z + 1; };
  for (int k = 0; k < 3; ++k)
    for (int j = 0; j < 4; ++j)
      for (int i = 0; i < 5; ++i)
        ct.values.push_back(linear({-0.25 + 0.5 * i, -0.25 + 0.5 * j, -0.25 + 0.5 * k}));
  // The cell centres span [-0.25, 1.75] × [-0.25, 1.25] × [-0.25, 0.75].
  const TetMesh inside = make_tet_grid({0, 0, 0}, {1.5, 1, 0.5}, {3, 2, 2}, 0.1);
  std::uint64_t outside = 99;
  const std::vector<double> m = volume_material(inside, ct, &outside);
  EXPECT_EQ(outside, 0u);
  for (std::size_t v = 0; v < m.size(); ++v) EXPECT_NEAR(m[v], linear(inside.points[v]), 1e-12);
  // Beyond the centres the border value holds; beyond the volume's box points are counted.
  const TetMesh wide = make_tet_grid({-1, 0, 0}, {3, 1, 0.5}, {4, 1, 1});
  const std::vector<double> w = volume_material(wide, ct, &outside);
  EXPECT_GT(outside, 0u);
  for (std::size_t v = 0; v < w.size(); ++v) {
    Vec3 p = wide.points[v];
    p.x = std::clamp(p.x, -0.25, 1.75);
    EXPECT_NEAR(w[v], linear(p), 1e-12);
  }
  ScalarVolume unitless = ct;
  unitless.spacing = {};
  EXPECT_THROW(volume_material(inside, unitless), InputError);
}

TEST(Material, BottomBoundaryPoints) {
  const TetMesh box = make_tet_grid({0, 0, 0}, {2, 1, 3}, {4, 2, 6}, 0.1);
  const auto bottom = bottom_boundary_points(box, {0, 0, 1}, 0);
  EXPECT_EQ(bottom.size(), 5u * 3);
  for (std::uint32_t v : bottom) EXPECT_EQ(box.points[v].z, 0);
  EXPECT_EQ(bottom_boundary_points(box, {0, 0, -2}, 0).size(), 5u * 3);  // the top
  EXPECT_THROW(bottom_boundary_points(box, {0, 0, 0}, 0), InputError);
}

TEST(Material, GeodesicFromTheBottomOfATallBox) {
  // On the sides of a box the geodesic distance to its bottom face is the height; on its top,
  // the height plus the way to the nearest side edge. Inside, the harmonic extension of those.
  const double height = 4;
  const TetMesh box = make_tet_grid({0, 0, 0}, {1, 1, height}, {6, 6, 24});
  const auto bottom = bottom_boundary_points(box, {0, 0, 1}, 0);
  const std::vector<double> m = geodesic_material(box, bottom);
  ASSERT_EQ(m.size(), box.points.size());
  for (std::uint32_t v : bottom) EXPECT_EQ(m[v], 0);
  const double cell = 1.0 / 6;
  double worst_side = 0;
  for (std::size_t v = 0; v < m.size(); ++v) {
    const Vec3 p = box.points[v];
    EXPECT_GE(m[v], 0);
    EXPECT_LE(m[v], height + 0.5 + cell);
    const bool side = p.x == 0 || p.x == 1 || p.y == 0 || p.y == 1;
    if (side) worst_side = std::max(worst_side, std::abs(m[v] - p.z));
  }
  // The heat method smooths by about one edge length.
  EXPECT_LT(worst_side, cell);
  EXPECT_THROW(geodesic_material(box, {}), InputError);
}

}  // namespace
}  // namespace tpmsfill
