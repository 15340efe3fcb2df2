// detail::ToleranceCover, the proof behind decimation's Hausdorff bound, and the point-triangle
// distance under it: what it proves is true (checked on a dense grid of the piece), what is
// false it refuses, and it proves the cases decimation meets (a fan of thin triangles, a seam
// between coplanar triangles, a crease).
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "mesh/internal/point_triangle.hpp"
#include "mesh/internal/tolerance_cover.hpp"

using namespace tpmsfill;
using tpmsfill::detail::Corners;
using tpmsfill::detail::squared_distance_to_triangle;

namespace {

// Largest distance from the barycentric grid of order 40 on `piece` to the union of `set`.
double max_distance(const Corners& piece, const std::vector<Corners>& set) {
  constexpr int n = 40;
  double worst = 0;
  for (int i = 0; i <= n; ++i)
    for (int j = 0; i + j <= n; ++j) {
      const Vec3 q =
          (1.0 / n) * (static_cast<double>(i) * piece[0] + static_cast<double>(j) * piece[1] +
                       static_cast<double>(n - i - j) * piece[2]);
      double best = INFINITY;
      for (const Corners& t : set)
        best = std::min(best, squared_distance_to_triangle(q, t[0], t[1], t[2]));
      worst = std::max(worst, std::sqrt(best));
    }
  return worst;
}

std::vector<std::uint32_t> all(const std::vector<Corners>& set) {
  std::vector<std::uint32_t> c;
  for (std::uint32_t i = 0; i < set.size(); ++i) c.push_back(i);
  return c;
}

// A fan of `k` triangles around `apex` (z = `lift`) over the regular polygon of radius r.
std::vector<Corners> fan(Vec3 apex, double r, int k) {
  std::vector<Corners> set;
  for (int i = 0; i < k; ++i) {
    const double a = 2 * M_PI * i / k, b = 2 * M_PI * (i + 1) / k;
    set.push_back({apex, Vec3{r * std::cos(a), r * std::sin(a), 0},
                   Vec3{r * std::cos(b), r * std::sin(b), 0}});
  }
  return set;
}

}  // namespace

TEST(PointTriangle, DistanceToEachFeature) {
  const Vec3 a{0, 0, 0}, b{2, 0, 0}, c{0, 2, 0};
  EXPECT_DOUBLE_EQ(squared_distance_to_triangle({0.5, 0.5, 3}, a, b, c), 9.0);  // face
  EXPECT_DOUBLE_EQ(squared_distance_to_triangle({-1, -1, 0}, a, b, c), 2.0);    // corner a
  EXPECT_DOUBLE_EQ(squared_distance_to_triangle({3, 0, 0}, a, b, c), 1.0);      // corner b
  EXPECT_DOUBLE_EQ(squared_distance_to_triangle({1, -2, 0}, a, b, c), 4.0);     // edge ab
  EXPECT_DOUBLE_EQ(squared_distance_to_triangle({2, 2, 0}, a, b, c), 2.0);      // edge bc
  EXPECT_DOUBLE_EQ(squared_distance_to_triangle({1, 1, 1}, a, a, c), 2.0);      // degenerate
}

TEST(ToleranceCover, ProvesAPieceOverAFanOfThinTriangles) {
  // 24 thin triangles around an apex inside the piece: no one triangle holds the piece.
  const std::vector<Corners> set = fan({0.1, 0.05, 0}, 3.0, 24);
  const Corners piece{Vec3{-1, -1, 0.004}, Vec3{1.2, -0.8, 0.004}, Vec3{0, 1.1, 0.004}};
  detail::ToleranceCover cover(0.005);
  std::vector<std::uint32_t> uses;
  ASSERT_TRUE(cover.within(piece, set, all(set), uses));
  EXPECT_GT(uses.size(), 1u);
  EXPECT_LE(max_distance(piece, set), 0.005);
}

TEST(ToleranceCover, RefusesAPieceLiftedBeyondTheTolerance) {
  const std::vector<Corners> set = fan({0, 0, 0}, 3.0, 8);
  detail::ToleranceCover cover(0.01);
  std::vector<std::uint32_t> uses;
  const Corners lifted{Vec3{-1, -1, 0.011}, Vec3{1, -1, 0.011}, Vec3{0, 1, 0.011}};
  EXPECT_FALSE(cover.within(lifted, set, all(set), uses));
  // Corners on the surface, the middle bulging out by 0.02: false, although every corner is
  // within the tolerance (a sampled check at the corners would pass it).
  const std::vector<Corners> roof = {{Vec3{-1, -1, 0}, Vec3{1, -1, 0}, Vec3{0, 0, 0.04}},
                                     {Vec3{1, -1, 0}, Vec3{0, 1, 0}, Vec3{0, 0, 0.04}},
                                     {Vec3{0, 1, 0}, Vec3{-1, -1, 0}, Vec3{0, 0, 0.04}}};
  const Corners flat{Vec3{-1, -1, 0}, Vec3{1, -1, 0}, Vec3{0, 1, 0}};
  EXPECT_GT(max_distance(flat, roof), 0.01);
  EXPECT_FALSE(cover.within(flat, roof, all(roof), uses));
}

TEST(ToleranceCover, RefusesAPieceSpanningAGap) {
  // Two thin triangles along the x and y axes (an L): the piece's corners lie on them, its
  // far edge crosses the empty corner between them, 0.4 away.
  const std::vector<Corners> set = {{Vec3{0, 0, 0}, Vec3{1, 0, 0}, Vec3{0, 0.05, 0}},
                                    {Vec3{0, 0, 0}, Vec3{0.05, 0, 0}, Vec3{0, 1, 0}}};
  const Corners piece{Vec3{0, 0, 0}, Vec3{0.9, 0, 0}, Vec3{0, 0.9, 0}};
  detail::ToleranceCover cover(0.01);
  std::vector<std::uint32_t> uses;
  EXPECT_FALSE(cover.within(piece, set, all(set), uses));
  EXPECT_GT(max_distance(piece, set), 0.3);
}

TEST(ToleranceCover, ProvesAPieceAcrossACrease) {
  // Two faces of a box meeting at a right angle along x = 0 ... 1, y = 0, z = 0, and a piece
  // cutting the corner by less than the tolerance.
  const std::vector<Corners> set = {{Vec3{0, 0, 0}, Vec3{1, 0, 0}, Vec3{1, 1, 0}},
                                    {Vec3{0, 0, 0}, Vec3{1, 1, 0}, Vec3{0, 1, 0}},
                                    {Vec3{1, 0, 0}, Vec3{0, 0, 0}, Vec3{0, 0, -1}},
                                    {Vec3{1, 0, 0}, Vec3{0, 0, -1}, Vec3{1, 0, -1}}};
  const Corners piece{Vec3{0.2, 0.006, 0}, Vec3{0.8, 0.006, 0}, Vec3{0.5, 0, -0.006}};
  detail::ToleranceCover cover(0.005);
  std::vector<std::uint32_t> uses;
  EXPECT_TRUE(cover.within(piece, set, all(set), uses));
  EXPECT_LE(max_distance(piece, set), 0.005);
}
