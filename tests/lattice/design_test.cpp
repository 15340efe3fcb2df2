// TpmsType design: every TPMS type as a distance, porosity and thickness you ask for, rotation,
// grading, blending, skins, recipes and custom fields — each judged on the field or on fill()'s
// validated output, with the tolerance stated.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <random>
#include <tpmsfill/error.hpp>
#include <tpmsfill/fill.hpp>
#include <tpmsfill/lattice/design.hpp>
#include <tpmsfill/mesh/components.hpp>
#include <tpmsfill/mesh/validate.hpp>
#include <tpmsfill/recipe.hpp>
#include <tpmsfill/sampling/classify.hpp>
#include <tpmsfill/sampling/spatial.hpp>

#include "test_util.hpp"

using namespace tpmsfill;

namespace {

FillOptions cube_job(double voxel, const TpmsOptions& lattice) {
  FillOptions o;
  o.grid.voxel_size = voxel;
  static_cast<TpmsOptions&>(o.design) = lattice;
  return o;
}

// A point of the zero set of `phi` on the segment a–b (phi(a) and phi(b) of opposite signs).
template <class F>
Vec3 zero_between(const F& phi, Vec3 a, Vec3 b) {
  double fa = phi(a);
  for (int it = 0; it < 60; ++it) {
    const Vec3 m = 0.5 * (a + b);
    const double fm = phi(m);
    if ((fm < 0) == (fa < 0))
      a = m, fa = fm;
    else
      b = m;
  }
  return 0.5 * (a + b);
}

// |∇φ| by central differences.
template <class F>
double gradient_norm(const F& phi, Vec3 p, double h = 1e-5) {
  const double gx = phi(p + Vec3{h, 0, 0}) - phi(p - Vec3{h, 0, 0});
  const double gy = phi(p + Vec3{0, h, 0}) - phi(p - Vec3{0, h, 0});
  const double gz = phi(p + Vec3{0, 0, h}) - phi(p - Vec3{0, 0, h});
  return std::sqrt(gx * gx + gy * gy + gz * gz) / (2 * h);
}

// Zero-set points of φ_TPMS found along random segments in one cell.
template <class F>
std::vector<Vec3> surface_points(const F& phi, int wanted, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(0, 2);
  std::vector<Vec3> points;
  for (int tries = 0; tries < 20 * wanted && static_cast<int>(points.size()) < wanted; ++tries) {
    const Vec3 a{u(rng), u(rng), u(rng)}, b{u(rng), u(rng), u(rng)};
    if ((phi(a) < 0) != (phi(b) < 0)) points.push_back(zero_between(phi, a, b));
  }
  return points;
}

// Fraction of a grid's nodes that the output mesh encloses, per slab of nodes along z.
std::vector<double> solid_fraction_per_slab(const TriangleSoup& mesh, const Box3& box,
                                            double spacing, int slabs) {
  Grid g;
  g.spacing = spacing;
  g.origin = box.min + Vec3{spacing / 2, spacing / 2, spacing / 2};
  const Vec3 size = box.size();
  g.dims = {static_cast<int>(size.x / spacing), static_cast<int>(size.y / spacing),
            static_cast<int>(size.z / spacing)};
  const Occupancy occupancy = classify_grid(build_index(mesh), g);
  std::vector<double> solid(slabs, 0), count(slabs, 0);
  for (int k = 0; k < g.dims[2]; ++k)
    for (int j = 0; j < g.dims[1]; ++j)
      for (int i = 0; i < g.dims[0]; ++i) {
        const int s = std::min(slabs - 1, k * slabs / g.dims[2]);
        solid[s] += occupancy.inside.values[g.index(i, j, k)];
        count[s] += 1;
      }
  for (int s = 0; s < slabs; ++s) solid[s] /= count[s];
  return solid;
}

// Largest change of phi between neighbouring samples h apart along the segment a–b. A
// continuous field's shrinks with h; a jump (a torn cell) stays.
template <class F>
double largest_step(const F& phi, Vec3 a, Vec3 b, double h) {
  const int n = static_cast<int>(norm(b - a) / h);
  double largest = 0, previous = phi(a);
  for (int s = 1; s <= n; ++s) {
    const double v = phi(a + (static_cast<double>(s) / n) * (b - a));
    largest = std::max(largest, std::fabs(v - previous));
    previous = v;
  }
  return largest;
}

}  // namespace

TEST(Design, EveryTypeIsAFirstOrderDistanceAtItsSurface) {
  // f/|∇f| has a unit gradient on the zero set exactly when ∇f is right: a wrong derivative in
  // the type table shows up as |∇φ| ≠ 1. Rotated, with an anisotropic cell and an origin shift.
  for (TpmsType type : test::kAllTpmsTypes) {
    for (const Mat3& rotation : {Mat3{}, rotation_from_euler({20, -35, 50})}) {
      const TpmsOptions o{
          .type = type, .cell = {2, 2.5, 1.5}, .origin = {0.3, -0.2, 0.1}, .rotation = rotation};
      auto phi = [&](Vec3 p) { return static_cast<double>(test::tpms_value(p, o)); };
      const auto points = surface_points(phi, 40, 7);
      ASSERT_GE(points.size(), 20u) << tpms_type_name(type);
      for (Vec3 p : points)
        EXPECT_NEAR(gradient_norm(phi, p, 1e-4), 1.0, 0.02) << tpms_type_name(type);
    }
  }
}

TEST(Design, NamesRoundTripAndUnknownNamesListTheKnown) {
  for (TpmsType type : test::kAllTpmsTypes)
    EXPECT_EQ(tpms_type_from_name(tpms_type_name(type)), type);
  EXPECT_EQ(tpms_type_from_name("schwarz-d"), TpmsType::Diamond);
  try {
    tpms_type_from_name("gyroidd");
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("lidinoid"), std::string::npos);
  }
}

TEST(Design, RotationTurnsTheField) {
  // φ with rotation R at p equals φ without it at Rᵀp (origin 0); a quarter turn about z maps
  // the cubic primitive lattice onto itself.
  const Mat3 r = rotation_from_euler({10, 20, 30});
  const TpmsOptions turned{.type = TpmsType::Gyroid, .rotation = r},
      plain{.type = TpmsType::Gyroid};
  const TpmsOptions quarter{.type = TpmsType::Primitive,
                            .rotation = rotation_from_euler({0, 0, 90})};
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(-3, 3);
  for (int n = 0; n < 200; ++n) {
    const Vec3 p{u(rng), u(rng), u(rng)};
    EXPECT_NEAR(test::tpms_value(p, turned), test::tpms_value(r.transposed() * p, plain), 1e-5);
    EXPECT_NEAR(test::tpms_value(p, quarter),
                test::tpms_value(p, TpmsOptions{.type = TpmsType::Primitive}), 1e-5);
  }
  EXPECT_THROW(require_valid(TpmsOptions{.rotation = Mat3{{1, 0, 0, 0, 1, 0, 0, 0, -1}}}),
               InputError);
  EXPECT_THROW(require_valid(TpmsOptions{.rotation = Mat3{{2, 0, 0, 0, 1, 0, 0, 0, 1}}}),
               InputError);
}

TEST(Design, PorosityWithinOnePercentForEveryTypeNetworkAndSheet) {
  // A cube of 2 × 2 × 2 whole cells (the lattice is periodic, so it measures the cell), at
  // a = T/40: the output's porosity is within ±1 % of the target for every type and style.
  const TriangleSoup cube = test::make_box({0, 0, 0}, {4, 4, 4});
  for (TpmsType type : test::kAllTpmsTypes)
    for (TpmsStyle style : {TpmsStyle::Network, TpmsStyle::Sheet})
      for (double target : {0.7}) {
        FillOptions o = cube_job(0.05, {.type = type, .style = style, .porosity = target});
        o.keep_islands = true;
        o.check_self_intersections = false;
        const FillResult r = fill(cube, o);
        EXPECT_NEAR(r.report.porosity(), target, 0.01)
            << tpms_label(o.design) << " level " << r.report.level << " thickness "
            << r.report.thickness;
      }
}

TEST(Design, PorositySolveIsMonotoneAndReachesTheExtremes) {
  for (TpmsStyle style : {TpmsStyle::Network, TpmsStyle::Sheet}) {
    const CellSamples cell = sample_cell({.type = TpmsType::Iwp, .style = style});
    double previous = style == TpmsStyle::Network ? -HUGE_VAL : HUGE_VAL;
    for (double p : {0.1, 0.3, 0.5, 0.7, 0.9, 0.97}) {
      const double v = level_for_porosity(cell, style, p);
      // More void: a higher network level, a thinner sheet.
      if (style == TpmsStyle::Network)
        EXPECT_GT(v, previous);
      else
        EXPECT_LT(v, previous);
      previous = v;
      TpmsOptions o{.type = TpmsType::Iwp, .style = style};
      (style == TpmsStyle::Network ? o.level : o.thickness) = v;
      EXPECT_NEAR(1 - tpms_solid_fraction(o), p, 0.002);
    }
    EXPECT_THROW(level_for_porosity(cell, style, 1.0), InputError);
  }
}

TEST(Design, SheetWallsHaveTheRequestedThicknessAlongTheNormal) {
  // Sample points of the output's surface away from the cube's faces; the wall thickness
  // there is the distance along the inward normal to the wall's other side. The median over
  // the samples is within 10 % of the requested thickness (a = 0.05 mm, t = 0.3 mm).
  const TriangleSoup cube = test::make_box({0, 0, 0}, {4, 4, 4});
  for (TpmsType type : test::kAllTpmsTypes) {
    FillOptions o = cube_job(0.05, {.type = type, .style = TpmsStyle::Sheet, .thickness = 0.3});
    o.check_self_intersections = false;
    const TriangleSoup mesh = fill(cube, o).mesh;
    std::vector<double> thickness;
    for (std::size_t t = 0; t < mesh.triangles.size() && thickness.size() < 150; t += 97) {
      const auto& tri = mesh.triangles[t];
      const Vec3 a = mesh.points[tri[0]], b = mesh.points[tri[1]], c = mesh.points[tri[2]];
      const Vec3 centroid = (1.0 / 3) * (a + b + c);
      if (std::min({centroid.x, centroid.y, centroid.z}) < 0.5 ||
          std::max({centroid.x, centroid.y, centroid.z}) > 3.5)
        continue;
      Vec3 n = cross(b - a, c - a);
      n = (-1.0 / norm(n)) * n;  // inward
      const Vec3 start = centroid + 1e-6 * n;
      double nearest = HUGE_VAL;
      for (const auto& other : mesh.triangles) {  // Möller–Trumbore
        const Vec3 p0 = mesh.points[other[0]], e1 = mesh.points[other[1]] - p0,
                   e2 = mesh.points[other[2]] - p0;
        const Vec3 q = cross(n, e2);
        const double det = dot(e1, q);
        if (std::fabs(det) < 1e-14) continue;
        const Vec3 s = start - p0;
        const double u = dot(s, q) / det;
        if (u < 0 || u > 1) continue;
        const Vec3 r = cross(s, e1);
        const double v = dot(n, r) / det;
        if (v < 0 || u + v > 1) continue;
        const double d = dot(e2, r) / det;
        if (d > 1e-9) nearest = std::min(nearest, d);
      }
      if (nearest < 1.0) thickness.push_back(nearest);
    }
    ASSERT_GE(thickness.size(), 50u);
    std::nth_element(thickness.begin(), thickness.begin() + thickness.size() / 2, thickness.end());
    EXPECT_NEAR(thickness[thickness.size() / 2], 0.3, 0.03) << tpms_type_name(type);
  }
}

TEST(Design, GradedPorosityIsMonotoneAlongTheAxis) {
  // Porosity 0.8 at the bottom to 0.5 at the top of a 8 mm cube: the solid fraction of the
  // output, measured per slab of 1 mm, rises slab by slab, and the end slabs are within 5 % of
  // the ramp's values there.
  const TriangleSoup cube = test::make_box({0, 0, 0}, {8, 8, 8});
  FillOptions o = cube_job(0.1, {.type = TpmsType::Gyroid});
  o.design.grading.push_back(
      {Graded::Porosity,
       {.shape = RampShape::Linear, .axis = {0, 0, 1}, .start = 0.8, .end = 0.5}});
  const TriangleSoup mesh = fill(cube, o).mesh;
  const auto solid = solid_fraction_per_slab(mesh, bounding_box(cube), 0.05, 8);
  for (int s = 1; s < 8; ++s) EXPECT_GT(solid[s], solid[s - 1]) << s;
  EXPECT_NEAR(1 - solid[0], 0.8 - 0.3 / 16, 0.05);
  EXPECT_NEAR(1 - solid[7], 0.5 + 0.3 / 16, 0.05);
}

TEST(Design, CellGradedByAVolumeOrDepthMixesALadderOfCellSizes) {
  // A volume whose value is x (0 to 20 mm) grades the cell 1.5 → 3 mm. No phase follows a
  // field's level sets, so the design is made at the cell sizes 1.5 · 2^(k/4), k = 0..4
  // (neighbours 1.19× apart), and mixed in log size: where x asks for one of them the field is
  // that lattice's own, and it is continuous everywhere.
  ScalarVolume v{.dims = {41, 3, 3}, .spacing = {0.5, 0.5, 0.5}, .origin = {0, 0, 0}, .values = {}};
  for (int n = 0; n < 41 * 9; ++n) v.values.push_back(0.5 * (n % 41));
  LatticeDesign d{{.type = TpmsType::Gyroid, .cell = {1.5, 1.5, 1.5}, .porosity = 0.7}};
  d.grading.push_back({Graded::Cell,
                       {.shape = RampShape::Volume,
                        .from = 0,
                        .to = 20,
                        .start = 1.5,
                        .end = 3,
                        .volume = std::make_shared<const ScalarVolume>(std::move(v))}});
  auto phi = [&](Vec3 p) { return static_cast<double>(test::design_value(p, d)); };
  auto at_cell = [](double cell) {
    return LatticeDesign{{.type = TpmsType::Gyroid, .cell = {cell, cell, cell}, .porosity = 0.7}};
  };
  for (int k = 0; k < 5; ++k) {
    const double cell = 1.5 * std::pow(2.0, k / 4.0), x = 20 * (cell / 1.5 - 1);
    for (double y : {0.13, 0.41, 0.77}) {
      const Vec3 p{x, y, 0.3};
      EXPECT_NEAR(phi(p), test::design_value(p, at_cell(cell)), 1e-5) << "cell " << cell;
    }
  }
  // Continuous: the largest step between samples shrinks with their spacing, and is no larger
  // than the ladder's own lattices take (f/|∇f| is steep near f's critical points).
  const Vec3 a{-1, 0.5, 0.5}, b{21, 0.5, 0.5};
  const double coarse = largest_step(phi, a, b, 0.01);
  EXPECT_LT(largest_step(phi, a, b, 0.0025), 0.5 * coarse);
  double own = 0;
  for (double cell : {1.5, 3.0}) {
    const LatticeDesign plain = at_cell(cell);
    own = std::max(own, largest_step([&](Vec3 p) { return double(test::design_value(p, plain)); },
                                     a, b, 0.01));
  }
  EXPECT_LT(coarse, 1.5 * own);

  // By depth: 1 mm cells at the skin, 2.5 mm from 3 mm in. The output is valid and keeps the
  // porosity every rung has: two rungs mixed would thin the walls (72 % void), and the mix's
  // offset, solved once on the first pair, restores it.
  FillOptions o = cube_job(0.08, {.type = TpmsType::Gyroid, .porosity = 0.7});
  o.design.grading.push_back(
      {Graded::Cell, {.shape = RampShape::Depth, .from = 0, .to = 3, .start = 1, .end = 2.5}});
  const FillResult r = fill(test::make_box({0, 0, 0}, {10, 10, 10}), o);
  EXPECT_TRUE(r.report.validation.valid());
  EXPECT_NEAR(r.report.porosity(), 0.7, 0.01);
}

TEST(Design, CellGradingKeepsThePhaseContinuous) {
  // Cell size 1.5 → 4 mm along x. The field stays a distance (no jump between neighbouring
  // samples: a torn cell would show one), the zero crossings along x are T/2 apart at each
  // end, and the filled output is valid (fill validates: closed, manifold, no cracks).
  LatticeDesign d{{.type = TpmsType::Primitive}};
  d.grading.push_back({Graded::Cell,
                       {.shape = RampShape::Linear,
                        .point = Vec3{0, 0, 0},
                        .axis = {1, 0, 0},
                        .from = 0,
                        .to = 20,
                        .start = 1.5,
                        .end = 4}});
  auto phi = [&](Vec3 p) { return static_cast<double>(test::design_value(p, d)); };
  const double coarse = largest_step(phi, {-2, 0.1, 0.2}, {24, 0.1, 0.2}, 0.01);
  EXPECT_LT(largest_step(phi, {-2, 0.1, 0.2}, {24, 0.1, 0.2}, 0.0025), 0.5 * coarse);
  EXPECT_LT(coarse, 0.05);  // a torn cell would jump by about T/2
  // Along y = z = T/4 the primitive is cos X alone: it changes sign every T_x/2.
  std::vector<double> crossings;
  double previous = phi({-2, 0.5, 0.5});
  for (double x = -2 + 0.005; x <= 24; x += 0.005) {
    const double v = phi({x, 0.5, 0.5});
    if ((v < 0) != (previous < 0)) crossings.push_back(x);
    previous = v;
  }
  ASSERT_GE(crossings.size(), 8u);
  EXPECT_NEAR(crossings[1] - crossings[0], 0.75, 0.02);  // T = 1.5 below x = 0
  EXPECT_NEAR(crossings.back() - crossings[crossings.size() - 2], 2.0, 0.02);  // T = 4 beyond 20

  FillOptions o = cube_job(0.1, {.type = TpmsType::Gyroid});
  o.design.grading.push_back(
      {Graded::Cell, {.shape = RampShape::Linear, .axis = {1, 0, 0}, .start = 1.5, .end = 4}});
  const FillResult r = fill(test::make_box({0, 0, 0}, {12, 6, 6}), o);
  EXPECT_TRUE(r.report.validation.valid());
  EXPECT_EQ(r.report.components(), 1u);
  // Radial cell grading (from an axis) is continuous too.
  LatticeDesign radial{{.type = TpmsType::Gyroid}};
  radial.grading.push_back({Graded::Cell,
                            {.shape = RampShape::Radial,
                             .point = Vec3{0, 0, 0},
                             .axis = {0, 0, 1},
                             .from = 0,
                             .to = 6,
                             .start = 1.5,
                             .end = 3}});
  auto radial_phi = [&](Vec3 p) { return static_cast<double>(test::design_value(p, radial)); };
  const double radial_coarse = largest_step(radial_phi, {0.001, 0.002, 0.3}, {8, 4.8, 0.3}, 0.01);
  EXPECT_LT(largest_step(radial_phi, {0.001, 0.002, 0.3}, {8, 4.8, 0.3}, 0.0025),
            0.5 * radial_coarse);
}

TEST(Design, HybridTransitionIsContinuousAndAddsNoComponent) {
  // Gyroid below x = 5, primitive above, across 2 mm, by a sigmoid and by a Beta function: the
  // blended field has no jump, and the output is one valid component (islands kept, so an
  // extra component would show).
  for (Transition transition : {Transition::Sigmoid, Transition::Beta}) {
    FillOptions o = cube_job(0.1, {.type = TpmsType::Gyroid});
    o.design.blends.push_back(
        {.tpms = {.type = TpmsType::Primitive},
         .region = {.shape = RegionShape::HalfSpace, .point = {5, 0, 0}, .axis = {1, 0, 0}},
         .width = 2,
         .transition = transition});
    auto phi = [&](Vec3 p) { return static_cast<double>(test::design_value(p, o.design)); };
    const double coarse = largest_step(phi, {0, 0.3, 0.7}, {10, 0.3, 0.7}, 0.01);
    EXPECT_LT(largest_step(phi, {0, 0.3, 0.7}, {10, 0.3, 0.7}, 0.0025), 0.5 * coarse);
    // Far from the transition each side is its own lattice.
    EXPECT_FLOAT_EQ(test::design_value({1, 0.3, 0.7}, o.design),
                    test::tpms_value({1, 0.3, 0.7}, {.type = TpmsType::Gyroid}));
    EXPECT_FLOAT_EQ(test::design_value({9, 0.3, 0.7}, o.design),
                    test::tpms_value({9, 0.3, 0.7}, {.type = TpmsType::Primitive}));
    o.keep_islands = true;
    const FillResult r = fill(test::make_box({0, 0, 0}, {10, 6, 6}), o);
    EXPECT_EQ(r.report.components(), 1u) << transition_name(transition);
  }
}

TEST(Design, SkinIsWithinOneVoxelOfItsThickness) {
  // A field that is void everywhere leaves only the skin: a hollow box whose volume gives
  // the wall thickness, within one voxel of the requested 0.5 mm. (A TPMS level that leaves
  // no solid is refused: review.hpp.)
  const double a = 0.1, skin = 0.5, side = 10;
  FillOptions o = cube_job(a, {.type = TpmsType::Gyroid});
  o.design.custom = function_source([](Vec3) { return 10.0f; });
  o.skin = skin;
  const FillResult r = fill(test::make_box({0, 0, 0}, {side, side, side}), o);
  const double cavity = std::cbrt(side * side * side - r.report.lattice_volume());
  EXPECT_NEAR((side - cavity) / 2, skin, a);
  EXPECT_EQ(r.report.components(), 2u);  // the outer surface and the cavity's
  // With a lattice, a closed skin seals the void in (cavities: components of negative
  // volume); with windows at least 99 % of the void drains.
  auto sealed = [&](bool windows) {
    FillOptions o = cube_job(a, {.type = TpmsType::Gyroid});
    o.skin = skin;
    o.skin_windows = windows;
    const FillResult r = fill(test::make_box({0, 0, 0}, {side, side, side}), o);
    double cavities = 0;
    for (const auto& c : mesh_components(r.mesh).info) cavities += std::min(0.0, c.volume);
    return -cavities / (side * side * side - r.report.lattice_volume());
  };
  EXPECT_NEAR(sealed(false), 1.0, 0.01);
  EXPECT_LT(sealed(true), 0.01);
}

TEST(Design, UngradedDesignGivesTheGeneralPathsBits) {
  // An ungraded, unblended separable design takes a short path (design.cpp, DesignRows::rows);
  // a blend whose region lies far outside the grid (weight 0 at every node) sends the same base
  // lattice through the general path, node by node: the two must agree bit for bit.
  const Grid g = test::grid_around({{0, 0, 0}, {3, 2, 2}}, 0.1, 0);
  for (const TpmsType type :
       {TpmsType::Gyroid, TpmsType::Primitive, TpmsType::Diamond, TpmsType::Iwp, TpmsType::Neovius,
        TpmsType::Frd, TpmsType::Lidinoid, TpmsType::SplitP}) {
    for (const double level : {0.0, 0.4}) {
      LatticeDesign plain{TpmsOptions{.type = type, .level = level}};
      LatticeDesign general = plain;
      general.blends.push_back(
          {.tpms = {.type = TpmsType::Primitive},
           .region = {.shape = RegionShape::HalfSpace, .point = {1e3, 0, 0}, .axis = {1, 0, 0}},
           .width = 1});
      EXPECT_EQ(sample_field(design_source(plain), g).values,
                sample_field(design_source(general), g).values)
          << tpms_type_name(type) << " level " << level;
    }
  }
}

TEST(Design, CustomSourcesPlugIntoTheSamePipeline) {
  // The gyroid supplied by the caller, as a function of the point and as a source that
  // evaluates whole rows itself, gives the built-in field.
  const TpmsOptions gyroid{.type = TpmsType::Gyroid};
  LatticeDesign by_point, by_rows;
  by_point.custom = function_source([&](Vec3 p) { return test::tpms_value(p, gyroid); });
  by_rows.custom.on_grid = [gyroid](const Grid& grid) -> RowFunction {
    // Every node of the block, whatever `need` says: writing more than is needed is allowed.
    return [gyroid, grid](std::size_t first_row, std::size_t row_count, float* values,
                          const std::uint8_t*) {
      for_each_needed_node(grid, first_row, row_count, nullptr,
                           [&](int i, int j, int k, std::size_t n) {
                             values[n] = test::tpms_value(grid.node(i, j, k), gyroid);
                           });
    };
  };
  const Grid g = test::grid_around({{0, 0, 0}, {3, 3, 3}}, 0.1, 0);
  const Field reference = sample_field(tpms_source(gyroid), g);
  EXPECT_EQ(sample_field(design_source(by_point), g).values, reference.values);
  EXPECT_EQ(sample_field(design_source(by_rows), g).values, reference.values);
  EXPECT_EQ(sample_field(design_source(LatticeDesign{gyroid}), g).values, reference.values);
  // And through fill(): the same output as the built-in lattice.
  FillOptions builtin = cube_job(0.1, gyroid), custom = builtin;
  custom.design = by_rows;
  const TriangleSoup cube = test::make_box({0, 0, 0}, {5, 5, 5});
  const FillResult a = fill(cube, builtin), b = fill(cube, custom);
  EXPECT_EQ(a.mesh.triangles.size(), b.mesh.triangles.size());
  EXPECT_DOUBLE_EQ(a.report.lattice_volume(), b.report.lattice_volume());
}

TEST(Design, DesignErrorsAreClear) {
  LatticeDesign d;
  d.grading.push_back({Graded::Cell, {.shape = RampShape::Depth, .start = 1, .end = 2}});
  EXPECT_NO_THROW(require_valid(d));  // a ladder of cell sizes
  d.grading[0].ramp.start = 0;
  EXPECT_THROW(require_valid(d), InputError);  // no cell of size 0
  d.grading = {{Graded::Level, {.start = 0, .end = 0.2}}};
  d.style = TpmsStyle::Sheet;
  EXPECT_THROW(require_valid(d), InputError);
  d = {};
  d.blends.push_back({.width = 0});
  EXPECT_THROW(require_valid(d), InputError);
  d = {};
  d.blends.push_back({.region = {.shape = RegionShape::Sphere, .size = 0}});
  EXPECT_THROW(require_valid(d), InputError);
  d = {};
  d.porosity = 1.5;
  EXPECT_THROW(require_valid(d), InputError);
}

TEST(Recipe, RoundTripsEverySetting) {
  FillOptions o;
  o.grid.voxel_size = 0.07;
  o.skin = 0.4;
  o.skin_windows = true;
  o.inside = InsideRule::Parity;
  o.measure = true;
  o.min_wall = 0.35;
  o.min_pore = 0.6;
  o.design.type = TpmsType::Neovius;
  o.design.style = TpmsStyle::Sheet;
  o.design.cell = {2, 3, 4};
  o.design.porosity = 0.65;
  o.design.rotation = rotation_from_euler({0, 0, 45});
  o.design.grading.push_back({Graded::Cell,
                              {.shape = RampShape::Radial,
                               .point = Vec3{1, 2, 3},
                               .axis = {0, 0, 1},
                               .from = 0,
                               .to = 9,
                               .start = 2,
                               .end = 3}});
  o.design.blends.push_back({.tpms = {.type = TpmsType::Iwp, .level = 0.1},
                             .region = {.shape = RegionShape::Cylinder, .size = 3},
                             .width = 1.5,
                             .transition = Transition::Beta,
                             .peak = 0.3});
  const std::string text = recipe_json(o);
  const FillOptions back = read_recipe(text, "r.json");
  EXPECT_EQ(recipe_json(back), text);
  EXPECT_EQ(back.design.rotation, o.design.rotation);
  EXPECT_EQ(back.min_wall, 0.35);
  EXPECT_EQ(back.min_pore, 0.6);
  EXPECT_EQ(back.design.blends.at(0).tpms.type, TpmsType::Iwp);
  EXPECT_EQ(*back.design.grading.at(0).ramp.to, 9.0);
}

namespace {

// What read_recipe says of `text` (named r.json): its error, or "no error".
std::string message(const std::string& text) {
  try {
    read_recipe(text, "r.json");
  } catch (const Error& e) {
    return e.what();
  }
  return "no error";
}

}  // namespace

TEST(Recipe, ErrorsSayWhere) {
  EXPECT_EQ(message("{\n  \"voxel\": 0.1,\n  \"lattice\": {\"tpye\": \"gyroid\"}\n}")
                .rfind("r.json: lattice.tpye: unknown key", 0),
            0u);
  EXPECT_EQ(message("{\n  \"voxel\": 0.1,\n  \"skin\": ,\n}").rfind("r.json:3:", 0), 0u);
  EXPECT_NE(
      message("{\"blends\": [{\"region\": {\"shape\": \"cube\"}}]}").find("blends[0].region.shape"),
      std::string::npos);
  EXPECT_NE(message("{\"lattice\": {\"porosity\": 2}}").find("porosity"), std::string::npos);
  EXPECT_NE(message("{\"custom\": true}").find("custom"), std::string::npos);
  // A number beyond a double (found by fuzzing: nlohmann throws out_of_range, not parse_error).
  EXPECT_EQ(message("{\"voxel\": 21111E1111111111}").rfind("r.json:1: not valid JSON", 0), 0u);
  // The types recipe.hpp promises: where in the file for malformed JSON, which key otherwise.
  EXPECT_THROW(read_recipe("{\"skin\": }", "r.json"), ParseError);
  EXPECT_THROW(read_recipe("{\"skni\": 1}", "r.json"), InputError);
}

// Issue 37: limits a recipe from a stranger meets, the same as the command line's.
TEST(Recipe, HostileRecipesMeetTheLimits) {
  // Nested 30,000 deep: refused on its text, before a parser or a dump recurses into it; the
  // line where it passes the limit.
  EXPECT_EQ(message("{\n\"lattice\":\n" + std::string(30000, '[') + std::string(30000, ']') + "}"),
            "r.json:3: JSON nested more than 64 levels deep (the limit)");
  EXPECT_EQ(message("{\"a\": \"" + std::string(100, '[') + "\"}").find("nested"),
            std::string::npos);  // brackets in a string are text
  // "band": 1e9 was accepted where --band refuses past 64.
  EXPECT_EQ(message("{\"band\": 1000000000}"), "r.json: band: must be 1 to 64 voxels");
  EXPECT_EQ(message("{\"band\": 0}"), "r.json: band: must be 1 to 64 voxels");
  // 100,000 blends ran for minutes: at most kMaxBlends.
  std::string blends = "{\"blends\": [";
  for (std::size_t i = 0; i <= kMaxBlends; ++i)
    blends += std::string(i ? "," : "") +
              R"({"region": {"shape": "sphere", "point": [0, 0, 0], "size": 1}})";
  EXPECT_NE(message(blends + "]}").find("65 blends: at most 64 (the limit)"), std::string::npos);
  // The known keys are each named once ("grading, grading, blends, blends" before).
  const std::string unknown = message("{\"colour\": 1}");
  for (const std::string key : {"grading", "blends", "voxel"}) {
    const std::size_t first = unknown.find(key);
    ASSERT_NE(first, std::string::npos) << unknown;
    EXPECT_EQ(unknown.find(key, first + 1), std::string::npos) << unknown;
  }
}

TEST(Recipe, ResolvedOptionsRecipeReproducesTheJob) {
  // Rerunning the echoed recipe reproduces the output exactly.
  FillOptions o = cube_job(0.1, {.type = TpmsType::Diamond, .porosity = 0.6});
  o.design.grading.push_back({Graded::Porosity, {.start = 0.7, .end = 0.5}});
  const TriangleSoup cube = test::make_box({0, 0, 0}, {5, 5, 5});
  const FillResult first = fill(cube, o);
  const FillOptions echoed = read_recipe(recipe_json(first.resolved), "echo");
  ASSERT_TRUE(echoed.design.grading.at(0).ramp.to.has_value());
  EXPECT_DOUBLE_EQ(*echoed.design.grading[0].ramp.to, 5.0);
  const FillResult second = fill(cube, echoed);
  EXPECT_EQ(first.mesh.points, second.mesh.points);
  EXPECT_EQ(first.mesh.triangles, second.mesh.triangles);
}

TEST(Recipe, DocumentedRecipesRead) {
  // The recipes docs/recipes.md shows and the catalogue renders are valid and blend.
  const auto files =
      test::files_in(std::filesystem::path(TPMSFILL_SOURCE_DIR) / "docs" / "recipes", 1 << 20);
  ASSERT_GE(files.size(), 3u);
  for (const auto& f : files) {
    const FillOptions o = read_recipe_file(f.string());
    EXPECT_FALSE(o.design.blends.empty()) << f;
  }
}

TEST(Recipe, SeedFourFiguresAreRecipes) {
  // Issue 41: seed 004's Fig. 4 (a star ring changing porosity, type, size or thickness, each
  // without and with the Beta transition) and Fig. 7 (four rings) as recipes. Each Fig. 4 pair
  // is the same design but for its transition band; the main lattice is the seed's (P, 5 mm,
  // raw C = 0); the rings change what their names say.
  const auto dir = std::filesystem::path(TPMSFILL_SOURCE_DIR) / "docs" / "recipes" / "seed004";
  const auto files = test::files_in(dir, 1 << 20);
  ASSERT_EQ(files.size(), 11u);
  for (const char* feature : {"porosity", "type", "size", "thickness"}) {
    const std::string name = std::string("fig4-") + feature;
    const FillOptions sharp = read_recipe_file((dir / (name + "-sharp.json")).string());
    const FillOptions beta = read_recipe_file((dir / (name + "-beta.json")).string());
    for (const FillOptions* o : {&sharp, &beta}) {
      EXPECT_EQ(o->design.type, TpmsType::Primitive) << name;
      EXPECT_EQ(o->design.cell, (Vec3{5, 5, 5}));
      EXPECT_EQ(o->design.unit, LevelUnit::Raw);
      EXPECT_EQ(o->design.level, 0);
      ASSERT_EQ(o->design.blends.size(), 1u) << name;
      EXPECT_EQ(o->design.blends[0].region.shape, RegionShape::Polygon);
    }
    const TpmsOptions& in = beta.design.blends[0].tpms;
    FillOptions a, b;
    static_cast<TpmsOptions&>(a.design) = in;
    static_cast<TpmsOptions&>(b.design) = sharp.design.blends[0].tpms;
    EXPECT_EQ(recipe_json(a), recipe_json(b)) << name;
    EXPECT_EQ(beta.design.blends[0].transition, Transition::Beta);
    EXPECT_NE(sharp.design.blends[0].transition, Transition::Beta);
    EXPECT_LT(sharp.design.blends[0].region.outer + sharp.design.blends[0].region.inner,
              beta.design.blends[0].region.outer + beta.design.blends[0].region.inner);
    const std::string f(feature);
    EXPECT_EQ(in.type != TpmsType::Primitive, f == "type") << name;
    EXPECT_EQ(in.cell.x != 5, f == "size") << name;
    EXPECT_EQ(in.style == TpmsStyle::Sheet, f == "thickness") << name;
    EXPECT_EQ(in.level != 0, f == "porosity") << name;
  }
  const FillOptions rings = read_recipe_file((dir / "fig7-four-rings.json").string());
  EXPECT_EQ(rings.design.blends.size(), 4u);
  // Fig. 9's blade: I-WP (skeletal in 9c, a shell in 9d) and a skeletal G beyond a free
  // boundary, grown by the Beta transition.
  for (const char* name : {"fig9c-skeletal-iwp-g.json", "fig9d-shell-iwp-skeletal-g.json"}) {
    const FillOptions blade = read_recipe_file((dir / name).string());
    EXPECT_EQ(blade.design.type, TpmsType::Iwp) << name;
    EXPECT_EQ(blade.design.style == TpmsStyle::Sheet,
              std::string(name).find("shell") != std::string::npos);
    ASSERT_EQ(blade.design.blends.size(), 1u) << name;
    const Blend& g = blade.design.blends[0];
    EXPECT_EQ(g.tpms.type, TpmsType::Gyroid);
    EXPECT_EQ(g.tpms.style, TpmsStyle::Network);
    EXPECT_EQ(g.region.shape, RegionShape::Polygon);
    EXPECT_EQ(g.transition, Transition::Beta);
  }
}

TEST(Design, DepthGradingIsDenserNearTheSurface) {
  // Porosity 0.5 on the surface of a 12 mm cube rising to 0.85 from 3 mm deep: the outer 1 mm
  // shell of the output is denser than its central 4 mm cube, each within 6 % of the ramp's
  // mean there (0.5–0.6 in the shell, 0.85 at the centre).
  FillOptions o = cube_job(0.1, {.type = TpmsType::Gyroid});
  o.design.grading.push_back(
      {Graded::Porosity,
       {.shape = RampShape::Depth, .from = 0, .to = 3, .start = 0.5, .end = 0.85}});
  const Box3 box{{0, 0, 0}, {12, 12, 12}};
  const TriangleSoup mesh = fill(test::make_box(box.min, box.max), o).mesh;
  const Grid g = test::grid_around(box, 0.05, 0);
  const Occupancy solid = classify_grid(build_index(mesh), g);
  double shell = 0, shell_n = 0, core = 0, core_n = 0;
  for (int k = 0; k < g.dims[2]; ++k)
    for (int j = 0; j < g.dims[1]; ++j)
      for (int i = 0; i < g.dims[0]; ++i) {
        const Vec3 p = g.node(i, j, k);
        const double depth = std::min({p.x, p.y, p.z, 12 - p.x, 12 - p.y, 12 - p.z});
        if (depth < 0) continue;
        const double s = solid.inside.values[g.index(i, j, k)];
        if (depth < 1) shell += s, shell_n += 1;
        if (depth > 4) core += s, core_n += 1;
      }
  EXPECT_NEAR(1 - shell / shell_n, 0.55, 0.06);
  EXPECT_NEAR(1 - core / core_n, 0.85, 0.06);
}

TEST(Design, ReportMeasuresPoresWallsAndLabyrinths) {
  // A network's void is one labyrinth, a sheet's two; at porosity 0.8 the pores are wider
  // than the struts, and the sheet's walls measure about their thickness (within a voxel).
  const TriangleSoup cube = test::make_box({0, 0, 0}, {8, 8, 8});
  auto measured = [](FillOptions o) {
    o.measure = true;
    return o;
  };
  const FillResult network =
      fill(cube, measured(cube_job(0.1, {.type = TpmsType::Gyroid, .porosity = 0.8})));
  ASSERT_TRUE(network.report.measures.has_value());
  EXPECT_EQ(network.report.measures->labyrinths, 1u);
  EXPECT_GT(network.report.measures->pore.mean, network.report.measures->wall.mean);
  const FillResult sheet = fill(
      cube, measured(cube_job(
                0.1, {.type = TpmsType::Gyroid, .style = TpmsStyle::Sheet, .thickness = 0.4})));
  EXPECT_EQ(sheet.report.measures->labyrinths, 2u);
  EXPECT_NEAR(sheet.report.measures->wall.p50, 0.4, 0.1);
  EXPECT_GT(network.report.specific_surface(), 0);
  EXPECT_FALSE(fill(cube, cube_job(0.1, {})).report.measures.has_value());  // off by default
}

TEST(Design, BlendRegionsTakeOverInsideAndLeaveOutside) {
  // Deep inside each region (beyond half the width) the blended lattice is the region's own;
  // far outside it is the base; in the transition it lies between the two.
  const TpmsOptions base{.type = TpmsType::Gyroid}, other{.type = TpmsType::Neovius};
  const Region regions[] = {
      {.shape = RegionShape::HalfSpace, .point = {0, 0, 0}, .axis = {0, 0, 1}},
      {.shape = RegionShape::Slab, .point = {0, 0, 0}, .axis = {0, 0, 1}, .size = 4},
      {.shape = RegionShape::Sphere, .point = {0, 0, 0}, .size = 3},
      {.shape = RegionShape::Cylinder, .point = {0, 0, 0}, .axis = {0, 0, 1}, .size = 3}};
  for (const Region& region : regions)
    for (Transition transition : {Transition::Sigmoid, Transition::Beta}) {
      LatticeDesign d{base};
      d.blends.push_back({.tpms = other, .region = region, .width = 1, .transition = transition});
      const Vec3 inside{0.3, 0.2, 0.8}, outside{7.3, 6.2, -8.4};
      EXPECT_FLOAT_EQ(test::design_value(inside, d), test::tpms_value(inside, other))
          << region_name(region.shape);
      EXPECT_FLOAT_EQ(test::design_value(outside, d), test::tpms_value(outside, base))
          << region_name(region.shape);
    }
}

TEST(Recipe, FourierTermsAndRawLevelsRoundTrip) {
  // Issue 41: a fourier lattice's terms and raw levels {"c": ...} read back as written, a
  // blend of a named type drops the base's terms, and bad terms or mixed units say where.
  FillOptions o;
  o.design.type = TpmsType::Fourier;
  o.design.terms = fourier_terms(TpmsOptions{.type = TpmsType::Diamond});
  o.design.terms.push_back({0.25, {2, -1, 0}, 0.5});
  o.design.style = TpmsStyle::Sheet;
  o.design.level = -0.1, o.design.thickness = 0.4, o.design.unit = LevelUnit::Raw;
  o.design.blends.push_back({.tpms = {.type = TpmsType::Gyroid, .level = 0.2},
                             .region = {.shape = RegionShape::Sphere, .size = 3},
                             .width = 1});
  const std::string text = recipe_json(o);
  const FillOptions back = read_recipe(text, "r.json");
  EXPECT_EQ(recipe_json(back), text);
  EXPECT_EQ(back.design.terms, o.design.terms);
  EXPECT_EQ(back.design.unit, LevelUnit::Raw);
  EXPECT_TRUE(back.design.blends.at(0).tpms.terms.empty());
  EXPECT_EQ(back.design.blends.at(0).tpms.unit, LevelUnit::Millimetre);
  EXPECT_NE(message(R"({"lattice": {"type": "fourier", "terms": [{"wave": [1, 0.5, 0]}]}})")
                .find("lattice.terms[0].wave: must be whole numbers"),
            std::string::npos);
  EXPECT_NE(message(R"({"lattice": {"type": "fourier"}})").find("needs 1 to 256 terms"),
            std::string::npos);
  EXPECT_NE(message(R"({"lattice": {"type": "gyroid", "terms": [{"wave": [1, 0, 0]}]}})")
                .find("Fourier terms are for the fourier lattice type"),
            std::string::npos);
  EXPECT_NE(message(R"({"lattice": {"style": "sheet", "level": {"c": 0.1}, "thickness": 0.3}})")
                .find("lattice.thickness: mixes mm and raw C"),
            std::string::npos);
  EXPECT_NE(message(R"({"lattice": {"level": {"c": 0.1}, "porosity": 0.5}})")
                .find("raw level C or a porosity"),
            std::string::npos);
  EXPECT_NE(message(R"({"lattice": {"level": {"mm": 0.1}}})").find("lattice.level"),
            std::string::npos);
}
