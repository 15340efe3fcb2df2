// Stage "voxel": dilation, boundary and band against brute-force definitions.
#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdlib>
#include <random>
#include <set>
#include <tpmsfill/error.hpp>
#include <tpmsfill/sampling/voxel.hpp>

using namespace tpmsfill;

namespace {

Mask empty_mask(int nx, int ny, int nz) {
  Mask m;
  m.grid.dims = {nx, ny, nz};
  m.values.assign(m.grid.node_count(), 0);
  return m;
}

// A random blobby mask: union of balls, so it has concave pockets and thin gaps.
Mask random_blobs(unsigned seed, int n) {
  Mask m = empty_mask(n, n + 1, n + 2);
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> pos(2, n - 2), rad(0.8, n / 4.0);
  for (int b = 0; b < 6; ++b) {
    const double cx = pos(rng), cy = pos(rng), cz = pos(rng), r = rad(rng);
    for (int k = 0; k < m.grid.dims[2]; ++k)
      for (int j = 0; j < m.grid.dims[1]; ++j)
        for (int i = 0; i < m.grid.dims[0]; ++i)
          if ((i - cx) * (i - cx) + (j - cy) * (j - cy) + (k - cz) * (k - cz) < r * r)
            m.values[m.grid.index(i, j, k)] = 1;
  }
  return m;
}

// Brute force: is there a node with value `want` within Chebyshev distance r of (i, j, k)?
// Nodes beyond the grid have value 0.
bool near_value(const Mask& m, int i, int j, int k, int r, std::uint8_t want) {
  for (int dk = -r; dk <= r; ++dk)
    for (int dj = -r; dj <= r; ++dj)
      for (int di = -r; di <= r; ++di) {
        const int a = i + di, b = j + dj, c = k + dk;
        const bool in = a >= 0 && b >= 0 && c >= 0 && a < m.grid.dims[0] && b < m.grid.dims[1] &&
                        c < m.grid.dims[2];
        const std::uint8_t v = in ? m.values[m.grid.index(a, b, c)] : 0;
        if (v == want) return true;
      }
  return false;
}

}  // namespace

TEST(Voxel, DilationIsTheChebyshevBall) {
  Mask m = empty_mask(11, 11, 11);
  m.values[m.grid.index(6, 6, 4)] = 1;
  m.values[m.grid.index(0, 0, 10)] = 1;  // clipped at the grid's corner
  for (int r : {1, 2}) {
    const Mask d = dilate(m, r);
    const long count = std::count(d.values.begin(), d.values.end(), 1);
    EXPECT_EQ(count, (2 * r + 1) * (2 * r + 1) * (2 * r + 1) + (r + 1) * (r + 1) * (r + 1));
  }
  EXPECT_EQ(dilate(m, 0).values, m.values);
}

TEST(Voxel, DilationMatchesBruteForce) {
  for (unsigned seed = 1; seed <= 4; ++seed) {
    const Mask m = random_blobs(seed, 14);
    for (int r : {1, 2, 3}) {
      const Mask d = dilate(m, r);
      for (int k = 0; k < m.grid.dims[2]; ++k)
        for (int j = 0; j < m.grid.dims[1]; ++j)
          for (int i = 0; i < m.grid.dims[0]; ++i)
            ASSERT_EQ(d.values[m.grid.index(i, j, k)] != 0, near_value(m, i, j, k, r, 1))
                << seed << " r=" << r << " at " << i << "," << j << "," << k;
    }
  }
}

// The paper's bw(·) (eq. 6), brute force: set nodes with an unset 26-neighbour, nodes beyond
// the grid counting as unset.
bool paper_boundary(const Mask& m, int i, int j, int k) {
  return m.values[m.grid.index(i, j, k)] && near_value(m, i, j, k, 1, 0);
}

TEST(Voxel, BandHoldsThePapersBoundaryVoxels) {
  // B = bw(I) ∪ bw(dil(I)) (eq. 7) is part of the band of half-width 1.
  for (unsigned seed = 1; seed <= 3; ++seed) {
    const Mask m = random_blobs(seed, 14);
    const Mask dilated = dilate(m, 1);
    const Band band = band_voxels(m);
    const std::set<std::uint64_t> in_band(band.nodes.begin(), band.nodes.end());
    std::size_t paper = 0;
    for (int k = 0; k < m.grid.dims[2]; ++k)
      for (int j = 0; j < m.grid.dims[1]; ++j)
        for (int i = 0; i < m.grid.dims[0]; ++i) {
          const bool on_face = i == 0 || j == 0 || k == 0 || i + 1 == m.grid.dims[0] ||
                               j + 1 == m.grid.dims[1] || k + 1 == m.grid.dims[2];
          // On the grid's faces bw depends on what lies beyond the grid; make_grid's padding
          // keeps every node there outside.
          if (on_face) continue;
          if (!paper_boundary(m, i, j, k) && !paper_boundary(dilated, i, j, k)) continue;
          ++paper;
          ASSERT_EQ(in_band.count(m.grid.index(i, j, k)), 1u) << seed << " " << i << j << k;
        }
    EXPECT_GT(paper, 100u);
  }
}

TEST(Voxel, BandIsNodesNearTheOtherSide) {
  for (unsigned seed = 1; seed <= 4; ++seed) {
    const Mask m = random_blobs(seed, 16);
    for (int w : {1, 2}) {
      const Band band = band_voxels(m, {.width = w});
      ASSERT_TRUE(std::is_sorted(band.nodes.begin(), band.nodes.end()));
      std::set<std::uint64_t> in_band(band.nodes.begin(), band.nodes.end());
      ASSERT_EQ(in_band.size(), band.nodes.size());
      for (int k = 0; k < m.grid.dims[2]; ++k)
        for (int j = 0; j < m.grid.dims[1]; ++j)
          for (int i = 0; i < m.grid.dims[0]; ++i) {
            const std::size_t n = m.grid.index(i, j, k);
            const bool expected = near_value(m, i, j, k, w, m.values[n] ? 0 : 1);
            ASSERT_EQ(in_band.count(n) == 1, expected) << seed << " w=" << w;
          }
    }
  }
}

TEST(Voxel, EveryMixedCellHasAllCornersInTheBand) {
  const Mask m = random_blobs(7, 18);
  const Band band = band_voxels(m);
  std::set<std::uint64_t> in_band(band.nodes.begin(), band.nodes.end());
  const Grid& g = m.grid;
  int mixed = 0;
  for (int k = 0; k + 1 < g.dims[2]; ++k)
    for (int j = 0; j + 1 < g.dims[1]; ++j)
      for (int i = 0; i + 1 < g.dims[0]; ++i) {
        int inside = 0;
        for (int c = 0; c < 8; ++c)
          inside += m.values[g.index(i + (c & 1), j + (c >> 1 & 1), k + (c >> 2 & 1))];
        if (inside == 0 || inside == 8) continue;
        ++mixed;
        for (int c = 0; c < 8; ++c)
          ASSERT_TRUE(in_band.count(g.index(i + (c & 1), j + (c >> 1 & 1), k + (c >> 2 & 1))));
      }
  EXPECT_GT(mixed, 100);
}

TEST(Voxel, RegionsAre26Connected) {
  Mask m = empty_mask(8, 8, 8);
  auto set = [&](int i, int j, int k) { m.values[m.grid.index(i, j, k)] = 1; };
  set(1, 1, 1);
  set(2, 2, 2);  // touches (1,1,1) at a corner only: same region
  set(2, 3, 2);
  set(6, 6, 6);  // alone
  set(5, 1, 6);
  set(6, 1, 6);  // a run of two
  const Regions r = label_regions(m);
  EXPECT_EQ(r.count, 3u);
  EXPECT_EQ(r.region_at(1, 1, 1), 0u);  // numbered by first node in index order
  EXPECT_EQ(r.region_at(2, 2, 2), 0u);
  EXPECT_EQ(r.region_at(2, 3, 2), 0u);
  EXPECT_EQ(r.region_at(5, 1, 6), 1u);
  EXPECT_EQ(r.region_at(6, 1, 6), 1u);
  EXPECT_EQ(r.region_at(6, 6, 6), 2u);
  EXPECT_EQ(r.region_at(0, 0, 0), 0xffffffffu);
  EXPECT_EQ(r.region_at(7, 1, 6), 0xffffffffu);
}

TEST(Voxel, RegionsMatchFloodFill) {
  for (unsigned seed = 10; seed < 16; ++seed) {
    Mask m = empty_mask(12, 11, 10);
    std::mt19937 rng(seed);
    for (auto& v : m.values) v = rng() % 100 < 12;  // sparse noise: many small regions
    const Regions r = label_regions(m);
    // Flood fill with 26-neighbours; the region ids must induce the same partition.
    const Grid& g = m.grid;
    std::vector<int> label(m.values.size(), -1);
    int count = 0;
    for (int k = 0; k < g.dims[2]; ++k)
      for (int j = 0; j < g.dims[1]; ++j)
        for (int i = 0; i < g.dims[0]; ++i) {
          if (!m.values[g.index(i, j, k)] || label[g.index(i, j, k)] >= 0) continue;
          std::vector<std::array<int, 3>> stack{{i, j, k}};
          label[g.index(i, j, k)] = count;
          while (!stack.empty()) {
            auto [a, b, c] = stack.back();
            stack.pop_back();
            for (int dk = -1; dk <= 1; ++dk)
              for (int dj = -1; dj <= 1; ++dj)
                for (int di = -1; di <= 1; ++di) {
                  const int x = a + di, y = b + dj, z = c + dk;
                  if (x < 0 || y < 0 || z < 0 || x >= g.dims[0] || y >= g.dims[1] || z >= g.dims[2])
                    continue;
                  const std::size_t n = g.index(x, y, z);
                  if (m.values[n] && label[n] < 0) {
                    label[n] = count;
                    stack.push_back({x, y, z});
                  }
                }
          }
          ++count;
        }
    ASSERT_EQ(r.count, static_cast<std::uint32_t>(count));
    for (int k = 0; k < g.dims[2]; ++k)
      for (int j = 0; j < g.dims[1]; ++j)
        for (int i = 0; i < g.dims[0]; ++i) {
          const std::size_t n = g.index(i, j, k);
          // Both number regions in order of their first node, so the labels are equal.
          ASSERT_EQ(r.region_at(i, j, k),
                    m.values[n] ? static_cast<std::uint32_t>(label[n]) : 0xffffffffu);
        }
  }
}

// --- distance transform ---------------------------------------------------------------------

namespace {

// Brute force: squared distance (voxels²) from each node to the nearest unset node, the nodes
// of a one-node ring beyond the grid counting as unset unless beyond_grid_set; the result as
// distance_transform rounds it (+infinity: none).
std::vector<float> brute_distance(const Mask& m, bool beyond_grid_set) {
  const Grid& g = m.grid;
  std::vector<std::array<int, 3>> unset;
  const int pad = beyond_grid_set ? 0 : 1;
  for (int k = -pad; k < g.dims[2] + pad; ++k)
    for (int j = -pad; j < g.dims[1] + pad; ++j)
      for (int i = -pad; i < g.dims[0] + pad; ++i) {
        const bool in =
            i >= 0 && j >= 0 && k >= 0 && i < g.dims[0] && j < g.dims[1] && k < g.dims[2];
        if (!in || !m.values[g.index(i, j, k)]) unset.push_back({i, j, k});
      }
  std::vector<float> out(m.values.size());
  for (int k = 0; k < g.dims[2]; ++k)
    for (int j = 0; j < g.dims[1]; ++j)
      for (int i = 0; i < g.dims[0]; ++i) {
        std::uint64_t best = UINT64_MAX;
        for (const auto& u : unset) {
          const std::int64_t di = u[0] - i, dj = u[1] - j, dk = u[2] - k;
          best = std::min<std::uint64_t>(best, di * di + dj * dj + dk * dk);
        }
        out[g.index(i, j, k)] =
            best == UINT64_MAX
                ? std::numeric_limits<float>::infinity()
                : static_cast<float>(std::sqrt(static_cast<double>(best)) * g.spacing);
      }
  return out;
}

// Mostly set, with a few unset nodes: distances of several voxels in every direction.
Mask sparse_holes(unsigned seed, std::array<int, 3> dims, int per_mille) {
  Mask m = empty_mask(dims[0], dims[1], dims[2]);
  m.grid.spacing = 0.37;
  std::mt19937 rng(seed);
  for (auto& v : m.values) v = static_cast<int>(rng() % 1000) >= per_mille;
  return m;
}

}  // namespace

TEST(Voxel, DistanceTransformMatchesBruteForce) {
  std::vector<Mask> masks;
  for (unsigned seed = 1; seed <= 3; ++seed) {
    Mask blobs = random_blobs(seed, 13);
    blobs.grid.spacing = 0.25;
    masks.push_back(blobs);
    masks.push_back(sparse_holes(seed, {17, 12, 9}, 4));
    masks.push_back(sparse_holes(seed + 10, {9, 14, 11}, 60));
  }
  // Distances over 90 voxels, where the envelope takes over from the window (see
  // distance_transform.hpp), in every pass.
  masks.push_back(sparse_holes(8, {230, 3, 2}, 2));
  masks.push_back(sparse_holes(9, {2, 190, 3}, 4));
  masks.push_back(sparse_holes(10, {3, 2, 200}, 3));
  masks.push_back(sparse_holes(4, {1, 23, 7}, 20));   // one node wide
  masks.push_back(sparse_holes(5, {31, 1, 1}, 30));   // a single row
  masks.push_back(sparse_holes(6, {12, 10, 8}, 0));   // no unset node
  masks.push_back(sparse_holes(7, {6, 7, 8}, 1000));  // all unset
  for (std::size_t c = 0; c < masks.size(); ++c)
    for (bool beyond : {false, true}) {
      const Field d = distance_transform(masks[c], beyond);
      ASSERT_EQ(d.grid, masks[c].grid);
      const std::vector<float> expected = brute_distance(masks[c], beyond);
      for (std::size_t n = 0; n < expected.size(); ++n)
        ASSERT_EQ(d.values[n], expected[n])
            << "mask " << c << " beyond " << beyond << " node " << n;
    }
}

TEST(Voxel, DistanceTransformOfAFullMask) {
  Mask m = empty_mask(5, 6, 7);
  std::fill(m.values.begin(), m.values.end(), 1);
  const Field inside = distance_transform(m, false);  // bounded by the grid's faces
  EXPECT_EQ(inside.values[m.grid.index(0, 0, 0)], 1.0f);
  EXPECT_EQ(inside.values[m.grid.index(2, 3, 3)], 3.0f);  // 3 to x = -1 and x = 5, z = -1, z = 7
  const Field none = distance_transform(m, true);
  EXPECT_TRUE(
      std::all_of(none.values.begin(), none.values.end(), [](float v) { return std::isinf(v); }));
  m.values[m.grid.index(4, 5, 6)] = 0;
  const Field corner = distance_transform(m, true);
  EXPECT_FLOAT_EQ(corner.values[0], static_cast<float>(std::sqrt(16.0 + 25.0 + 36.0)));
}

TEST(Voxel, DistanceTransformIsIndependentOfThreads) {
  Mask m = random_blobs(3, 70);
  m.grid.spacing = 0.1;
  std::vector<float> one, many;
  {
    tbb::global_control c(tbb::global_control::max_allowed_parallelism, 1);
    one = distance_transform(m, true).values;
  }
  {
    tbb::global_control c(tbb::global_control::max_allowed_parallelism, 4);
    many = distance_transform(m, true).values;
  }
  EXPECT_EQ(one, many);
  EXPECT_GT(*std::max_element(one.begin(), one.end()), 1.0f);
}

TEST(Voxel, DistanceTransformRejectsAMismatchedMask) {
  Mask m = empty_mask(4, 4, 4);
  m.values.pop_back();
  EXPECT_THROW(distance_transform(m), InputError);
}
