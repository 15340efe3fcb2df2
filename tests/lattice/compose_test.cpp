// Stage "compose": the band field (eq. 10) against the full field, and no sample on zero.
#include <gtest/gtest.h>

#include <atomic>
#include <cmath>
#include <tpmsfill/error.hpp>
#include <tpmsfill/lattice/compose.hpp>
#include <tpmsfill/lattice/tpms.hpp>
#include <tpmsfill/sampling/voxel.hpp>

using namespace tpmsfill;

namespace {

// A ball's exact signed distance on a grid, its occupancy and band.
struct Ball {
  Grid grid;
  Field distance;
  Mask inside;
  Band band;
  std::vector<float> band_distance;
};

Ball make_ball(double radius, double spacing) {
  Ball b;
  const int n = static_cast<int>(std::ceil(2 * radius / spacing)) + 7;
  b.grid.origin = {-(n / 2) * spacing, -(n / 2) * spacing, -(n / 2) * spacing};
  b.grid.spacing = spacing;
  b.grid.dims = {n, n, n};
  b.distance = {b.grid, std::vector<float>(b.grid.node_count())};
  b.inside = {b.grid, std::vector<std::uint8_t>(b.grid.node_count())};
  for (int k = 0; k < n; ++k)
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i) {
        const std::size_t id = b.grid.index(i, j, k);
        b.distance.values[id] = static_cast<float>(norm(b.grid.node(i, j, k)) - radius);
        b.inside.values[id] = b.distance.values[id] < 0;
      }
  b.band = band_voxels(b.inside);
  for (std::uint64_t id : b.band.nodes) b.band_distance.push_back(b.distance.values[id]);
  return b;
}

}  // namespace

TEST(Compose, BandFieldHasTheSignsOfTheFullField) {
  const Ball b = make_ball(5.0, 0.2);
  for (TpmsType type : {TpmsType::Gyroid, TpmsType::Primitive, TpmsType::Diamond}) {
    const FieldSource lattice = tpms_source({.type = type, .cell = {2, 2, 2}});
    const Field band = compose_field(b.inside, b.band, b.band_distance, lattice);
    const Field full = compose_field(b.distance, lattice);
    std::size_t solid = 0;
    for (std::size_t n = 0; n < band.values.size(); ++n) {
      ASSERT_EQ(band.values[n] < 0, full.values[n] < 0) << n;
      ASSERT_GE(band.values[n], b.distance.values[n] < 0 ? -1e30f : 0.0f);
      solid += band.values[n] < 0;
    }
    // About half the ball's nodes are lattice.
    const double ball_nodes = 4.0 / 3.0 * M_PI * 125 / (0.2 * 0.2 * 0.2);
    EXPECT_NEAR(solid / ball_nodes, 0.5, 0.05) << tpms_type_name(type);
  }
}

TEST(Compose, SkinIsSolidWithinItsThicknessOfTheSurface) {
  // A ball of radius 5 with a lattice that is void everywhere (level above its clamp): only
  // the skin is solid, and exactly where the distance is within (−skin, 0).
  const double skin = 0.6;
  const Ball b = make_ball(5.0, 0.2);
  const Band wide = band_voxels(b.inside, {skin_band_width(skin, 0.2)});
  std::vector<float> d;
  for (std::uint64_t id : wide.nodes) d.push_back(b.distance.values[id]);
  const FieldSource empty = tpms_source({.level = 10});
  const Field phi = compose_field(b.inside, wide, d, empty, {.skin = skin});
  const Field full = compose_field(b.distance, empty, {.skin = skin});
  for (std::size_t n = 0; n < phi.values.size(); ++n) {
    const float dist = b.distance.values[n];
    ASSERT_EQ(phi.values[n] < 0, dist < 0 && dist > -skin) << n;
    ASSERT_EQ(full.values[n] < 0, phi.values[n] < 0) << n;
  }
}

TEST(Compose, NoSampleEqualsZero) {
  // A slab whose faces lie on grid planes: its distance is exactly 0 on two planes of nodes,
  // and the gyroid's zero set passes through nodes at the lattice's symmetry points.
  Grid g;
  g.spacing = 0.25;
  g.dims = {24, 24, 24};
  g.origin = {-3, -3, -3};
  Field slab{g, std::vector<float>(g.node_count())};
  int zeros = 0;
  for (int k = 0; k < 24; ++k)
    for (int j = 0; j < 24; ++j)
      for (int i = 0; i < 24; ++i) {
        const double z = g.coordinate(2, k);
        slab.values[g.index(i, j, k)] = static_cast<float>(std::fabs(z) - 1.0);
        zeros += std::fabs(z) == 1.0;
      }
  ASSERT_GT(zeros, 0);
  const Field phi = compose_field(slab, tpms_source({.level = -5}));  // the model decides
  for (float v : phi.values) ASSERT_NE(v, 0.0f);
}

TEST(Compose, RejectsMismatchedInputs) {
  const Ball b = make_ball(2.0, 0.5);
  std::vector<float> short_distances(b.band_distance.begin(), b.band_distance.end() - 1);
  EXPECT_THROW(compose_field(b.inside, b.band, short_distances, tpms_source({})), InputError);
  EXPECT_THROW(compose_field(b.inside, b.band, b.band_distance, FieldSource{}), InputError);
}

TEST(Compose, AnySourceIsClippedTheSameWay) {
  // A caller's field through the seam: the half-space z < 0.3 clipped to a ball of radius 2
  // is the ball's cap below z = 0.3; the lattice is evaluated only where the model does not
  // decide (inside the ball), which the source counts.
  const Ball b = make_ball(2.0, 0.1);
  std::atomic<std::size_t> calls{0};
  const FieldSource half = function_source([&](Vec3 p) {
    ++calls;
    return static_cast<float>(p.z - 0.3);
  });
  const Field phi = compose_field(b.inside, b.band, b.band_distance, half);
  std::size_t inside = 0, band_outside = 0;
  for (std::size_t n = 0; n < phi.values.size(); ++n) {
    const Vec3 p = b.grid.node(static_cast<int>(n % b.grid.dims[0]),
                               static_cast<int>(n / b.grid.dims[0] % b.grid.dims[1]),
                               static_cast<int>(n / b.grid.dims[0] / b.grid.dims[1]));
    ASSERT_EQ(phi.values[n] < 0, norm(p) < 2.0 && p.z < 0.3 && b.inside.values[n]) << n;
    inside += b.inside.values[n];
  }
  for (std::uint64_t id : b.band.nodes) band_outside += !b.inside.values[id];
  EXPECT_EQ(calls.load(), inside + band_outside);
}
