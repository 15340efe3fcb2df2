// Seed 004's ring regions (issue 14, first increment): a blend region bounded by a closed
// outline in a plane, with inner and outer rings, round or mitered.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <random>
#include <tpmsfill/error.hpp>
#include <tpmsfill/fill.hpp>
#include <tpmsfill/lattice/design.hpp>
#include <tpmsfill/recipe.hpp>

#include "lattice/internal/polygon_distance.hpp"
#include "lattice/internal/polygon_miter.hpp"
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
  // A concave outline is mitered through its straight skeleton; one that crosses itself has
  // none: refused in one sentence.
  r.join = RingJoin::Miter;
  r.loop = {{0, 0}, {10, 0}, {10, 10}, {5, 3}, {0, 10}};
  LatticeDesign d;
  d.blends = {Blend{.region = r}};
  EXPECT_NO_THROW(require_valid(d));
  d.blends[0].region.loop = {{0, 0}, {10, 0}, {0, 10}, {10, 10}};
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

namespace {

using Point2 = std::array<double, 2>;

// The convex closed form: the largest signed distance to an edge's line (outward normals).
double largest_line_distance(const std::vector<Point2>& loop, Point2 p) {
  double area = 0, best = -INFINITY;
  for (std::size_t i = 0; i < loop.size(); ++i) {
    const Point2 a = loop[i], b = loop[(i + 1) % loop.size()];
    area += a[0] * b[1] - a[1] * b[0];
  }
  const double orientation = area > 0 ? 1 : -1;
  for (std::size_t i = 0; i < loop.size(); ++i) {
    const Point2 a = loop[i], b = loop[(i + 1) % loop.size()];
    const double ex = b[0] - a[0], ey = b[1] - a[1], length = std::hypot(ex, ey);
    best = std::max(best, orientation * (ey * (p[0] - a[0]) - ex * (p[1] - a[1])) / length);
  }
  return best;
}

bool inside_polygon(const std::vector<Point2>& loop, Point2 p) {
  bool inside = false;
  for (std::size_t i = 0; i < loop.size(); ++i) {
    const Point2 a = loop[i], b = loop[(i + 1) % loop.size()];
    if ((a[1] > p[1]) != (b[1] > p[1]) &&
        p[0] < a[0] + (p[1] - a[1]) * (b[0] - a[0]) / (b[1] - a[1]))
      inside = !inside;
  }
  return inside;
}

std::vector<Point2> star(int points, double outer, double inner) {
  std::vector<Point2> loop;
  for (int i = 0; i < 2 * points; ++i) {
    const double a = std::numbers::pi * i / points, radius = i % 2 ? inner : outer;
    loop.push_back({radius * std::cos(a), radius * std::sin(a)});
  }
  return loop;
}

}  // namespace

TEST(RingRegion, MiterSkeletonOfAConvexPolygonIsTheLargestEdgeLineDistance) {
  // An irregular convex heptagon, both orientations: the straight skeletons' faces give the
  // closed form to 1e-9 relative everywhere within the reach, and beyond it only farther (the
  // class's own closed form, taken for convex outlines unless told not to, too).
  std::vector<Point2> loop;
  const double radii[] = {6.5, 7, 6, 7.5, 6.8, 7.2, 6.2};
  for (int i = 0; i < 7; ++i) {
    const double a = 2 * std::numbers::pi * (i + 0.1 * (i % 3)) / 7;
    loop.push_back({3 + radii[i] * std::cos(a), -2 + radii[i] * std::sin(a)});
  }
  for (std::size_t i = 0; i < 7; ++i) {  // every corner turns left: convex
    const Point2 a = loop[i], b = loop[(i + 1) % 7], c = loop[(i + 2) % 7];
    ASSERT_GT((b[0] - a[0]) * (c[1] - b[1]) - (b[1] - a[1]) * (c[0] - b[0]), 0);
  }
  ASSERT_EQ(largest_line_distance(loop, {3, -2}) < 0, true);
  const double reach = 2.5;
  std::mt19937 random(7);
  std::uniform_real_distribution<double> x(-9, 15), y(-14, 10);
  for (int path = 0; path < 4; ++path) {
    const bool reversed = path % 2, skeleton = path < 2;
    std::vector<Point2> l = loop;
    if (reversed) std::reverse(l.begin(), l.end());
    const detail::PolygonMiterDistance miter(l, reach, !skeleton);
    int checked = 0;
    for (int n = 0; n < 20000; ++n) {
      const Point2 p{x(random), y(random)};
      const double expected = largest_line_distance(loop, p), got = miter(p);
      if (expected <= reach) {
        ++checked;
        ASSERT_NEAR(got, expected, 1e-9 * std::max(1.0, std::fabs(expected)))
            << p[0] << " " << p[1] << " reversed " << reversed << " skeleton " << skeleton;
      } else {
        ASSERT_GT(got, reach) << p[0] << " " << p[1];
      }
    }
    EXPECT_GT(checked, 5000);
    // The corners and the midpoints of the sides lie on the zero iso-line.
    for (std::size_t i = 0; i < l.size(); ++i) {
      const Point2 a = l[i], b = l[(i + 1) % l.size()];
      EXPECT_NEAR(miter(a), 0, 1e-12);
      EXPECT_NEAR(miter({0.5 * (a[0] + b[0]), 0.5 * (a[1] + b[1])}), 0, 1e-12);
    }
  }
}

TEST(RingRegion, MiterOfAnLShapeFollowsItsStraightSkeleton) {
  // The square 0..10 minus its quarter 5..10 x 5..10: a reflex corner at (5, 5). Each point's
  // value is the distance to the line of the edge whose offset front reaches it first.
  const std::vector<Point2> l = {{0, 0}, {10, 0}, {10, 5}, {5, 5}, {5, 10}, {0, 10}};
  struct Case {
    Point2 p;
    double value;
  };
  const Case cases[] = {
      {{2, 2}, -2},      // the lower-left corner's bisector: y = 0 and x = 0 both 2 away
      {{7, 2.5}, -2.5},  // the lower arm's ridge, between y = 0 and y = 5 (x = 10 is 3 away)
      {{2, 7}, -2},      // the upper arm, nearest x = 0
      // Inside at the reflex corner the inner front is mitered too: the fronts x = 5 - t and
      // y = 5 - t meet on the corner's bisector, so (4.5, 3), below it, is reached by
      // y = 5 - t at t = 2 (the Euclidean distance, to the corner, would be 2.06).
      {{4.5, 3}, -2},
      {{4, 4}, -1},  // on that bisector: both fronts at t = 1
      // Outside, in the notch, the outer fronts x = 5 + t (over y >= 5 + t) and y = 5 + t
      // (over x >= 5 + t) trim each other along the diagonal: the nearer line wins, so
      // (6, 6) is reached by both at t = 1 and (6, 8) by x = 5 + t at t = 1.
      {{6, 6}, 1},
      {{6, 8}, 1},
      // Beyond a convex corner the fronts extend to a mitered spike: the larger of the two
      // lines' distances, e.g. beyond (0, 0) max(1, 2) and beyond (10, 5) max(2, 1).
      {{-1, -2}, 2},
      {{12, 6}, 2},
      {{11, 6}, 1},
      {{5, 0}, 0},  // on the outline
      {{10, 2}, 0},
  };
  for (bool reversed : {false, true}) {
    std::vector<Point2> loop = l;
    if (reversed) std::reverse(loop.begin(), loop.end());
    const detail::PolygonMiterDistance miter(loop, 3);
    for (const Case& c : cases)
      EXPECT_NEAR(miter(c.p), c.value, 1e-9) << c.p[0] << " " << c.p[1] << " " << reversed;
    // Farther than the reach: only outside or inside is known.
    EXPECT_GT(miter({20, 20}), 3);
    EXPECT_GT(miter({-4, 13.5}), 3);
  }
}

TEST(RingRegion, MiterOfAStarIsContinuousAndZeroOnTheOutline) {
  // A five-pointed star (10 corners, 5 of them reflex): along random segments the value is
  // 1-Lipschitz wherever it is exact (within the reach), negative exactly inside, no larger
  // than the Euclidean distance, and zero on the outline.
  const std::vector<Point2> loop = star(5, 10, 4);
  const double reach = 3;
  const detail::PolygonMiterDistance miter(loop, reach);
  const detail::PolygonDistance round(loop, reach);
  std::mt19937 random(11);
  std::uniform_real_distribution<double> coordinate(-15, 15), angle(0, 2 * std::numbers::pi),
      along(0, 1);
  int steps = 0;
  for (int segment = 0; segment < 300; ++segment) {
    Point2 p{coordinate(random), coordinate(random)};
    const double a = angle(random), step = 0.013;
    double previous = miter(p);
    for (int n = 0; n < 400; ++n) {
      const Point2 q{p[0] + step * std::cos(a), p[1] + step * std::sin(a)};
      const double value = miter(q);
      ASSERT_EQ(value < 0, inside_polygon(loop, q)) << q[0] << " " << q[1] << " " << value;
      // Mitered offsets run ahead of round ones (spikes outside, sharp corners inside):
      // never farther from the outline than the Euclidean distance.
      if (std::fabs(round(q)) <= reach) {
        ASSERT_LE(std::fabs(value), std::fabs(round(q)) + 1e-9) << q[0] << " " << q[1];
      }
      if (std::fabs(previous) <= reach && std::fabs(value) <= reach) {
        ++steps;
        ASSERT_LE(std::fabs(value - previous), step + 1e-9) << q[0] << " " << q[1];
      }
      p = q, previous = value;
    }
  }
  EXPECT_GT(steps, 20000);
  for (std::size_t i = 0; i < loop.size(); ++i) {
    const Point2 a = loop[i], b = loop[(i + 1) % loop.size()];
    for (int n = 0; n < 20; ++n) {
      const double t = along(random);
      EXPECT_LT(std::fabs(miter({a[0] + t * (b[0] - a[0]), a[1] + t * (b[1] - a[1])})), 1e-9);
    }
  }
  // Beyond a tip the spike runs out along its bisector: there both edge lines are as far,
  // the larger of the tip's two lines' distances (its triangle's closed form).
  const Point2 beyond{loop[0][0] + 1, loop[0][1]};
  EXPECT_NEAR(miter(beyond), largest_line_distance({loop[9], loop[0], loop[1]}, beyond), 1e-9);
  EXPECT_GT(miter(beyond), 0.25);
}

TEST(RingRegion, MiteredStarBlendIsValidAndFills) {
  // A mitered I-WP star in a P lattice, which the convex-only version refused.
  Region r;
  r.shape = RegionShape::Polygon;
  r.point = {15, 15, 0};
  for (const Point2& q : star(5, 10, 4)) r.loop.push_back(q);
  r.inner = 1, r.outer = 2;
  r.join = RingJoin::Miter;
  FillOptions o;
  o.grid.voxel_size = 0.4;
  o.design.type = TpmsType::Primitive;
  o.design.cell = {5, 5, 5};
  Blend b;
  b.tpms = o.design;
  b.tpms.type = TpmsType::Iwp;
  b.region = r;
  b.transition = Transition::Beta;
  o.design.blends = {b};
  EXPECT_NO_THROW(require_valid(o.design));
  // Deep inside the star the blend has taken over; far outside it is absent.
  EXPECT_NEAR(weight(r, Transition::Beta, {15, 15, 1}), 1, 1e-9);
  EXPECT_NEAR(weight(r, Transition::Beta, {15, 28, 1}), 0, 1e-9);
  const FillResult result = fill(test::make_box({0, 0, 0}, {30, 30, 4}), o);
  EXPECT_TRUE(result.report.validation.valid());
  EXPECT_GT(result.mesh.triangles.size(), 1000u);
}
