// Stage "measure": pore and wall sizes and labyrinths of fields made in code whose answers are
// known (flat walls, spherical pores, gyroid sheet and network).
#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <functional>
#include <numbers>
#include <numeric>
#include <random>
#include <string>
#include <tpmsfill/error.hpp>
#include <tpmsfill/lattice/measure.hpp>
#include <tpmsfill/lattice/tpms.hpp>
#include <tpmsfill/sampling/voxel.hpp>

#include "test_util.hpp"

namespace tpmsfill {
namespace {

struct Scene {
  Field phi;
  Mask inside;
};

// Signed distance to an axis-aligned box (negative inside).
double box_distance(const Box3& box, Vec3 p) {
  double outside = 0, inside = -1e300;
  for (int axis = 0; axis < 3; ++axis) {
    const double q = std::max(box.min[axis] - p[axis], p[axis] - box.max[axis]);
    outside += q > 0 ? q * q : 0;
    inside = std::max(inside, q);
  }
  return outside > 0 ? std::sqrt(outside) : std::min(inside, 0.0);
}

// The box model on a grid of spacing a (pad mm around grid_box, by default the box), with
// φ = max(φ_box, lattice(p)) as compose_field makes it: the lattice clipped to the box.
Scene make_scene(const Box3& box, double a, double pad, const std::function<double(Vec3)>& lattice,
                 const Box3* grid_box = nullptr) {
  Scene s;
  const Grid g = test::grid_around(grid_box ? *grid_box : box, a, pad);
  s.phi = {g, std::vector<float>(g.node_count())};
  s.inside = {g, std::vector<std::uint8_t>(g.node_count())};
  for (int k = 0; k < g.dims[2]; ++k)
    for (int j = 0; j < g.dims[1]; ++j)
      for (int i = 0; i < g.dims[0]; ++i) {
        const Vec3 p = g.node(i, j, k);
        const double model = box_distance(box, p);
        s.phi.values[g.index(i, j, k)] = static_cast<float>(std::max(model, lattice(p)));
        s.inside.values[g.index(i, j, k)] = model < 0;
      }
  return s;
}

// Walls of thickness t with gaps g between them, normal to `normal` (unit), the first wall
// starting at offset along the normal: signed distance to the nearest wall face.
std::function<double(Vec3)> flat_walls(Vec3 normal, double offset, double t, double g) {
  return [=](Vec3 p) {
    const double period = t + g;
    const double u = std::fmod(std::fmod(dot(p, normal) - offset, period) + period, period);
    return u < t ? -std::min(u, t - u) : std::min(u - t, period - u);
  };
}

// Gyroid f = cos X sin Y + cos Y sin Z + cos Z sin X (X = 2πx/T, ...) divided by |∇f|: a
// first-order distance to the minimal surface, mm.
double gyroid(Vec3 p, double T) {
  const double w = 2 * std::numbers::pi / T;
  const double X = w * p.x, Y = w * p.y, Z = w * p.z;
  const double f =
      std::cos(X) * std::sin(Y) + std::cos(Y) * std::sin(Z) + std::cos(Z) * std::sin(X);
  const Vec3 grad = w * Vec3{std::cos(Z) * std::cos(X) - std::sin(X) * std::sin(Y),
                             std::cos(X) * std::cos(Y) - std::sin(Y) * std::sin(Z),
                             std::cos(Y) * std::cos(Z) - std::sin(Z) * std::sin(X)};
  return f / std::max(norm(grad), 0.5 * w);
}

const Box3 kCube{{0, 0, 0}, {4, 4, 4}};

void expect_consistent(const SizeDistribution& s, int bins) {
  if (s.samples == 0) {
    EXPECT_EQ(s, SizeDistribution{});
    return;
  }
  ASSERT_EQ(s.bin_edges.size(), static_cast<std::size_t>(bins) + 1);
  ASSERT_EQ(s.counts.size(), static_cast<std::size_t>(bins));
  EXPECT_EQ(std::accumulate(s.counts.begin(), s.counts.end(), std::uint64_t{0}), s.samples);
  EXPECT_EQ(s.bin_edges.front(), s.min);
  EXPECT_TRUE(std::is_sorted(s.bin_edges.begin(), s.bin_edges.end()));
  EXPECT_LE(s.min, s.p10);
  EXPECT_LE(s.p10, s.p50);
  EXPECT_LE(s.p50, s.p90);
  EXPECT_LE(s.p90, s.max);
  EXPECT_LE(s.min, s.mean);
  EXPECT_LE(s.mean, s.max);
}

}  // namespace

TEST(Measure, FlatWallsReadTheirThicknessAndGap) {
  // Three gaps of 0.77 mm between four walls of 0.43 mm, sampled at a = 0.1 mm with the
  // faces between nodes; the box starts and ends with a wall.
  const double a = 0.1, t = 0.43, gap = 0.77, x0 = 0.013;
  const Box3 box{{x0, 0, 0}, {x0 + 3 * (t + gap) + t, 3, 3}};
  const Scene s = make_scene(box, a, 0.25, flat_walls({1, 0, 0}, x0, t, gap));
  const LatticeMeasures m = measure_lattice(s.phi, s.inside);
  expect_consistent(m.pore, 16);
  expect_consistent(m.wall, 16);
  EXPECT_GT(m.pore.samples, 1000u);
  EXPECT_GT(m.wall.samples, 1000u);
  EXPECT_NEAR(m.pore.min, gap, a / 2);
  EXPECT_NEAR(m.pore.max, gap, a / 2);
  EXPECT_NEAR(m.wall.min, t, a / 2);
  EXPECT_NEAR(m.wall.max, t, a / 2);
  EXPECT_EQ(m.void_components, 3u);
  EXPECT_EQ(m.labyrinths, 3u);
  EXPECT_NEAR(m.largest_void_fraction, 1.0 / 3, 1e-9);
}

TEST(Measure, PrintabilityTellsTheDesignsThinWallsFromTheSurfacesSlivers) {
  // Walls of 0.43 mm with gaps of 0.77 mm, the box's first face cutting the first wall to a
  // sliver of 0.12 mm. A 0.3 mm limit finds nothing thin inside the part and the sliver at its
  // surface; a 0.5 mm limit finds the walls themselves. The smallest samples are the design's
  // walls (0.43 mm within half a voxel), none of them the sliver.
  const double a = 0.1, t = 0.43, gap = 0.77, x0 = 0.013, sliver = 0.12;
  const Box3 box{{x0 + t - sliver, 0, 0}, {x0 + 3 * (t + gap) + t, 3, 3}};
  const Scene s = make_scene(box, a, 0.25, flat_walls({1, 0, 0}, x0, t, gap));
  const LatticeMeasures loose = measure_lattice(s.phi, s.inside, {.min_wall = 0.3});
  EXPECT_EQ(loose.wall.below_limit, 0u);
  EXPECT_GT(loose.wall.below_limit_at_surface, 0u);
  EXPECT_EQ(loose.pore.below_limit + loose.pore.below_limit_at_surface, 0u) << "no pore limit";
  ASSERT_EQ(loose.wall.smallest.size(), 10u);
  for (std::size_t i = 0; i < loose.wall.smallest.size(); ++i) {
    const SizeSample& w = loose.wall.smallest[i];
    EXPECT_NEAR(w.diameter, t, a / 2) << i;
    EXPECT_GT(w.at.x, box.min.x + sliver) << "not the sliver";
    if (i > 0) {
      EXPECT_LE(loose.wall.smallest[i - 1].diameter, w.diameter);
    }
  }
  const LatticeMeasures tight = measure_lattice(s.phi, s.inside, {.min_wall = 0.5});
  EXPECT_GT(tight.wall.below_limit, 0u);
  EXPECT_EQ(tight.wall.below_limit + tight.wall.below_limit_at_surface, tight.wall.samples)
      << "every wall is thinner than 0.5 mm";
  EXPECT_EQ(tight.wall.smallest, loose.wall.smallest) << "limits do not change the samples";
  EXPECT_THROW(measure_lattice(s.phi, s.inside, {.min_wall = -1}), InputError);
}

TEST(Measure, ObliqueWallsReadTheirThicknessAndGap) {
  // Walls whose normal (2, 1, 2)/3 is on no grid axis: the surface cuts the cells anyhow.
  const double a = 0.1, t = 0.55, gap = 0.9;
  const Box3 box{{0, 0, 0}, {4, 4, 4}};
  const Scene s = make_scene(box, a, 0.25, flat_walls({2.0 / 3, 1.0 / 3, 2.0 / 3}, 0.031, t, gap));
  const LatticeMeasures m = measure_lattice(s.phi, s.inside);
  // The oblique ridge is sampled finely, so the median reads the width within half a voxel;
  // the largest within a voxel (near the box's faces a pore sphere can bulge out of the model).
  EXPECT_NEAR(m.pore.p50, gap, a / 2);
  EXPECT_NEAR(m.wall.p50, t, a / 2);
  EXPECT_NEAR(m.pore.max, gap, a);
  EXPECT_NEAR(m.wall.max, t, a);
}

TEST(Measure, SphericalPoresReadTheirDiameter) {
  // Eight spherical pores of 1 mm in a solid block, centred at random sub-voxel offsets.
  const double a = 0.1, D = 1.0;
  std::vector<Vec3> centres;
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> jitter(0, a);
  for (int c = 0; c < 8; ++c)
    centres.push_back(Vec3{1.0 + 1.5 * (c & 1), 1.0 + 1.5 * (c >> 1 & 1), 1.0 + 1.5 * (c >> 2)} +
                      Vec3{jitter(rng), jitter(rng), jitter(rng)});
  const Box3 box{{0, 0, 0}, {3.6, 3.6, 3.6}};
  const Scene s = make_scene(box, a, 0.2, [&](Vec3 p) {
    double phi = -1e9;
    for (const Vec3& c : centres) phi = std::max(phi, D / 2 - norm(p - c));
    return phi;
  });
  const LatticeMeasures m = measure_lattice(s.phi, s.inside);
  expect_consistent(m.pore, 16);
  EXPECT_EQ(m.void_components, 8u);
  EXPECT_EQ(m.labyrinths, 8u);
  EXPECT_GE(m.pore.samples, 8u);
  EXPECT_NEAR(m.pore.max, D, a);
  // Each sphere's ridge is the node nearest its centre, up to √3/2·a away (centre mid-cell),
  // where twice the distance reads up to √3·a low and never high: with the a/2 added back a
  // diameter lies in [D − (√3 − 1/2)·a, D + a/2].
  EXPECT_GE(m.pore.min, D - std::sqrt(3.0) * a + a / 2 - 1e-3);
  EXPECT_LE(m.pore.max, D + a / 2 + 1e-3);
}

TEST(Measure, GyroidSheetHasTwoLabyrinthsAndNetworkOne) {
  const double T = 2, a = 0.1, t = 0.3;
  const Scene sheet =
      make_scene(kCube, a, 0.2, [&](Vec3 p) { return std::abs(gyroid(p, T)) - t / 2; });
  const LatticeMeasures ms = measure_lattice(sheet.phi, sheet.inside);
  EXPECT_EQ(ms.labyrinths, 2u);
  EXPECT_GE(ms.void_components, 2u);
  EXPECT_LE(ms.largest_void_fraction, 0.55);  // the two labyrinths are congruent
  EXPECT_NEAR(ms.wall.p50, t, a);             // a sheet is as thick as it was made
  expect_consistent(ms.pore, 16);
  expect_consistent(ms.wall, 16);

  const Scene network = make_scene(kCube, a, 0.2, [&](Vec3 p) { return gyroid(p, T); });
  const LatticeMeasures mn = measure_lattice(network.phi, network.inside);
  EXPECT_EQ(mn.labyrinths, 1u);
  EXPECT_GT(mn.largest_void_fraction, 0.9);
  // The gyroid's two network halves are congruent: the widest struts are as thick as the
  // widest pores are wide. (Not the medians: struts cut by the cube's faces are thin walls,
  // while cut pores are measured as if they went on.)
  EXPECT_NEAR(mn.pore.p90, mn.wall.p90, a);
  EXPECT_NEAR(mn.pore.max, mn.wall.max, a);
}

TEST(Measure, VoidComponentsAre6Connected) {
  // Inside everywhere; two void cubes that share only an edge, and a third apart: three
  // components (a 26-connected labelling would see two).
  Grid g;
  g.dims = {12, 12, 12};
  g.spacing = 0.1;
  Field phi{g, std::vector<float>(g.node_count(), -1.0f)};
  const Mask inside{g, std::vector<std::uint8_t>(g.node_count(), 1)};
  auto open = [&](int i0, int j0, int k0, int size) {
    for (int k = k0; k < k0 + size; ++k)
      for (int j = j0; j < j0 + size; ++j)
        for (int i = i0; i < i0 + size; ++i) phi.values[g.index(i, j, k)] = 1.0f;
  };
  open(1, 1, 1, 3);  // nodes 1..3
  open(4, 4, 1, 3);  // touches the first along the edge i = 3/4, j = 3/4
  open(8, 8, 8, 2);
  const LatticeMeasures m = measure_lattice(phi, inside, {.min_labyrinth_fraction = 0.2});
  EXPECT_EQ(m.void_components, 3u);
  EXPECT_EQ(m.labyrinths, 2u);  // 27, 27 and 8 of 62 void nodes
  EXPECT_NEAR(m.largest_void_fraction, 27.0 / 62, 1e-12);
}

TEST(Measure, NothingToMeasure) {
  const Box3 box{{0, 0, 0}, {1, 1, 1}};
  auto all = [](double v) { return [v](Vec3) { return v; }; };
  const Scene solid = make_scene(box, 0.1, 0.2, all(-1));  // no void
  const LatticeMeasures ms = measure_lattice(solid.phi, solid.inside);
  EXPECT_EQ(ms.pore, SizeDistribution{});
  EXPECT_EQ(ms.void_components, 0u);
  EXPECT_EQ(ms.labyrinths, 0u);
  EXPECT_EQ(ms.largest_void_fraction, 0.0);
  EXPECT_NEAR(ms.wall.max, 1.0, 0.1);  // the whole block is one wall

  const Scene hollow = make_scene(box, 0.1, 0.2, all(1));  // no solid: nothing bounds a pore
  const LatticeMeasures mh = measure_lattice(hollow.phi, hollow.inside);
  EXPECT_EQ(mh.pore, SizeDistribution{});
  EXPECT_EQ(mh.wall, SizeDistribution{});
  EXPECT_EQ(mh.void_components, 1u);
  EXPECT_EQ(mh.largest_void_fraction, 1.0);

  Scene empty = solid;  // no model
  std::fill(empty.inside.values.begin(), empty.inside.values.end(), 0);
  EXPECT_EQ(measure_lattice(empty.phi, empty.inside), LatticeMeasures{});
}

TEST(Measure, SameResultForAnyThreadCount) {
  const Scene s = make_scene(kCube, 0.08, 0.2, [](Vec3 p) { return gyroid(p, 1.7) + 0.05; });
  LatticeMeasures one, many;
  {
    tbb::global_control c(tbb::global_control::max_allowed_parallelism, 1);
    one = measure_lattice(s.phi, s.inside, {.histogram_bins = 7});
  }
  {
    tbb::global_control c(tbb::global_control::max_allowed_parallelism, 4);
    many = measure_lattice(s.phi, s.inside, {.histogram_bins = 7});
  }
  EXPECT_EQ(one, many);
  expect_consistent(one.pore, 7);
  expect_consistent(one.wall, 7);
}

TEST(Measure, RejectsBadInput) {
  const Scene s = make_scene({{0, 0, 0}, {1, 1, 1}}, 0.1, 0.2, [](Vec3 p) { return p.x - 0.5; });
  Field shifted = s.phi;
  shifted.grid.origin.x += 0.01;
  EXPECT_THROW(measure_lattice(shifted, s.inside), InputError);
  Mask short_mask = s.inside;
  short_mask.values.pop_back();
  EXPECT_THROW(measure_lattice(s.phi, short_mask), InputError);
  EXPECT_THROW(measure_lattice(s.phi, s.inside, {.histogram_bins = 0}), InputError);
  EXPECT_THROW(measure_lattice(s.phi, s.inside, {.min_labyrinth_fraction = 1.5}), InputError);
}

TEST(Measure, ReportsProgressAndCancels) {
  struct Recorder : Progress {
    std::string stage;
    double last = 0;
    bool stop = false;
    void begin(std::string_view name) override { stage = name; }
    bool report(double fraction) override {
      last = fraction;
      return !stop;
    }
  };
  const Scene s = make_scene({{0, 0, 0}, {1, 1, 1}}, 0.1, 0.2, [](Vec3 p) { return p.x - 0.5; });
  Recorder recorder;
  measure_lattice(s.phi, s.inside, {.progress = &recorder});
  EXPECT_EQ(recorder.stage, "measure");
  EXPECT_EQ(recorder.last, 1.0);
  recorder.stop = true;
  EXPECT_THROW(measure_lattice(s.phi, s.inside, {.progress = &recorder}), Cancelled);
}

// Timing on a femur-sized grid (6.3 M nodes), best of 3 at 1 and 2 threads: run with
// --gtest_also_run_disabled_tests --gtest_filter='Measure.DISABLED_Timing*'.
TEST(Measure, DISABLED_TimingOnA185CubedGrid) {
  Grid g;
  g.spacing = 0.1;
  g.origin = {-0.2, -0.2, -0.2};
  g.dims = {185, 185, 185};
  TpmsOptions lattice;  // gyroid network, 2 mm cells
  const Field phi = sample_field(tpms_source(lattice), g);
  Mask inside{g, std::vector<std::uint8_t>(g.node_count())};
  for (int k = 0; k < 185; ++k)  // a ball: a clipped lattice like a real model's
    for (int j = 0; j < 185; ++j)
      for (int i = 0; i < 185; ++i)
        inside.values[g.index(i, j, k)] = norm(g.node(i, j, k) - Vec3{9, 9, 9}) < 8.8;
  Mask solid{g, std::vector<std::uint8_t>(g.node_count())};
  for (std::size_t n = 0; n < solid.values.size(); ++n)
    solid.values[n] = inside.values[n] && phi.values[n] < 0;
  for (int threads : {1, 2}) {
    tbb::global_control c(tbb::global_control::max_allowed_parallelism, threads);
    double edt = 1e9, measure = 1e9;
    LatticeMeasures m;
    for (int rep = 0; rep < 3; ++rep) {
      auto t0 = std::chrono::steady_clock::now();
      const Field d = distance_transform(solid);
      edt = std::min(edt, test::seconds_since(t0));
      EXPECT_EQ(d.values.size(), g.node_count());
      t0 = std::chrono::steady_clock::now();
      m = measure_lattice(phi, inside);
      measure = std::min(measure, test::seconds_since(t0));
    }
    std::printf(
        "%zu nodes, %d threads: distance_transform %.3f s, measure_lattice %.3f s; pore p50 %.3f "
        "max %.3f (%llu samples), wall p50 %.3f max %.3f (%llu), %llu void components, %llu "
        "labyrinths\n",
        g.node_count(), threads, edt, measure, m.pore.p50, m.pore.max,
        static_cast<unsigned long long>(m.pore.samples), m.wall.p50, m.wall.max,
        static_cast<unsigned long long>(m.wall.samples),
        static_cast<unsigned long long>(m.void_components),
        static_cast<unsigned long long>(m.labyrinths));
  }
}

// The accuracy table of docs/method.md: diameter error / a over random placements (random
// sub-voxel offsets, random directions), a = 0.1 mm. Run with --gtest_also_run_disabled_tests.
TEST(Measure, DISABLED_AccuracySurvey) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(0, 1);
  const double a = 0.1;
  auto unit = [&] {
    const Vec3 v{u(rng) - 0.5, u(rng) - 0.5, u(rng) - 0.5};
    return (1 / norm(v)) * v;
  };
  auto jitter = [&](Vec3 c) { return c + Vec3{u(rng) * a, u(rng) * a, u(rng) * a}; };
  // statistic(measures) − truth over `trials` scenes from make(): min, mean, max, in voxels.
  auto survey = [&](const char* what, double truth, int trials, auto make, auto statistic) {
    double lo = 1e9, hi = -1e9, sum = 0;
    for (int t = 0; t < trials; ++t) {
      const Scene s = make();
      const double e = (statistic(measure_lattice(s.phi, s.inside)) - truth) / a;
      lo = std::min(lo, e), hi = std::max(hi, e), sum += e;
    }
    std::printf("%-44s error/a  min %+.2f  mean %+.2f  max %+.2f\n", what, lo, sum / trials, hi);
  };
  auto pore_max = [](const LatticeMeasures& m) { return m.pore.max; };
  auto pore_p50 = [](const LatticeMeasures& m) { return m.pore.p50; };
  auto wall_p50 = [](const LatticeMeasures& m) { return m.wall.p50; };
  const Box3 cube{{0, 0, 0}, {3, 3, 3}};
  for (double D : {0.6, 1.0, 2.0}) {
    const std::string what = "sphere pore D " + std::to_string(D).substr(0, 3) + ", pore max";
    survey(
        what.c_str(), D, 30,
        [&] {
          const Vec3 c = jitter({1.5, 1.5, 1.5});
          return make_scene(cube, a, 0.2, [&](Vec3 p) { return D / 2 - norm(p - c); });
        },
        pore_max);
  }
  for (double D : {0.6, 1.0}) {
    const std::string what = "cylinder pore D " + std::to_string(D).substr(0, 3) + ", pore p50";
    survey(
        what.c_str(), D, 20,
        [&] {
          const Vec3 axis = unit(), c = jitter({1.5, 1.5, 1.5});
          return make_scene(cube, a, 0.2, [&](Vec3 p) {
            const Vec3 v = p - c;
            return D / 2 - norm(v - dot(v, axis) * axis);
          });
        },
        pore_p50);
  }
  for (double W : {0.45, 1.0}) {
    const std::string w = std::to_string(W).substr(0, 4);
    // Whole walls and gaps only: the box starts and ends with a wall.
    const Box3 tall{{0, 0, 0}, {3, 3, 1 + 5 * W}};
    auto axis_slabs = [&] {
      const double z0 = u(rng);
      return make_scene({{0, 0, z0}, {3, 3, z0 + 5 * W}}, a, 0.2, flat_walls({0, 0, 1}, z0, W, W),
                        &tall);
    };
    survey(("axis slabs " + w + ", pore p50").c_str(), W, 20, axis_slabs, pore_p50);
    survey(("axis slabs " + w + ", wall p50").c_str(), W, 20, axis_slabs, wall_p50);
    survey(("oblique slabs " + w + ", pore p50").c_str(), W, 20,
           [&] {
             const double offset = u(rng);
             return make_scene(cube, a, 0.2, flat_walls(unit(), offset, W, W));
           },
           pore_p50);
  }
}

}  // namespace tpmsfill
