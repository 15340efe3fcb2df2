// Stage "distance": signed distances on the band and on the whole grid.
#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <algorithm>
#include <cmath>
#include <tpmsfill/error.hpp>
#include <tpmsfill/sampling/classify.hpp>
#include <tpmsfill/sampling/distance.hpp>
#include <tpmsfill/sampling/spatial.hpp>

#include "test_util.hpp"

namespace tpmsfill {
namespace {

/// Inside nodes with an outside 26-neighbour, and outside nodes with an inside one.
Band band_of(const Mask& mask) {
  const Grid& g = mask.grid;
  Band band{g, {}};
  for (int k = 0; k < g.dims[2]; ++k)
    for (int j = 0; j < g.dims[1]; ++j)
      for (int i = 0; i < g.dims[0]; ++i) {
        const std::uint8_t v = mask.values[g.index(i, j, k)];
        bool boundary = false;
        for (int dk = -1; dk <= 1 && !boundary; ++dk)
          for (int dj = -1; dj <= 1 && !boundary; ++dj)
            for (int di = -1; di <= 1 && !boundary; ++di) {
              const int a = i + di, b = j + dj, c = k + dk;
              if (a < 0 || b < 0 || c < 0 || a >= g.dims[0] || b >= g.dims[1] || c >= g.dims[2])
                continue;
              boundary = mask.values[g.index(a, b, c)] != v;
            }
        if (boundary) band.nodes.push_back(g.index(i, j, k));
      }
  return band;
}

Vec3 node_of(const Grid& g, std::uint64_t n) {
  const auto nx = static_cast<std::uint64_t>(g.dims[0]), ny = static_cast<std::uint64_t>(g.dims[1]);
  return g.node(static_cast<int>(n % nx), static_cast<int>(n / nx % ny),
                static_cast<int>(n / (nx * ny)));
}

struct SphereCase {
  Vec3 c{0.13, -0.21, 0.37};
  double r = 4.0;
  TriangleSoup soup = test::make_sphere(c, r, 4);
  MeshIndex index = build_index(soup);
  Grid grid = test::grid_around(bounding_box(soup), 0.1, 0.3);
  Occupancy occ = classify_grid(index, grid);
  Band band = band_of(occ.inside);
};

TEST(Distance, SphereBandMatchesTheSphereWithinTessellationError) {
  const SphereCase s;
  ASSERT_GT(s.band.nodes.size(), 1000u);
  const std::vector<float> d = band_distances(s.index, s.occ.inside, s.band);
  ASSERT_EQ(d.size(), s.band.nodes.size());
  for (std::size_t q = 0; q < d.size(); ++q) {
    const Vec3 p = node_of(s.grid, s.band.nodes[q]);
    const double exact = std::fabs(norm(p - s.c) - s.r);
    EXPECT_NEAR(std::fabs(d[q]), exact, 0.01) << p.x << " " << p.y << " " << p.z;
    EXPECT_LE(std::fabs(d[q]), 0.1 * std::sqrt(3.0) + 1e-6);  // band: within a voxel diagonal
    EXPECT_EQ(std::signbit(d[q]), s.occ.inside.values[s.band.nodes[q]] == 1);
  }
}

TEST(Distance, BandEqualsTheFullFieldAtBandNodes) {
  const SphereCase s;
  const std::vector<float> band = band_distances(s.index, s.occ.inside, s.band);
  const Field full = signed_distance_field(s.index, s.occ.inside);
  ASSERT_EQ(full.values.size(), s.grid.node_count());
  EXPECT_EQ(full.grid, s.grid);
  for (std::size_t q = 0; q < band.size(); ++q) EXPECT_EQ(band[q], full.values[s.band.nodes[q]]);
  // Everywhere: |d| is the distance to the polyhedron, the sign is the mask's.
  for (std::size_t n = 0; n < full.values.size(); n += 7) {
    const Vec3 p = node_of(s.grid, n);
    EXPECT_NEAR(std::fabs(full.values[n]), std::fabs(norm(p - s.c) - s.r), 0.01);
    EXPECT_EQ(std::signbit(full.values[n]), s.occ.inside.values[n] == 1);
  }
}

TEST(Distance, HintsDoNotChangeTheResult) {
  const SphereCase s;
  const Field with = signed_distance_field(s.index, s.occ.inside, {.reuse_hints = true});
  const Field without = signed_distance_field(s.index, s.occ.inside, {.reuse_hints = false});
  EXPECT_EQ(with.values, without.values);
}

TEST(Distance, SameResultOnOneAndTwoThreadsAndWithTwoTrees) {
  // 81,920 triangles: the index holds two trees.
  const TriangleSoup soup = test::make_sphere({0.1, 0.2, 0.3}, 3.0, 6);
  const MeshIndex index = build_index(soup);
  const Grid grid = test::grid_around(bounding_box(soup), 0.05, 0.1);
  const Occupancy occ = classify_grid(index, grid);
  const Band band = band_of(occ.inside);
  std::vector<float> one, two;
  {
    tbb::global_control c(tbb::global_control::max_allowed_parallelism, 1);
    one = band_distances(index, occ.inside, band);
  }
  {
    tbb::global_control c(tbb::global_control::max_allowed_parallelism, 2);
    two = band_distances(index, occ.inside, band);
  }
  EXPECT_EQ(one, two);
  // And the same as a single tree over a shuffled soup (different tree, same minimum).
  TriangleSoup reversed = soup;
  std::reverse(reversed.triangles.begin(), reversed.triangles.end());
  EXPECT_EQ(band_distances(build_index(reversed), occ.inside, band), one);
}

TEST(Distance, PointOnAFaceIsZero) {
  const TriangleSoup cube = test::make_box({0, 0, 0}, {1, 1, 1});
  const MeshIndex index = build_index(cube);
  Grid grid;
  grid.origin = {-0.5, -0.5, -0.5};
  grid.spacing = 0.25;
  grid.dims = {9, 9, 9};
  const Occupancy occ = classify_grid(index, grid);
  const Field f = signed_distance_field(index, occ.inside);
  EXPECT_EQ(f.values[grid.index(2, 4, 4)], 0.0f);   // (0, 0.5, 0.5) on the -x face
  EXPECT_EQ(f.values[grid.index(4, 4, 4)], -0.5f);  // centre
  EXPECT_EQ(f.values[grid.index(0, 4, 4)], 0.5f);   // (-0.5, 0.5, 0.5)
  EXPECT_FLOAT_EQ(f.values[grid.index(0, 0, 0)], static_cast<float>(std::sqrt(0.75)));
}

TEST(Distance, MismatchedGridsAreAnInputError) {
  const SphereCase s;
  Band other = s.band;
  other.grid.spacing *= 2;
  EXPECT_THROW(band_distances(s.index, s.occ.inside, other), InputError);
}

TEST(Distance, ClosestPointsOnABoxAreTheNearestFacePoints) {
  // Outside the unit box, the nearest point is the point clamped onto it; inside, the point
  // moved onto its nearest face. Every third point lies exactly on an edge's extension, where
  // two or three triangles tie.
  const MeshIndex index = build_index(test::make_box({0, 0, 0}, {1, 1, 1}));
  std::vector<Vec3> points;
  for (int i = 0; i < 2000; ++i) {
    const double a = std::fmod(i * 0.7548776662, 1.0), b = std::fmod(i * 0.5698402910, 1.0),
                 c = std::fmod(i * 0.4142135624, 1.0);
    points.push_back({3 * a - 1, 3 * b - 1, i % 3 == 0 ? 2.0 : 3 * c - 1});
  }
  const std::vector<Vec3> q = closest_points(index, points);
  ASSERT_EQ(q.size(), points.size());
  for (std::size_t i = 0; i < points.size(); ++i) {
    const Vec3 p = points[i];
    Vec3 expected{std::clamp(p.x, 0.0, 1.0), std::clamp(p.y, 0.0, 1.0), std::clamp(p.z, 0.0, 1.0)};
    if (expected == p) {  // inside: the nearest face
      const double gaps[6] = {p.x, 1 - p.x, p.y, 1 - p.y, p.z, 1 - p.z};
      const int f = static_cast<int>(std::min_element(gaps, gaps + 6) - gaps);
      double* axis[3] = {&expected.x, &expected.y, &expected.z};
      *axis[f / 2] = f % 2;
    }
    EXPECT_NEAR(norm(q[i] - expected), 0, 1e-12) << "point " << i;
  }
  EXPECT_THROW(closest_points(index, {{0, 0, NAN}}), InputError);
}

}  // namespace
}  // namespace tpmsfill
