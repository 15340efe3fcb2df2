// Seed 004's ring regions (issue 14, first increment): a blend region bounded by a closed
// outline in a plane, with inner and outer rings, round or mitered.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <tpmsfill/design.hpp>
#include <tpmsfill/error.hpp>
#include <tpmsfill/fill.hpp>
#include <tpmsfill/recipe.hpp>

#include "test_util.hpp"

using namespace tpmsfill;

namespace {

// The blended lattice's weight μ at p: the base is a gyroid network at level 0, the blend the
// same gyroid at level 0.5 mm, so φ = φ0 + 0.5 μ wherever neither is clamped.
double weight(const Region& region, Transition transition, Vec3 p) {
  LatticeDesign base;
  base.cell = {4, 4, 4};
  LatticeDesign blended = base;
  Blend b;
  b.tpms = base;
  b.tpms.level = 0.5;
  b.region = region;
  b.transition = transition;
  blended.blends = {b};
  return (field_value(design_source(blended), p) - field_value(design_source(base), p)) / 0.5;
}

double smoothstep(double x) {
  return x * x * (3 - 2 * x);
}

Region circle(double radius, int corners, double inner, double outer) {
  Region r;
  r.shape = RegionShape::Polygon;
  for (int i = 0; i < corners; ++i) {
    const double a = 2 * std::numbers::pi * i / corners;
    r.loop.push_back({radius * std::cos(a), radius * std::sin(a)});
  }
  r.inner = inner, r.outer = outer;
  return r;
}

}  // namespace

TEST(RingRegion, RoundRingsOfACircleFollowTheRadius) {
  // A 256-gon of radius 10, inner ring at 8, outer at 13: the seed's t = (r − 8)/5, and with
  // the Beta peak at 0.5 (smoothstep) the blended weight is 1 − smoothstep(t).
  const Region r = circle(10, 256, 2, 3);
  for (double radius : {7.0, 8.0, 8.7, 9.9, 10.5, 11.3, 12.8, 13.0, 14.0})
    for (double angle : {0.1, 1.3, 2.9}) {
      const Vec3 p{radius * std::cos(angle), radius * std::sin(angle), 0.37};
      const double t = std::clamp((radius - 8) / 5, 0.0, 1.0);
      EXPECT_NEAR(weight(r, Transition::Beta, p), 1 - smoothstep(t), 1.5e-3)
          << radius << " " << angle;
    }
}

TEST(RingRegion, MiteredRingsOfASquareAreSquares) {
  Region r;
  r.shape = RegionShape::Polygon;
  r.loop = {{-5, -5}, {5, -5}, {5, 5}, {-5, 5}};
  r.inner = 1, r.outer = 3;
  r.join = RingJoin::Miter;
  // On the square max(|x|, |y|) = 6.5 (1.5 mm outside the outline) μ is the same everywhere,
  // corners included; round joins would round the corner off instead.
  const double expected = 1 - smoothstep(2.5 / 4);
  for (const Vec3 p : {Vec3{6.5, 0, 1}, Vec3{6.5, 6.5, 1}, Vec3{-3, 6.5, 1}, Vec3{-6.5, -6.5, 2}})
    EXPECT_NEAR(weight(r, Transition::Beta, p), expected, 1e-6) << p.x << " " << p.y;
  r.join = RingJoin::Round;
  EXPECT_LT(weight(r, Transition::Beta, {6.5, 6.5, 1}), expected - 0.1);
  // A concave outline cannot be mitered yet: refused in one sentence.
  r.join = RingJoin::Miter;
  r.loop = {{0, 0}, {10, 0}, {10, 10}, {5, 3}, {0, 10}};
  LatticeDesign d;
  d.blends = {Blend{.region = r}};
  EXPECT_THROW(require_valid(d), InputError);
}

TEST(RingRegion, TheBlendIsContinuousAcrossTheBand) {
  // A five-pointed star, round joins, in a tilted plane: along a line across the whole band
  // (both edges, a reflex corner's neighbourhood), no step of 0.01 mm moves μ by more than
  // its steepest slope allows (Beta at 0.5 over a 3 mm band: 1.5/3 per mm).
  Region r;
  r.shape = RegionShape::Polygon;
  for (int i = 0; i < 10; ++i) {
    const double a = std::numbers::pi * i / 5, radius = i % 2 ? 4 : 10;
    r.loop.push_back({radius * std::cos(a), radius * std::sin(a)});
  }
  r.u = {1, 0, 0.3};
  r.v = {0, 1, 0};
  r.inner = 1.5, r.outer = 1.5;
  double previous = weight(r, Transition::Beta, {-15, 0.2, 0}), worst = 0;
  bool inside = false, outside = false;
  for (double x = -15; x <= 15; x += 0.01) {
    const double mu = weight(r, Transition::Beta, {x, 0.2, 0});
    worst = std::max(worst, std::fabs(mu - previous));
    inside = inside || mu > 0.999, outside = outside || mu < 0.001;
    previous = mu;
  }
  EXPECT_TRUE(inside && outside);
  EXPECT_LT(worst, 0.01 * 0.5 * 1.05 + 1e-6);
}

TEST(RingRegion, FillsValidAndRoundTripsThroughRecipes) {
  // The seed's set-up: a P main region with 5 mm cells, an I-WP star in a 40 x 40 x 8 slab.
  const std::string recipe = R"({
    "voxel": 0.25,
    "lattice": {"type": "primitive", "cell": 5},
    "blends": [{"lattice": {"type": "iwp"},
                "region": {"shape": "polygon", "point": [20, 20, 0], "u": [1, 0, 0],
                           "v": [0, 1, 0], "inner": 1, "outer": 2, "join": "round",
                           "loop": [[10, 0], [3, 3], [0, 10], [-3, 3], [-10, 0], [-3, -3],
                                    [0, -10], [3, -3]]},
                "transition": "beta", "peak": 0.3}]})";
  const FillOptions o = read_recipe(recipe, "ring.json");
  ASSERT_EQ(o.design.blends.size(), 1u);
  EXPECT_EQ(o.design.blends[0].region.loop.size(), 8u);
  EXPECT_EQ(read_recipe(recipe_json(o), "echo.json").design.blends[0].region.loop,
            o.design.blends[0].region.loop);
  const FillResult r = fill(test::make_box({0, 0, 0}, {40, 40, 8}), o);
  EXPECT_TRUE(r.report.validation.valid());
  EXPECT_GT(r.mesh.triangles.size(), 10000u);
  // Refusals: too few corners, no band.
  LatticeDesign d;
  Region bad;
  bad.shape = RegionShape::Polygon;
  bad.loop = {{0, 0}, {1, 0}};
  d.blends = {Blend{.region = bad}};
  EXPECT_THROW(require_valid(d), InputError);
  bad.loop.push_back({0, 1});
  bad.inner = -2, bad.outer = 1;
  d.blends = {Blend{.region = bad}};
  EXPECT_THROW(require_valid(d), InputError);
}
