// fill() says when its valid output is not the part asked for: islands that were whole
// features, voids sealed in, models in another unit; and its report says how it ran.
#include <gtest/gtest.h>

#include <cmath>
#include <tpmsfill/error.hpp>
#include <tpmsfill/fill.hpp>
#include <tpmsfill/mesh/components.hpp>

#include "test_util.hpp"

using namespace tpmsfill;

namespace {

std::string all_warnings(const FillReport& r) {
  std::string s;
  for (const std::string& w : r.warnings) s += w + "\n";
  return s;
}

bool has(const std::string& text, const std::string& part) {
  return text.find(part) != std::string::npos;
}

// A 10 mm block with two 1.2 mm rods sticking out 30 mm along x and y: a 4 mm gyroid cannot
// join the lattice inside the rods to the block's.
TriangleSoup block_with_rods() {
  TriangleSoup s = test::make_box({0, 0, 0}, {10, 10, 10});
  s = test::concat(s, test::make_box({9, 4.4, 4.4}, {40, 5.6, 5.6}));
  return test::concat(s, test::make_box({4.4, 9, 4.4}, {5.6, 40, 5.6}));
}

}  // namespace

TEST(FillWarnings, IslandsThatAreWholeFeaturesAreListedAndWarned) {
  const FillResult r = fill(block_with_rods(), test::gyroid_options(4, 0.1));
  const FillReport& rep = r.report;
  ASSERT_GT(rep.islands_removed, 1u);
  // More than 5 % of the lattice went: warned, with the fraction and the fixes.
  const std::string w = all_warnings(rep);
  EXPECT_TRUE(has(w, "% of the lattice")) << w;
  EXPECT_TRUE(has(w, "--keep-islands keeps them")) << w;
  EXPECT_GT(rep.islands_volume, 0.05 * (rep.islands_volume + rep.lattice_volume()));
  // The largest are listed, largest first, each inside a rod (beyond the block).
  ASSERT_FALSE(rep.largest_islands.empty());
  EXPECT_LE(rep.largest_islands.size(), 10u);
  double listed = 0;
  for (std::size_t i = 0; i < rep.largest_islands.size(); ++i) {
    const RemovedIsland& island = rep.largest_islands[i];
    if (i) {
      EXPECT_LE(island.volume, rep.largest_islands[i - 1].volume);
    }
    EXPECT_TRUE(island.bbox.max.x > 10 || island.bbox.max.y > 10);
    EXPECT_GT(island.volume, 0);
    listed += island.volume;
  }
  EXPECT_LE(listed, rep.islands_volume * (1 + 1e-12));
  // Kept, they are in the output and nothing is warned about.
  FillOptions keep = test::gyroid_options(4, 0.1);
  keep.keep_islands = true;
  const FillResult kept = fill(block_with_rods(), keep);
  EXPECT_EQ(kept.report.islands_removed, 0u);
  EXPECT_FALSE(has(all_warnings(kept.report), "island")) << all_warnings(kept.report);
  EXPECT_NEAR(kept.report.lattice_volume(), rep.lattice_volume() + rep.islands_volume,
              1e-6 * kept.report.lattice_volume());
}

TEST(FillWarnings, ALatticeThatFallsApartIsNamedAsSuch) {
  // FRD at level 0.2 mm is a cloud of separate blobs: removal takes nearly everything.
  FillOptions o = test::gyroid_options(2.5, 0.1);
  o.design.type = TpmsType::Frd;
  o.design.level = 0.2;
  const FillResult r = fill(test::make_box({0, 0, 0}, {8, 8, 8}), o);
  EXPECT_TRUE(has(all_warnings(r.report), "the lattice falls apart")) << all_warnings(r.report);
}

TEST(FillWarnings, WallsAndPoresBelowWhatAPrinterMakesAreWarnedWithWhere) {
  // A gyroid network at cell 3 mm: its struts are about 1 mm and its pores about 1.4 mm. Limits
  // of 2 mm flag them with their share, sizes and places, and the report holds the figures;
  // limits of 0.2 mm flag nothing inside the part. Limits need the measures.
  FillOptions o = test::gyroid_options(3, 0.15);
  o.measure = true;
  o.min_wall = 2;
  o.min_pore = 2;
  const TriangleSoup cube = test::make_box({0, 0, 0}, {9, 9, 9});
  const FillResult strict = fill(cube, o);
  const std::string w = all_warnings(strict.report);
  EXPECT_TRUE(has(w, "walls below --min-wall 2 mm: ")) << w;
  EXPECT_TRUE(has(w, "pores below --min-pore 2 mm: ")) << w;
  EXPECT_TRUE(has(w, " mm at (")) << w;
  ASSERT_TRUE(strict.report.measures);
  const LatticeMeasures& m = *strict.report.measures;
  EXPECT_GT(m.wall.below_limit, m.wall.samples / 2);
  EXPECT_GT(m.pore.below_limit, m.pore.samples / 2);
  EXPECT_EQ(strict.report.min_wall, 2);
  for (const SizeSample& s : m.wall.smallest) {
    for (int axis = 0; axis < 3; ++axis) {
      EXPECT_GT(s.at[axis], 0) << "inside the part";
      EXPECT_LT(s.at[axis], 9) << "inside the part";
    }
  }

  o.min_wall = o.min_pore = 0.2;
  const FillResult loose = fill(cube, o);
  EXPECT_FALSE(has(all_warnings(loose.report), "measured inside the part"))
      << all_warnings(loose.report);
  EXPECT_EQ(loose.report.measures->wall.below_limit, 0u);
  EXPECT_EQ(loose.report.measures->pore.below_limit, 0u);

  o.measure = false;
  EXPECT_THROW(fill(cube, o), InputError);
}

TEST(FillWarnings, SealedVoidsAreWarnedWithOrWithoutWindows) {
  // Spherical pores of radius 1 mm on a 3 mm lattice, 0.8 mm from every face: no pore meets
  // the 0.5 mm skin, so windows cannot open them and all 27 stay sealed.
  auto pores = [](Vec3 p) {
    auto d = [](double x) { return std::fabs(x - 3 * std::round(x / 3)); };
    return static_cast<float>(1.0 - std::sqrt(d(p.x) * d(p.x) + d(p.y) * d(p.y) + d(p.z) * d(p.z)));
  };
  const TriangleSoup model = test::make_box({1.2, 1.2, 1.2}, {10.8, 10.8, 10.8});
  for (int variant = 0; variant < 3; ++variant) {
    FillOptions o = test::gyroid_options(3, 0.1);
    o.design.custom = function_source(pores);
    o.skin = variant > 0 ? 0.5 : 0;
    o.skin_windows = variant == 2;
    const FillResult r = fill(model, o);
    EXPECT_EQ(r.report.cavities, 27u) << variant;
    EXPECT_NEAR(r.report.cavities_volume, 27 * 4.18879, 27 * 4.18879 * 0.02) << variant;
    const std::string w = all_warnings(r.report);
    EXPECT_TRUE(has(w, "27 void(s)")) << w;
    const char* sentence[] = {"the lattice encloses 27", "the closed skin seals 27",
                              "the skin windows left 27"};
    EXPECT_TRUE(has(w, sentence[variant])) << w;
  }
}

TEST(FillWarnings, ReportSaysHowTheJobRan) {
  FillOptions o = test::gyroid_options(2, 0.25);
  o.units = {.units = Units::Centimetre, .scale = 0.5};  // 4 cm × 0.5 = 20 mm
  o.design.rotation = rotation_from_euler({10, 20, 30});
  o.design.grading.push_back({Graded::Porosity, {.axis = {0, 0, 1}, .start = 0.5, .end = 0.8}});
  const FillResult r = fill(test::make_box({0, 0, 0}, {4, 4, 4}), o);
  EXPECT_EQ(r.report.units, "cm");
  EXPECT_EQ(r.report.scale, 0.5);
  EXPECT_EQ(r.report.mm_per_unit, 5);
  EXPECT_NEAR(r.report.input_bbox.size().z, 20, 1e-12);
  EXPECT_NEAR(r.report.model_volume, 8000, 8000 * 0.01);
  EXPECT_NEAR(r.report.rotation_degrees.x, 10, 1e-9);
  EXPECT_NEAR(r.report.rotation_degrees.z, 30, 1e-9);
  EXPECT_EQ(r.report.grading, "porosity 0.5 to 0.8 along z (0 to 20 mm)");
  const std::string text = to_text(r.report);
  EXPECT_TRUE(has(text, "rotated 10 20 30 deg")) << text;
  EXPECT_TRUE(has(text, "grading      porosity 0.5 to 0.8 along z")) << text;
  EXPECT_TRUE(has(text, "read as cm scaled by 0.5: 5 mm per unit")) << text;
}

// With a skin, --porosity is the part's, skin included: the lattice is solved more porous so
// the whole comes out as asked (a 0.5 mm skin on a 6 mm plate used to give 54 % for 70 %).
// Where the skin alone is too much, the warning gives both numbers and the part gets the most
// porous lattice.
TEST(FillWarnings, PorosityWithASkinIsThePartsOrWarned) {
  const TriangleSoup plate = test::make_box({0, 0, 0}, {30, 24, 6});
  for (const double skin : {0.3, 0.5}) {
    for (const bool slabs : {false, true}) {
      FillOptions o = test::gyroid_options(3, 0.15);
      o.design.porosity = 0.7;
      o.skin = skin;
      if (slabs) o.slab_planes = 9;
      const FillResult r = fill(plate, o);
      EXPECT_NEAR(r.report.porosity(), 0.7, 0.03)
          << "skin " << skin << (slabs ? " in slabs" : "") << "\n"
          << all_warnings(r.report);
      EXPECT_GT(r.report.unclipped_porosity, 0.7) << "the lattice is solved more porous";
      EXPECT_FALSE(has(all_warnings(r.report), "porosity")) << all_warnings(r.report);
      EXPECT_EQ(*r.report.porosity_target, 0.7);
      // The echo fixes the level it solved, so the recipe reruns the job exactly.
      EXPECT_FALSE(r.resolved.design.porosity);
      EXPECT_EQ(fill(plate, r.resolved).report.lattice_volume(), r.report.lattice_volume());
    }
  }
  // 1 mm and 2.5 mm skins are 43 % and 85 % of the plate: 70 % cannot be reached.
  for (const double skin : {1.0, 2.5}) {
    FillOptions o = test::gyroid_options(3, 0.15);
    o.design.porosity = 0.7;
    o.skin = skin;
    const FillResult r = fill(plate, o);
    const std::string w = all_warnings(r.report);
    EXPECT_TRUE(has(w, "of the part's volume: with it the part can be at most")) << w;
    EXPECT_TRUE(has(w, "not the 70.0 % asked")) << w;
    const double core = (30 - 2 * skin) * (24 - 2 * skin) * (6 - 2 * skin) / (30.0 * 24 * 6);
    EXPECT_NEAR(r.report.porosity(), 0.97 * core, 0.03) << w;
  }
}
