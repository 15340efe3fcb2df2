// Point inversion G⁻¹(p) (solid_inverse.hpp): points of a fitted warped box come back at their
// own parameters, with the material there; points outside the solid are not inside.
#include <gtest/gtest.h>

#include <cmath>
#include <tpmsfill/solid/cube_map.hpp>
#include <tpmsfill/solid/solid_inverse.hpp>

#include "test_util.hpp"

namespace tpmsfill {
namespace {

TEST(SolidInverse, ImagesComeBackAtTheirParameters) {
  TetMesh blob = test::make_tet_grid({0, 0, 0}, {20, 10, 10}, {10, 5, 5}, 0.1);
  for (Vec3& p : blob.points)
    p = Vec3{p.x + 2 * std::sin(0.3 * p.y), p.y + 1.5 * std::sin(0.2 * p.z + 0.1 * p.x),
             p.z * (1 + 0.03 * p.x)};
  for (const Vec3& p : blob.points) blob.material.push_back(0.1 * p.x + std::sin(0.3 * p.z));
  const SolidFit fit = fit_solid_spline(blob, map_to_cube(blob), {.refinements = 1});
  ASSERT_EQ(fit.rounds.back().folded_samples, 0u);  // a bijection: one preimage per point
  const SolidLocator locator = build_solid_locator(fit.spline);
  test::Random random{17};
  auto next = [&] { return random.next(); };
  int worst_iterations = 0;
  for (int n = 0; n < 300; ++n) {
    const std::array<double, 3> x = {0.02 + 0.96 * next(), 0.02 + 0.96 * next(),
                                     0.02 + 0.96 * next()};
    const SolidPoint at = evaluate_solid(fit.spline, x);
    const Preimage back = invert_solid(fit.spline, locator, at.position);
    ASSERT_TRUE(back.inside) << n << ": left " << back.distance << " mm";
    EXPECT_LT(back.distance, 1e-9 * locator.size);
    for (int a = 0; a < 3; ++a) EXPECT_NEAR(back.uvw[a], x[a], 1e-7);
    const std::optional<double> m = material_at(fit.spline, locator, at.position);
    ASSERT_TRUE(m.has_value());
    EXPECT_NEAR(*m, at.material, 1e-7);
    worst_iterations = std::max(worst_iterations, back.iterations);
  }
  EXPECT_LE(worst_iterations, 30);
  // Outside: beyond the box's far end, and far away.
  for (const Vec3 p : {Vec3{40, 5, 5}, Vec3{10, 5, -30}, Vec3{1e6, 0, 0}}) {
    const Preimage out = invert_solid(fit.spline, locator, p);
    EXPECT_FALSE(out.inside);
    EXPECT_GT(out.distance, 1.0);
    EXPECT_FALSE(material_at(fit.spline, locator, p).has_value());
  }
}

}  // namespace
}  // namespace tpmsfill
