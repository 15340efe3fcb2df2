// Stages "porous" and "itdf" (issue 13): seed 003's structures from a fitted field, their
// porosity, their field in a fill, and the ITDF file that stores them.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <numbers>
#include <tpmsfill/error.hpp>
#include <tpmsfill/fill.hpp>
#include <tpmsfill/lattice/design.hpp>
#include <tpmsfill/recipe.hpp>
#include <tpmsfill/scan/itdf.hpp>
#include <tpmsfill/scan/porous.hpp>

#include "test_util.hpp"

using namespace tpmsfill;
using namespace tpmsfill::test;

namespace {

// C fitted to the signed distance of a ball of radius r at the cube's centre (negative in it).
PorousStructure ball_structure(double r, int counts = 12) {
  const std::array<int, 3> d{32, 32, 32};
  std::vector<double> x;
  for (int k = 0; k < d[2]; ++k)
    for (int j = 0; j < d[1]; ++j)
      for (int i = 0; i < d[0]; ++i) {
        const double u = (i + 0.5) / d[0] - 0.5, v = (j + 0.5) / d[1] - 0.5,
                     w = (k + 0.5) / d[2] - 0.5;
        x.push_back(std::sqrt(u * u + v * v + w * w) - r);
      }
  PorousStructure s;
  s.field = fit_bspline(x, d, {counts, counts, counts}).volume;
  s.sign = FieldSign::Signed;
  s.t2.constant = 0;  // t1 = −∞: the ball C <= 0
  return s;
}

// A sponge: solid outside random overlapping spherical pores, C the distance to the nearest
// pore centre minus a radius, t1 = 0 <= C <= t2 = +∞.
PorousStructure sponge_structure() {
  const std::array<int, 3> d{40, 40, 40};
  std::vector<std::array<double, 3>> centres;
  unsigned seed = 12345;
  auto next = [&] { return (seed = seed * 1103515245u + 12345u) / 4294967296.0; };
  for (int n = 0; n < 40; ++n) centres.push_back({next(), next(), next()});
  std::vector<double> x;
  for (int k = 0; k < d[2]; ++k)
    for (int j = 0; j < d[1]; ++j)
      for (int i = 0; i < d[0]; ++i) {
        double best = 1e9;
        for (const auto& c : centres) {
          const double u = (i + 0.5) / d[0] - c[0], v = (j + 0.5) / d[1] - c[1],
                       w = (k + 0.5) / d[2] - c[2];
          best = std::min(best, std::sqrt(u * u + v * v + w * w));
        }
        x.push_back(best - 0.12);
      }
  PorousStructure s;
  s.field = fit_bspline(x, d, {24, 24, 24}).volume;
  s.sign = FieldSign::Signed;
  s.t1.constant = 0;
  s.t2.constant = std::numeric_limits<double>::infinity();
  return s;
}

}  // namespace

TEST(Porous, BallVolumeFromTheFittedField) {
  const double r = 0.3;
  const PorousStructure s = ball_structure(r);
  const double exact = 4.0 / 3 * std::numbers::pi * r * r * r;
  EXPECT_NEAR(porous_solid_share(s, {1, 1, 1}, 96), exact, 0.01 * exact);
  // A band t1 <= C <= t2 around the surface: a shell between radii r − a and r + a.
  PorousStructure shell = s;
  shell.t1.constant = -0.05, shell.t2.constant = 0.05;
  const double shell_exact =
      4.0 / 3 * std::numbers::pi * (std::pow(r + 0.05, 3) - std::pow(r - 0.05, 3));
  EXPECT_NEAR(porous_solid_share(shell, {1, 1, 1}, 96), shell_exact, 0.03 * shell_exact);
}

TEST(Porous, PorosityIsReachedForSolidsAndSheets) {
  const PorousStructure sponge = sponge_structure();
  for (double p : {0.3, 0.6, 0.85}) {
    const PorousStructure s = with_porosity(sponge, p, {10, 10, 10});
    EXPECT_NEAR(1 - porous_solid_share(s, {10, 10, 10}), p, 0.005) << p;
    PorousStructure sheet = sponge;
    sheet.type = StructureType::Surface;
    sheet.sheet_thickness = 0.1;
    const PorousStructure t = with_porosity(sheet, p, {10, 10, 10});
    EXPECT_GT(t.sheet_thickness, 0);
    EXPECT_NEAR(1 - porous_solid_share(t, {10, 10, 10}), p, 0.005) << p;
  }
  EXPECT_THROW(with_porosity(sponge, 1.0, {1, 1, 1}), InputError);
}

TEST(Porous, InvalidStructuresAreRefused) {
  PorousStructure s = ball_structure(0.3, 6);
  PorousStructure bad = s;
  bad.t1.constant = 1, bad.t2.constant = 0;
  EXPECT_THROW(require_valid(bad), InputError);
  bad = s;
  bad.placement = Placement::Tile;  // no size: no cell to tile with
  EXPECT_THROW(require_valid(bad), InputError);
  bad = s;
  bad.field.coefficients.pop_back();
  EXPECT_THROW(require_valid(bad), InputError);
  bad = s;
  bad.size = {1, 0, 1};
  EXPECT_THROW(require_valid(bad), InputError);
}

TEST(Porous, FillWithAStructureIsValidAndHitsItsPorosity) {
  // The sponge stretched over a 20 mm box: the fill is validated (closed, manifold, outward)
  // and its measured porosity is the asked one within one point.
  FillOptions o;
  o.grid.voxel_size = 0.25;
  o.design.structure = sponge_structure();
  o.design.porosity = 0.7;
  o.measure = true;
  const FillResult r = fill(make_box({0, 0, 0}, {20, 20, 20}), o);
  EXPECT_GT(r.mesh.triangles.size(), 1000u);
  EXPECT_NEAR(r.report.porosity(), 0.7, 0.01);
  EXPECT_NEAR(signed_volume(r.mesh), r.report.lattice_volume(), 0.01 * r.report.lattice_volume());
}

TEST(Itdf, RoundTripsBitExactly) {
  ItdfFile f;
  f.structure = sponge_structure();
  f.structure.t1.constant = -0.02;
  f.structure.t2.constant = 0.03;
  f.structure.size = {10, 12, 14};
  f.fit = FitRecord{false, {40, 40, 40}, 0, 0.01, 0.05, -0.1, 0.5, 0, 0.002, 0.3};
  f.provenance = "made by porous_test";
  for (CoefficientType type :
       {CoefficientType::Float32, CoefficientType::Float64, CoefficientType::Int16}) {
    f.encoding[0].type = type;
    const std::string bytes = itdf_bytes(f);
    const ItdfFile back = parse_itdf(bytes, "mem.itdf");
    EXPECT_EQ(itdf_bytes(back), bytes) << int(type);
    EXPECT_EQ(back.provenance, f.provenance);
    ASSERT_TRUE(back.fit);
    EXPECT_EQ(back.fit->source_dims, f.fit->source_dims);
    EXPECT_EQ(back.structure.size, f.structure.size);
    // What was stored is what was fitted, within the coefficient type's rounding.
    const double tolerance = type == CoefficientType::Float64   ? 0
                             : type == CoefficientType::Float32 ? 1e-6
                                                                : 1e-3;
    for (std::size_t n = 0; n < f.structure.field.coefficients.size(); n += 97)
      EXPECT_NEAR(back.structure.field.coefficients[n], f.structure.field.coefficients[n],
                  tolerance);
  }
  // Spline thresholds and explicit knots round-trip too; an open side stays infinite.
  f.structure.t2.constant = std::numeric_limits<double>::infinity();
  f.structure.t1.spline = fit_bspline(std::vector<double>(64, 0.25), {4, 4, 4}, {4, 4, 4}).volume;
  f.structure.field.knots[0][4] += 0.01;  // no longer uniform: stored explicitly
  const std::string bytes = itdf_bytes(f);
  const ItdfFile back = parse_itdf(bytes, "mem.itdf");
  EXPECT_EQ(itdf_bytes(back), bytes);
  EXPECT_EQ(back.structure.field.knots[0], f.structure.field.knots[0]);
  EXPECT_TRUE(std::isinf(back.structure.t2.constant));
  EXPECT_NEAR(threshold_value(back.structure.t1, 0.3, 0.6, 0.9), 0.25, 1e-6);
}

TEST(Itdf, IsFarSmallerThanTheGridItCameFrom) {
  ItdfFile f;
  f.structure = sponge_structure();  // 24³ coefficients from 40³ samples
  EXPECT_LT(itdf_bytes(f).size(), 24u * 24 * 24 * 4 + 200);
  f.encoding[0].type = CoefficientType::Int16;
  EXPECT_LT(itdf_bytes(f).size(), 24u * 24 * 24 * 2 + 200);
}

TEST(Itdf, DamageIsNamedWithItsByteOffset) {
  ItdfFile f;
  f.structure = ball_structure(0.3, 6);
  f.provenance = "test";
  const std::string bytes = itdf_bytes(f);
  // Every truncation fails cleanly, with a byte offset.
  for (std::size_t n = 0; n < bytes.size(); ++n) {
    try {
      parse_itdf(bytes.substr(0, n), "cut.itdf");
      ADD_FAILURE() << "a file cut to " << n << " bytes was read";
    } catch (const ParseError& e) {
      EXPECT_TRUE(e.byte_offset().has_value()) << e.what();
    }
  }
  // A changed coefficient byte is caught by the CRC; a huge count before allocation.
  std::string flipped = bytes;
  flipped[200] ^= 0x40;
  EXPECT_THROW(parse_itdf(flipped, "flip.itdf"), ParseError);
  std::string huge = bytes;
  const std::uint32_t big = 1u << 20;
  std::memcpy(huge.data() + 44 + 4, &big, 4);  // C's first count
  try {
    parse_itdf(huge, "huge.itdf");
    ADD_FAILURE();
  } catch (const ParseError& e) {
    EXPECT_NE(std::string(e.what()).find("more than the file holds"), std::string::npos)
        << e.what();
  }
  std::string newer = bytes;
  newer[4] = 2;
  EXPECT_THROW(parse_itdf(newer, "v2.itdf"), InputError);
  EXPECT_THROW(parse_itdf("STL solid", "x.itdf"), ParseError);
}

TEST(Porous, ThresholdsFollowRampsAndTheirOwnGrids) {
  // A linear ramp is reproduced between its ends; a threshold grid of its own is fitted.
  Ramp ramp;
  ramp.axis = {0, 0, 1};
  ramp.start = -0.1, ramp.end = 0.3;
  const Threshold t = ramp_threshold(ramp, {10, 10, 20});
  ASSERT_TRUE(t.spline);
  for (double w : {0.0, 0.25, 0.5, 1.0})
    EXPECT_NEAR(threshold_value(t, 0.3, 0.7, w), -0.1 + 0.4 * w, 1e-6) << w;
  ramp.shape = RampShape::Depth;
  EXPECT_THROW(ramp_threshold(ramp, {1, 1, 1}), InputError);
  ScalarVolume grid;
  grid.dims = {5, 4, 3};
  grid.values.assign(60, 0.25);
  EXPECT_NEAR(threshold_value(fitted_threshold(grid, {3, 3, 3}), 0.1, 0.5, 0.9), 0.25, 1e-9);

  // Graded pores: the sponge's t1 from 0.08 at the bottom to -0.04 at the top leaves more
  // solid at the top.
  PorousStructure s = sponge_structure();
  ramp.shape = RampShape::Linear;
  ramp.start = 0.08, ramp.end = -0.04;
  s.t1 = ramp_threshold(ramp, {1, 1, 1});
  const FieldSource source = porous_source(s, {});
  Grid g;
  g.origin = {0.5 / 32, 0.5 / 32, 0.5 / 32};
  g.spacing = 1.0 / 32;
  g.dims = {32, 32, 32};
  const Field f = sample_field(source, g);
  std::size_t low = 0, high = 0;
  for (std::size_t n = 0; n < f.values.size(); ++n)
    (n < f.values.size() / 2 ? low : high) += f.values[n] <= 0;
  EXPECT_LT(double(low), 0.8 * double(high)) << low << " " << high;
}

TEST(Porous, AnIslandShellGoesWithTheCavityItEncloses) {
  // Two separate balls' distance as a sheet: two closed spherical shells, each an outer
  // surface and an inner (cavity) surface. The small shell is an island: removing it must
  // remove its cavity surface too, or the output would be inside out there.
  const std::array<int, 3> d{40, 40, 40};
  std::vector<double> x;
  for (int k = 0; k < d[2]; ++k)
    for (int j = 0; j < d[1]; ++j)
      for (int i = 0; i < d[0]; ++i) {
        const double u = (i + 0.5) / d[0], v = (j + 0.5) / d[1], w = (k + 0.5) / d[2];
        x.push_back(std::min(std::hypot(u - 0.35, v - 0.5, w - 0.5) - 0.22,
                             std::hypot(u - 0.8, v - 0.5, w - 0.5) - 0.08));
      }
  PorousStructure s;
  s.field = fit_bspline(x, d, {24, 24, 24}).volume;
  s.type = StructureType::Surface;
  s.sheet_thickness = 1.0;
  FillOptions o;
  o.grid.voxel_size = 0.2;
  o.design.structure = s;
  const FillResult r = fill(make_box({0, 0, 0}, {20, 20, 20}), o);
  EXPECT_EQ(r.report.islands_removed, 1u);
  EXPECT_EQ(r.report.cavities, 1u);  // the big shell's sealed inside
  // What is left is the big shell: 4/3 π ((R + t/2)³ − (R − t/2)³), R = 4.4 mm, t = 1 mm.
  const double shell = 4.0 / 3 * std::numbers::pi * (std::pow(4.9, 3) - std::pow(3.9, 3));
  EXPECT_NEAR(signed_volume(r.mesh), shell, 0.05 * shell);
}

TEST(Porous, AVoxelCoarserThanTheStructuresDetailIsWarned) {
  // The sponge's 24 coefficients span 21 knot intervals: 0.95 mm over a 20 mm box.
  FillOptions o;
  o.grid.voxel_size = 0.6;
  o.design.structure = sponge_structure();
  const FillResult r = fill(make_box({0, 0, 0}, {20, 20, 20}), o);
  bool warned = false;
  for (const std::string& w : r.report.warnings)
    warned = warned || w.find("knot span of 0.952 mm") != std::string::npos;
  EXPECT_TRUE(warned);
  o.grid.voxel_size = 0.4;
  for (const std::string& w : fill(make_box({0, 0, 0}, {20, 20, 20}), o).report.warnings)
    EXPECT_EQ(w.find("knot span"), std::string::npos) << w;
}

TEST(Porous, RecipesNameAStructureByItsFile) {
  const auto dir = scratch_dir();
  ItdfFile f;
  f.structure = sponge_structure();
  f.encoding[0].type = CoefficientType::Float64;  // stored exactly, to compare below
  write_itdf(dir / "sponge.itdf", f);
  write_file(dir / "r.json",
             R"({"voxel": 0.25, "field": "sponge.itdf", "lattice": {"porosity": 0.6}})");
  const FillOptions o = read_recipe_file((dir / "r.json").string());
  ASSERT_TRUE(o.design.structure);
  EXPECT_EQ(o.design.structure->field.coefficients, f.structure.field.coefficients);
  const FillResult r = fill(make_box({0, 0, 0}, {20, 20, 20}), o);
  EXPECT_NEAR(r.report.porosity(), 0.6, 0.01);
  // The echo names the file again (resolved against the folder it is read from).
  EXPECT_NE(recipe_json(r.resolved).find("sponge.itdf"), std::string::npos);
  write_file(dir / "bad.json", R"({"field": "missing.itdf"})");
  EXPECT_THROW(read_recipe_file((dir / "bad.json").string()), IoError);
}

TEST(Porous, APartThatMissesTheStructuresSolidIsWarned) {
  // A ball structure at porosity 0.3 fills most of its cube, but a model of two corner boxes
  // sees only the cube's corners, which stay mostly void: the part's porosity is far from 30 %
  // and the report says so with both numbers.
  FillOptions o;
  o.grid.voxel_size = 0.2;
  o.design.structure = ball_structure(0.3);
  o.design.porosity = 0.3;
  const TriangleSoup model =
      concat(make_box({0, 0, 0}, {5, 5, 5}), make_box({15, 15, 15}, {20, 20, 20}));
  const FillResult r = fill(model, o);
  ASSERT_GT(r.report.porosity(), 0.35);
  bool warned = false;
  for (const std::string& w : r.report.warnings)
    warned = warned || w.find("not the 30.0 % asked") != std::string::npos;
  EXPECT_TRUE(warned);
  // A model that fills its box gets the porosity asked, and no such warning.
  const FillResult whole = fill(make_box({0, 0, 0}, {20, 20, 20}), o);
  EXPECT_NEAR(whole.report.porosity(), 0.3, 0.02);
  for (const std::string& w : whole.report.warnings)
    EXPECT_EQ(w.find("% asked"), std::string::npos);
}
