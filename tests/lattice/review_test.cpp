// Stage "units" and stage "review": the model's unit, and designs that cannot come out as
// asked (refused) or may not (warned), each with the sentence a user reads.
#include <gtest/gtest.h>

#include <tpmsfill/error.hpp>
#include <tpmsfill/fill.hpp>
#include <tpmsfill/units.hpp>
#include "lattice/review.hpp"

#include "test_util.hpp"

using namespace tpmsfill;

namespace {

Box3 cube(double side) {
  return {{0, 0, 0}, {side, side, side}};
}

LatticeDesign gyroid(double cell = 2) {
  LatticeDesign d;
  d.cell = {cell, cell, cell};
  return d;
}

// The InputError's message, or "" when review_design accepts.
std::string refusal(const LatticeDesign& d, const Box3& model, double voxel) {
  try {
    review_design(resolve_design(d, model), model, {.voxel = voxel});
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

std::string warnings(const LatticeDesign& d, const Box3& model, double voxel) {
  std::string all;
  for (const std::string& w : review_design(resolve_design(d, model), model, {.voxel = voxel}))
    all += w + "\n";
  return all;
}

bool has(const std::string& text, const std::string& part) {
  return text.find(part) != std::string::npos;
}

}  // namespace

TEST(Units, FactorsAndNames) {
  EXPECT_EQ(millimetres_per(Units::Metre), 1000);
  EXPECT_EQ(millimetres_per(Units::Inch), 25.4);
  EXPECT_EQ(units_from_name("in"), Units::Inch);
  EXPECT_EQ(units_from_name("um"), Units::Micrometre);
  EXPECT_EQ(units_name(Units::Centimetre), "cm");
  EXPECT_THROW(units_from_name("furlong"), InputError);
  EXPECT_THROW(require_valid(ModelUnits{.scale = 0}), InputError);
  const TriangleSoup box =
      to_millimetres(test::make_box({0, 0, 0}, {1, 2, 3}), {.units = Units::Inch, .scale = 2});
  const Vec3 s = bounding_box(box).size();
  EXPECT_DOUBLE_EQ(s.x, 50.8);
  EXPECT_DOUBLE_EQ(s.z, 152.4);
}

TEST(Units, LikelyUnitOfImplausibleSizes) {
  // 0.3 "mm" is a 300 mm part in metres; 300,000 "mm" is 300 mm in micrometres; 4 "mm" is
  // not implausible, and 100 mm is a part.
  EXPECT_EQ(likely_units(cube(0.3), Units::Millimetre), Units::Metre);
  EXPECT_EQ(likely_units(cube(3e5), Units::Millimetre), Units::Micrometre);
  EXPECT_FALSE(likely_units(cube(4), Units::Millimetre));
  EXPECT_FALSE(likely_units(cube(100), Units::Millimetre));
  // A model read in metres that is 300 m across was in millimetres.
  EXPECT_EQ(likely_units(cube(3e5), Units::Metre), Units::Millimetre);
  EXPECT_EQ(units_hint(cube(0.3), Units::Millimetre), "; if it is in metres, add --units m");
}

TEST(Review, ModelSmallerThanOneCellIsRefusedWithTheLikelyUnit) {
  const std::string why = refusal(gyroid(2), cube(0.3), 0.01);
  EXPECT_TRUE(has(why, "0.3 mm across, smaller than one 2 mm cell")) << why;
  EXPECT_TRUE(has(why, "add --units m")) << why;
  // In metres the same model fills.
  const TriangleSoup model = test::make_box({0, 0, 0}, {0.03, 0.03, 0.03});
  FillOptions o;
  o.units.units = Units::Metre;
  o.grid.voxel_size = 0.4;
  o.design.cell = {5, 5, 5};
  const FillResult r = fill(model, o);
  EXPECT_NEAR(r.report.input_bbox.size().x, 30, 1e-9);
  EXPECT_EQ(r.report.units, "m");
  EXPECT_EQ(r.report.mm_per_unit, 1000);
  EXPECT_NEAR(r.report.porosity(), 0.5, 0.05);  // the gyroid's level 0 halves the volume
  o.units.units = Units::Millimetre;
  EXPECT_THROW(fill(model, o), InputError);
}

TEST(Review, FewerThanThreeCellsWarns) {
  EXPECT_TRUE(has(warnings(gyroid(2), cube(5), 0.1), "5 mm across, 2.5 cells")) << "";
  EXPECT_EQ(warnings(gyroid(2), cube(20), 0.1), "");
}

TEST(Review, VoxelCoarserThanACellFractionIsRefusedOrWarned) {
  const std::string why = refusal(gyroid(2), cube(20), 1.2);
  EXPECT_TRUE(has(why, "coarser than half of the smallest cell (2 mm)")) << why;
  EXPECT_TRUE(has(why, "--voxel 0.5 or less")) << why;
  EXPECT_TRUE(has(warnings(gyroid(2), cube(20), 0.6), "a quarter of the smallest cell")) << "";
  // A cell ramp's small end counts.
  LatticeDesign graded = gyroid(4);
  graded.grading.push_back({Graded::Cell, {.axis = {1, 0, 0}, .start = 1, .end = 4}});
  EXPECT_TRUE(has(refusal(graded, cube(20), 0.6), "at the start of the cell ramp"));
}

TEST(Review, LevelsThatLeaveNoSolidOrNoVoid) {
  LatticeDesign d = gyroid(2);
  d.level = 2;
  std::string why = refusal(d, cube(20), 0.1);
  EXPECT_TRUE(has(why, "leaves no solid")) << why;
  EXPECT_TRUE(has(why, "levels from")) << why;
  d.level = -2;
  EXPECT_TRUE(has(refusal(d, cube(20), 0.1), "leaves no void"));
  // A level that leaves a little solid (porosity 0.985) is warned about.
  d.level = 0;
  d.porosity = 0.985;
  EXPECT_TRUE(has(warnings(d, cube(20), 0.05), "leaves almost no solid")) << "";
  // A sheet wide enough to fill the cell.
  LatticeDesign sheet = gyroid(2);
  sheet.style = TpmsStyle::Sheet;
  sheet.thickness = 5;
  why = refusal(sheet, cube(20), 0.1);
  EXPECT_TRUE(has(why, "leaves no void")) << why;
}

TEST(Review, PorosityWithAGradedLevelIsRefused) {
  LatticeDesign d = gyroid(2);
  d.porosity = 0.7;
  d.grading.push_back({Graded::Level, {.start = -0.2, .end = 0.2}});
  try {
    require_valid(d);
    FAIL() << "accepted";
  } catch (const InputError& e) {
    EXPECT_TRUE(has(e.what(), "grade the porosity instead")) << e.what();
  }
}

TEST(Review, BlendRegionOutsideTheModel) {
  LatticeDesign d = gyroid(2);
  Blend b;
  b.tpms.type = TpmsType::Primitive;
  b.region = {.shape = RegionShape::Sphere, .point = {100, 100, 100}, .size = 5};
  d.blends.push_back(b);
  EXPECT_TRUE(has(refusal(d, cube(20), 0.1), "blend 1's sphere region lies outside"));
  d.blends[0].region = {.shape = RegionShape::Sphere, .point = {24, 24, 24}, .size = 8};
  // only its edge reaches the box's corner
  EXPECT_TRUE(has(warnings(d, cube(20), 0.1), "less than 8 of its 2 mm cells")) << "";
  d.blends[0].region.point = {10, 10, 10};
  EXPECT_EQ(warnings(d, cube(20), 0.1), "");
}

TEST(Review, RampRangesThatMissTheModel) {
  LatticeDesign d = gyroid(2);
  d.grading.push_back({Graded::Porosity, {.from = 50, .to = 80, .start = 0.5, .end = 0.8}});
  const std::string why = refusal(d, cube(20), 0.1);
  EXPECT_TRUE(has(why, "misses the model")) << why;
  d.grading[0].ramp.from = 19.5;
  d.grading[0].ramp.to = 40;  // the model sees 0.5 of its 20.5 mm
  EXPECT_TRUE(has(warnings(d, cube(20), 0.1), "of the change happens in the part")) << "";
  // A radial ramp centred outside the box.
  d.grading[0].ramp = {.shape = RampShape::Radial,
                       .point = Vec3{-30, 10, 10},
                       .axis = {0, 0, 0},
                       .from = 30,
                       .to = 50,
                       .start = 0.5,
                       .end = 0.8};
  EXPECT_TRUE(has(warnings(d, cube(20), 0.1), "centred outside the model's box")) << "";
}

TEST(Review, StrutsAndPoresThinnerThanTwoVoxels) {
  // A 2 mm gyroid at porosity 0.9 has struts about 0.5 mm across: fine at 0.05 mm voxels,
  // under two voxels at 0.3 mm.
  LatticeDesign d = gyroid(2);
  d.porosity = 0.9;
  EXPECT_EQ(warnings(d, cube(20), 0.05), "");
  const std::string w = warnings(d, cube(20), 0.3);
  EXPECT_TRUE(has(w, "struts at most")) << w;
  EXPECT_TRUE(has(w, "thinner than two voxels")) << w;
  d.porosity = 0.1;  // the mirror image: narrow pores
  EXPECT_TRUE(has(warnings(d, cube(20), 0.3), "pores at most")) << "";
}

TEST(Review, LayerSizesMatchTheDesign) {
  // A sheet's wall is its thickness; the sampled diameter reads within a sample spacing
  // (cell / 20) of it.
  for (double t : {0.2, 0.4, 0.6}) {
    TpmsOptions sheet{.type = TpmsType::Gyroid, .style = TpmsStyle::Sheet, .thickness = t};
    EXPECT_NEAR(layer_sizes(sheet).solid, t, 2.0 / 20) << t;
  }
  // A gyroid network at level 0 is its own complement: struts and pores alike.
  const LayerSizes g = layer_sizes(TpmsOptions{.type = TpmsType::Gyroid});
  EXPECT_NEAR(g.solid, g.pore, 2.0 / 20);
  EXPECT_GT(g.solid, 0.5);
}
