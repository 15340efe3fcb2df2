// Stage "slice": contours by marching squares (closed, oriented, simple), the exact check, and
// the layers' agreement with fill()'s mesh of the same job.
#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <cmath>
#include <numbers>
#include <tpmsfill/error.hpp>
#include <tpmsfill/fill.hpp>
#include <tpmsfill/slice.hpp>

#include "test_util.hpp"

using namespace tpmsfill;

namespace {

constexpr double kPi = std::numbers::pi;

// A plane of n × n nodes at spacing a with φ(x, y) given.
Field plane_field(int n, double a, const std::function<double(double, double)>& phi) {
  Field f{Grid{{0, 0, 0}, a, {n, n, 1}}, std::vector<float>(static_cast<std::size_t>(n) * n)};
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i)
      f.values[static_cast<std::size_t>(i + n * j)] =
          static_cast<float>(phi(f.grid.coordinate(0, i), f.grid.coordinate(1, j)));
  return f;
}

struct Sliced {
  SliceReport report;
  std::vector<Layer> layers;
};

Sliced slice_all(const TriangleSoup& model, const FillOptions& fo, double layer) {
  Sliced s;
  s.report = slice(model, fo, {.layer = layer}, [&](const Layer& l) {
    Layer copy = l;
    copy.field = {};
    s.layers.push_back(std::move(copy));
  });
  return s;
}

}  // namespace

TEST(TraceContours, DiskIsOneCounterClockwiseContourOfItsArea) {
  const double R = 3;
  const Field f =
      plane_field(101, 0.1, [&](double x, double y) { return std::hypot(x - 5, y - 5) - R; });
  const std::vector<Contour> c = trace_contours(f);
  ASSERT_EQ(c.size(), 1u);
  EXPECT_TRUE(c[0].outer());
  // Chords of a circle at spacing 0.1 miss at most a²/(8R) of its radius.
  EXPECT_NEAR(c[0].area, kPi * R * R, 2 * kPi * R * (0.01 / (8 * R)) + 1e-9);
  EXPECT_EQ(count_contour_defects(c, 0.1), 0u);
}

TEST(TraceContours, AnnulusHasAClockwiseHole) {
  const Field f = plane_field(101, 0.1, [](double x, double y) {
    const double r = std::hypot(x - 5, y - 5);
    return std::max(r - 4, 2 - r);
  });
  const std::vector<Contour> c = trace_contours(f);
  ASSERT_EQ(c.size(), 2u);
  const Contour& outer = c[0].outer() ? c[0] : c[1];
  const Contour& hole = c[0].outer() ? c[1] : c[0];
  EXPECT_TRUE(outer.outer());
  EXPECT_FALSE(hole.outer());
  EXPECT_NEAR(outer.area, kPi * 16, 0.01);
  EXPECT_NEAR(hole.area, -kPi * 4, 0.01);
}

TEST(TraceContours, SaddlesFollowTheAsymptoticDecider) {
  // One square with solid at two opposite corners. Joined when the solid's product wins:
  // one contour round both corners; separated otherwise: two.
  auto square = [](float a, float b, float c, float d) {
    Field f{Grid{{0, 0, 0}, 1, {4, 4, 1}}, std::vector<float>(16, 1.0f)};
    f.values[5] = a, f.values[6] = b, f.values[10] = c, f.values[9] = d;  // (1,1) (2,1) (2,2) (1,2)
    return trace_contours(f);
  };
  const std::vector<Contour> joined = square(-2, 1, -2, 1);     // (−2)(−2) = 4 > 1
  const std::vector<Contour> separated = square(-1, 2, -1, 2);  // 1 < 4
  const std::vector<Contour> tie = square(-1, 1, -1, 1);        // a tie separates
  EXPECT_EQ(joined.size(), 1u);
  EXPECT_EQ(separated.size(), 2u);
  EXPECT_EQ(tie.size(), 2u);
  for (const auto* c : {&joined, &separated, &tie}) {
    EXPECT_EQ(count_contour_defects(*c, 1), 0u);
    for (const Contour& k : *c) EXPECT_TRUE(k.outer());
  }
}

TEST(TraceContours, RandomFieldsGiveSimpleDisjointContours) {
  // Noise makes every configuration and saddle; the contours must still be closed, simple
  // and disjoint, and their areas must add up to what the sign pattern implies (the solid
  // nodes' share, within the cells the contours cut).
  test::Random random{12345};
  auto next = [&] { return random.next() - 0.5; };
  for (int trial = 0; trial < 20; ++trial) {
    Field f = plane_field(40, 0.25, [&](double, double) { return next(); });
    for (int i = 0; i < 40; ++i)
      for (int k : {0, 39}) f.values[i + 40 * k] = f.values[k + 40 * i] = 1;
    std::uint64_t pairs = 0;
    const std::vector<Contour> c = trace_contours(f);
    EXPECT_EQ(count_contour_defects(c, 0.25, &pairs), 0u) << "trial " << trial;
    EXPECT_GT(pairs, 0u);
    double area = 0;
    for (const Contour& k : c) area += k.area;
    EXPECT_GT(area, 0);
    EXPECT_LT(area, 39 * 39 * 0.0625);
  }
}

TEST(TraceContours, RefusesAPlaneWhoseBorderIsSolid) {
  const Field f = plane_field(10, 1, [](double, double) { return -1; });
  EXPECT_THROW(trace_contours(f), InputError);
}

TEST(ContourDefects, FindsCrossingsTouchesAndFolds) {
  const Contour square{{{0, 0}, {1, 0}, {1, 1}, {0, 1}}, 1};
  EXPECT_EQ(count_contour_defects({square}, 1), 0u);
  const Contour eight{{{0, 0}, {1, 1}, {1, 0}, {0, 1}}, 0};  // a bow tie: crosses itself
  EXPECT_GT(count_contour_defects({eight}, 1), 0u);
  const Contour touching{{{1, 0.5}, {2, 0}, {2, 1}}, 0.5};  // its corner on the square's side
  EXPECT_GT(count_contour_defects({square, touching}, 1), 0u);
  const Contour fold{{{0, 0}, {2, 0}, {1, 0}, {1, 1}}, 0};  // turns back along itself
  EXPECT_GT(count_contour_defects({fold}, 1), 0u);
  const Contour far{{{5, 5}, {6, 5}, {6, 6}}, 0.5};
  EXPECT_EQ(count_contour_defects({square, far}, 1), 0u);
}

TEST(Slice, VolumeMatchesFillsLatticeWithinOnePercent) {
  const TriangleSoup sphere = test::make_sphere({0, 0, 0}, 5, 4);
  FillOptions fo = test::gyroid_options(2.5, 0.1);
  fo.keep_islands = true;  // a layer cannot tell an island: compare the same solid
  const FillResult filled = fill(sphere, fo);
  const Sliced s = slice_all(sphere, fo, 0.05);
  const double lattice = filled.report.lattice_volume();
  EXPECT_NEAR(s.report.volume, lattice, 0.01 * lattice);
  ASSERT_EQ(s.layers.size(), s.report.layers.size());
  EXPECT_EQ(s.report.layers.size(), layer_count(bounding_box(sphere), {.layer = 0.05}));
  EXPECT_GT(s.report.segment_pairs_checked, 0u);
  EXPECT_EQ(s.report.job.design, filled.report.design);
  // The model's volume from the layers' inside nodes, against the sphere's own.
  EXPECT_NEAR(s.report.job.model_volume, test::signed_volume(sphere),
              0.01 * test::signed_volume(sphere));
}

TEST(Slice, EachLayerIsTheSectionOfFillsMesh) {
  const TriangleSoup torus = test::make_torus(6, 2.5, 96, 48);
  FillOptions fo = test::gyroid_options(2, 0.1);
  fo.keep_islands = true;
  const FillResult filled = fill(torus, fo);
  const Sliced s = slice_all(torus, fo, 0.3);
  for (const Layer& layer : s.layers) {
    // Both sample the same nodes in x and y, but between node planes fill's surface is
    // interpolated along z where slice samples the plane itself: fill's surface may sit up to
    // a voxel higher or lower. So the layer's area lies between fill's sections within a voxel
    // of it (and where the surface is steep, they are all nearly equal).
    double lo = HUGE_VAL, hi = -HUGE_VAL;
    for (double dz : {-0.1, -0.05, 0.0, 0.05, 0.1}) {
      const double a = test::section_area(filled.mesh, layer.z + dz);
      lo = std::min(lo, a), hi = std::max(hi, a);
    }
    EXPECT_GE(layer.area, lo - 0.01 * hi) << "layer " << layer.index << " z " << layer.z;
    EXPECT_LE(layer.area, hi * 1.01) << "layer " << layer.index << " z " << layer.z;
    for (const Contour& c : layer.contours) EXPECT_GE(c.points.size(), 3u);
  }
}

TEST(Slice, ContoursAreOrientedAndTheSkinClosesTheSection) {
  // A closed skin makes each layer's outline the sphere's circle: one outer contour of area
  // π(R² − z²) holding the lattice's holes.
  const double R = 5;
  const TriangleSoup sphere = test::make_sphere({0, 0, 0}, R, 5);
  FillOptions fo = test::gyroid_options(2.5, 0.08);
  fo.skin = 0.5;
  const Sliced s = slice_all(sphere, fo, 0.5);
  for (const Layer& layer : s.layers) {
    if (std::fabs(layer.z) > 3.5) continue;  // near the poles the skin is the whole section
    double largest = 0;
    int outer = 0;
    for (const Contour& c : layer.contours) {
      largest = std::max(largest, c.area);
      outer += c.outer();
    }
    const double disk = kPi * (R * R - layer.z * layer.z);
    EXPECT_NEAR(largest, disk, 0.02 * disk) << "z " << layer.z;
    EXPECT_GE(layer.contours.size() - outer, 1u) << "no hole inside the skin at z " << layer.z;
    EXPECT_LT(layer.area, largest);
  }
}

TEST(Slice, DepthGradingReadsTheSameDepthAsFill) {
  // The depth below the surface comes from fill's grid planes around each layer: it must reach
  // as deep as the ramp does, or the graded porosity would differ from fill's.
  const TriangleSoup box = test::make_box({0, 0, 0}, {8, 8, 8});
  FillOptions fo = test::gyroid_options(2, 0.1);
  fo.keep_islands = true;
  fo.design.porosity = 0.6;
  fo.design.grading.push_back(
      {Graded::Porosity,
       Ramp{.shape = RampShape::Depth, .from = 0, .to = 2, .start = 0.4, .end = 0.8}});
  const FillResult filled = fill(box, fo);
  const Sliced s = slice_all(box, fo, 0.1);
  EXPECT_NEAR(s.report.volume, filled.report.lattice_volume(),
              0.01 * filled.report.lattice_volume());
  EXPECT_EQ(s.report.slab_planes, 3);  // the depth comes from fill's grid planes, not the slab
}

TEST(Slice, SameLayersWhateverTheThreadCount) {
  const TriangleSoup torus = test::make_torus(5, 2, 64, 32);
  const FillOptions fo = test::gyroid_options(2, 0.15);
  auto run = [&](int threads) {
    tbb::global_control c(tbb::global_control::max_allowed_parallelism, threads);
    return slice_all(torus, fo, 0.4).layers;
  };
  const std::vector<Layer> one = run(1), many = run(8);
  ASSERT_EQ(one.size(), many.size());
  for (std::size_t l = 0; l < one.size(); ++l) {
    ASSERT_EQ(one[l].contours.size(), many[l].contours.size());
    for (std::size_t c = 0; c < one[l].contours.size(); ++c)
      EXPECT_EQ(one[l].contours[c].points, many[l].contours[c].points);
  }
}

TEST(Slice, OpenScanIsClassifiedAsFillDoes) {
  // A box with a hole: auto cleans and caps it, as fill does, and the volumes still agree.
  const TriangleSoup open = test::make_box_with_hole({0, 0, 0}, {6, 6, 6});
  FillOptions fo = test::gyroid_options(2, 0.12);
  fo.keep_islands = true;
  const FillResult filled = fill(open, fo);
  const Sliced s = slice_all(open, fo, 0.1);
  EXPECT_TRUE(s.report.job.cleaned());
  EXPECT_NEAR(s.report.volume, filled.report.lattice_volume(),
              0.01 * filled.report.lattice_volume());
}

TEST(Slice, UnitsAndLayerRange) {
  // A model in centimetres comes out in millimetres, and layers cover its height exactly.
  const TriangleSoup cm = test::make_box({0, 0, 0}, {1, 1, 0.8});
  FillOptions fo = test::gyroid_options(3, 0.2);
  fo.units.units = Units::Centimetre;
  const Sliced s = slice_all(cm, fo, 0.5);
  ASSERT_EQ(s.layers.size(), 16u);
  EXPECT_DOUBLE_EQ(s.layers.front().bottom, 0);
  EXPECT_NEAR(s.layers.back().top, 8, 1e-12);
  EXPECT_NEAR(s.layers[3].z, 1.75, 1e-12);
  EXPECT_NEAR(s.report.job.model_volume, 800, 8);
}

TEST(Slice, RefusesBadOptionsAndPassesTheSinksErrorOn) {
  const TriangleSoup box = test::make_box({0, 0, 0}, {4, 4, 4});
  const FillOptions fo = test::gyroid_options(2, 0.2);
  auto none = [](const Layer&) {};
  EXPECT_THROW(slice(box, fo, {.layer = 0}, none), InputError);
  EXPECT_THROW(slice(box, fo, {.layer = -1}, none), InputError);
  EXPECT_THROW(slice(box, fo, {.layer = 0.1, .start = NAN}, none), InputError);
  int calls = 0;
  EXPECT_THROW(slice(box, fo, {.layer = 0.5},
                     [&](const Layer&) {
                       if (++calls == 3) throw IoError("disk full");
                     }),
               IoError);
  EXPECT_EQ(calls, 3);
  FillOptions tiny = fo;
  tiny.memory_budget = 1000;
  EXPECT_THROW(slice(box, tiny, {.layer = 0.5}, none), ResourceError);
}

TEST(Slice, CancelStopsBeforeTheNextLayers) {
  struct StopAtSlice : Progress {
    bool report(double stage, double) override { return !(in_slice && stage > 0); }
    void begin(const StageInfo& s) override { in_slice = s.name == "slice"; }
    bool in_slice = false;
  } stop;
  const TriangleSoup box = test::make_box({0, 0, 0}, {4, 4, 20});
  int layers = 0;
  EXPECT_THROW(slice(box, test::gyroid_options(2, 0.2), {.layer = 0.1, .progress = &stop},
                     [&](const Layer&) { ++layers; }),
               Cancelled);
  EXPECT_LT(layers, 200);
}

TEST(Slice, WarnsOfLayersNoPrinterUsesAndOfEmptyOnes) {
  // A thickness meant in µm (30 mm layers) and a start far below the model: each a warning
  // with the numbers, never a silent result.
  const TriangleSoup box = test::make_box({0, 0, 0}, {6, 6, 6});
  const FillOptions fo = test::gyroid_options(2, 0.2);
  auto none = [](const Layer&) {};
  const SliceReport thick = slice(box, fo, {.layer = 2}, none);
  ASSERT_EQ(thick.layers.size(), 3u);
  ASSERT_EQ(thick.job.warnings.size(), 1u);
  EXPECT_NE(thick.job.warnings[0].find("--layer is in mm"), std::string::npos);
  try {  // so thick that no layer's centre meets the model: refused, saying why
    slice(box, fo, {.layer = 30}, none);
    FAIL() << "no InputError";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("no layer meets it"), std::string::npos) << e.what();
  }
  const SliceReport low = slice(box, fo, {.layer = 0.5, .start = -10}, none);
  ASSERT_EQ(low.job.warnings.size(), 1u);
  EXPECT_NE(low.job.warnings[0].find("the first 20 layer(s) are empty"), std::string::npos)
      << low.job.warnings[0];
  EXPECT_TRUE(slice(box, fo, {.layer = 0.5}, none).job.warnings.empty());
}
