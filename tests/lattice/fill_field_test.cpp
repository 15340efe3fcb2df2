// fill_field: a design that bounds its own solid, meshed over a box with no model to clip it.
#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <numbers>
#include <tpmsfill/error.hpp>
#include <tpmsfill/field.hpp>
#include <tpmsfill/fill.hpp>

#include "test_util.hpp"

using namespace tpmsfill;

namespace {

FillOptions field_options(std::function<float(Vec3)> field, double voxel) {
  FillOptions o;
  o.grid.voxel_size = voxel;
  o.design.cell = {2, 2, 2};  // what the review and the report read; the field is the source
  o.design.custom = function_source(std::move(field));
  return o;
}

const Vec3 kPlaces[] = {{0, 0, 0}, {150, 150, 0}, {0, 0, -1000}, {-350, 20, 400}};

}  // namespace

// A torus's field, wherever it sits: one closed, outward 2-manifold of genus 1 (V = F / 2)
// holding 2π²Rr² within 1 %, with no input and no model in the report.
TEST(FillField, ATorusIsOneClosedShellOfGenusOneWithItsVolumeWhereverItSits) {
  const double R = 6, r = 2;
  for (const Vec3 at : kPlaces) {
    const auto torus = [=](Vec3 p) {
      const Vec3 q = p - at;
      return static_cast<float>(std::hypot(std::hypot(q.x, q.y) - R, q.z) - r);
    };
    const FillResult f =
        fill_field(Box3{at - Vec3{9, 9, 3}, at + Vec3{9, 9, 3}}, field_options(torus, 0.1));
    const MeshValidity& v = f.report.validation;
    ASSERT_TRUE(v.valid()) << v.problems().front();
    EXPECT_EQ(v.components, 1u);
    EXPECT_EQ(2 * v.vertices, v.triangles) << "not genus 1";
    const double volume = 2 * std::numbers::pi * std::numbers::pi * R * r * r;
    EXPECT_NEAR(*v.volume, volume, 0.01 * volume);
    EXPECT_EQ(f.report.input_triangles, 0u);
    EXPECT_EQ(f.report.rows, 0u);
    EXPECT_EQ(f.report.model_volume, 0.0);
    EXPECT_EQ(f.report.grid.spacing, 0.1);
  }
}

// A solid that runs off the grid (everything below a plane) is closed at the grid's outermost
// nodes: one closed shell of genus 0 (2V = F + 4), a slab of the grid's inner box.
TEST(FillField, ASolidReachingTheGridsEdgeIsClosedThere) {
  const Vec3 at{150, 150, 0};
  const auto below = [=](Vec3 p) { return static_cast<float>(p.z - at.z); };
  const FillResult f =
      fill_field(Box3{at - Vec3{5, 5, 5}, at + Vec3{5, 5, 5}}, field_options(below, 0.25));
  const MeshValidity& v = f.report.validation;
  ASSERT_TRUE(v.valid()) << v.problems().front();
  EXPECT_EQ(v.components, 1u);
  EXPECT_EQ(2 * v.vertices, v.triangles + 4) << "not genus 0";
  // The inner nodes span the box and one more voxel of padding on each side; the solid ends
  // between the outermost node and the next, within a voxel of the box grown by a voxel.
  const Grid& g = f.report.grid;
  const double a = g.spacing, side = (g.dims[0] - 1) * a, depth = at.z - g.origin.z;
  EXPECT_GT(v.volume, (side - 2 * a) * (side - 2 * a) * (depth - a));
  EXPECT_LT(v.volume, side * side * depth);
}

// Islands are judged over the whole grid as one part: of two separate balls the smaller goes,
// unless islands are kept.
TEST(FillField, TheSmallerOfTwoBallsIsAnIslandUnlessKept) {
  const auto balls = [](Vec3 p) {
    const double big = norm(p - Vec3{-4, 0, 0}) - 3, small = norm(p - Vec3{5, 0, 0}) - 1.5;
    return static_cast<float>(std::fmin(big, small));
  };
  const Box3 box{{-8, -4, -4}, {8, 4, 4}};
  FillOptions o = field_options(balls, 0.1);
  const FillResult dropped = fill_field(box, o);
  EXPECT_EQ(dropped.report.validation.components, 1u);
  EXPECT_EQ(dropped.report.islands_removed, 1u);
  EXPECT_NEAR(*dropped.report.validation.volume, 4 * std::numbers::pi * 27 / 3, 1.0);
  o.keep_islands = true;
  EXPECT_EQ(fill_field(box, o).report.validation.components, 2u);
}

// What follows a model's surface has nothing to follow, and a grid over the budget cannot go
// in slabs: refused with the reason, before any work.
TEST(FillField, RefusesWhatNeedsAModelAndGridsOverTheBudget) {
  const auto ball = [](Vec3 p) { return static_cast<float>(norm(p) - 2); };
  const Box3 box{{-3, -3, -3}, {3, 3, 3}};
  FillOptions skin = field_options(ball, 0.2);
  skin.skin = 0.5;
  EXPECT_THROW(fill_field(box, skin), InputError);
  FillOptions inches = field_options(ball, 0.2);
  inches.units.units = Units::Inch;
  EXPECT_THROW(fill_field(box, inches), InputError);
  FillOptions tight = field_options(ball, 0.02);
  tight.memory_budget = 100u << 20;  // the whole grid needs about 580 MB
  try {
    fill_field(box, tight);
    FAIL() << "a grid over the budget was meshed";
  } catch (const ResourceError& e) {
    // The voxel size it names fits the whole grid (slabs, which fill() would take, are no
    // option here).
    const std::string why = e.what();
    const std::size_t at = why.find("a voxel size of ");
    ASSERT_NE(at, std::string::npos) << why;
    FillOptions fits = tight;
    fits.grid.voxel_size = std::stod(why.substr(at + 16));
    EXPECT_GT(fits.grid.voxel_size, 0.02);
    EXPECT_EQ(fill_field(box, fits).report.slab_planes, 0);
  }
}
