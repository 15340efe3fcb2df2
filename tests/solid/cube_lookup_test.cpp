// The cube map's inverse (cube_lookup.hpp): I_G and I_M reproduce the box's affine map and a
// linear material, and give every point back at its own (u, v, w).
#include <gtest/gtest.h>

#include <cmath>
#include "solid/cube_lookup.hpp"

#include "test_util.hpp"

namespace tpmsfill {
namespace {

TEST(CubeLookup, BoxIsAffineAndLinearMaterialIsExact) {
  const Vec3 min{-1, 2, 0.5}, max{3, 3, 2};
  TetMesh box = test::make_tet_grid(min, max, {8, 3, 5}, 0.12);
  auto linear = [](Vec3 p) { return 2 * p.x - p.y + 3 * p.z; };
  for (const Vec3& p : box.points) box.material.push_back(linear(p));
  const CubeLookup lookup = build_cube_lookup(box, map_to_cube(box));
  test::Random numbers{12345};
  auto random = [&] { return numbers.next(); };
  for (int i = 0; i < 2000; ++i) {
    const std::array<double, 3> uvw{random(), random(), random()};
    const CubeSample s = cube_lookup(lookup, uvw);
    EXPECT_TRUE(s.inside);
    const Vec3 expected{min.x + uvw[0] * (max.x - min.x), min.y + uvw[1] * (max.y - min.y),
                        min.z + uvw[2] * (max.z - min.z)};
    EXPECT_LT(norm(s.position - expected), 1e-12);
    EXPECT_NEAR(s.material, linear(expected), 1e-11);
    double sum = 0;
    for (double w : s.weights) {
      EXPECT_GE(w, 0);
      sum += w;
    }
    EXPECT_NEAR(sum, 1, 1e-14);
  }
  // Outside the cube: clamped onto it.
  EXPECT_LT(norm(cube_lookup(lookup, {-0.5, 2, 0.5}).position - Vec3{min.x, max.y, 1.25}), 1e-12);
}

TEST(CubeLookup, EveryPointComesBackAtItsOwnImage) {
  TetMesh ball = test::make_tet_grid({-1, -1, -1}, {1, 1, 1}, {6, 6, 6}, 0.1);
  for (Vec3& p : ball.points) {
    const double x2 = p.x * p.x, y2 = p.y * p.y, z2 = p.z * p.z;
    p = {p.x * std::sqrt(1 - y2 / 2 - z2 / 2 + y2 * z2 / 3),
         p.y * std::sqrt(1 - z2 / 2 - x2 / 2 + z2 * x2 / 3),
         p.z * std::sqrt(1 - x2 / 2 - y2 / 2 + x2 * y2 / 3)};
  }
  const CubeMap map = map_to_cube(ball);
  const CubeLookup lookup = build_cube_lookup(ball, map);
  for (std::size_t v = 0; v < ball.points.size(); ++v)
    EXPECT_LT(norm(cube_lookup(lookup, map.uvw[v]).position - ball.points[v]), 1e-9) << v;
}

}  // namespace
}  // namespace tpmsfill
