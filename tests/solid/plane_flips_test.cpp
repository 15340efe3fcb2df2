// Edge flips that mend a plane triangulation's turned-over triangles (solid/internal/
// plane_flips.hpp): on jittered grids whose squares' fans were re-split on a diagonal that turns
// a triangle over, every triangle ends counter-clockwise, and the winding number of random points,
// the border edges and the points are what they were.
#include <gtest/gtest.h>

#include <algorithm>
#include <map>
#include <set>

#include "mesh/exact_orientation.hpp"
#include "solid/internal/plane_flips.hpp"
#include "test_util.hpp"

namespace tpmsfill {
namespace {

using Triangles = std::vector<std::array<std::uint32_t, 3>>;

int orientation(const std::vector<Vec3>& p, std::uint32_t a, std::uint32_t b, std::uint32_t c) {
  return detail::orientation_2({p[a].x, p[a].y}, {p[b].x, p[b].y}, {p[c].x, p[c].y});
}

// Triangles over q counter-clockwise minus clockwise.
int winding(const std::vector<Vec3>& p, const Triangles& triangles, Vec3 q) {
  std::vector<Vec3> at = p;
  at.push_back(q);
  const auto o = static_cast<std::uint32_t>(p.size());
  int w = 0;
  for (const auto& t : triangles) {
    const int s = orientation(at, t[0], t[1], t[2]);
    if (orientation(at, t[0], t[1], o) == s && orientation(at, t[1], t[2], o) == s &&
        orientation(at, t[2], t[0], o) == s)
      w += s;
  }
  return w;
}

std::set<std::pair<std::uint32_t, std::uint32_t>> border(const Triangles& triangles) {
  std::set<std::pair<std::uint32_t, std::uint32_t>> directed, out;
  for (const auto& t : triangles)
    for (int k = 0; k < 3; ++k) directed.insert({t[k], t[(k + 1) % 3]});
  for (const auto& [a, b] : directed)
    if (!directed.count({b, a})) out.insert({a, b});
  return out;
}

TEST(PlaneFlips, TurnedQuadsAreFlippedBackWithTheSameWindingAndBorder) {
  for (std::uint64_t seed = 1; seed <= 20; ++seed) {
    test::Random random{seed};
    const int n = 12;  // points per side of a jittered grid, ±0.2 of a step
    std::vector<Vec3> points;
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i)
        points.push_back(
            {i + 0.4 * (random.next() - 0.5), j + 0.4 * (random.next() - 0.5), seed * 1e-3});
    // Each square a fan of four around a point near its corner v + 1, past the diagonal
    // v – v + n + 1. In some squares the fan's first two triangles are replaced by those on
    // that diagonal: the second turns over (its centre lies on the corner's side), and
    // flipping back is the one mend.
    Triangles triangles;
    std::size_t replaced = 0;
    for (int j = 0; j + 1 < n; ++j)
      for (int i = 0; i + 1 < n; ++i) {
        const auto v = static_cast<std::uint32_t>(j * n + i), w = v + static_cast<std::uint32_t>(n);
        const Vec3 mid = 0.5 * (points[v] + points[w + 1]);
        const auto c = static_cast<std::uint32_t>(points.size());
        points.push_back(mid + (0.05 + 0.5 * random.next()) * (points[v + 1] - mid));
        if (random.next() < 0.3) {
          triangles.push_back({v, v + 1, w + 1});
          triangles.push_back({v, w + 1, c});
          ++replaced;
        } else {
          triangles.push_back({v, v + 1, c});
          triangles.push_back({v + 1, w + 1, c});
        }
        triangles.push_back({w + 1, w, c});
        triangles.push_back({w, v, c});
      }
    std::size_t turned = 0;
    for (const auto& t : triangles) turned += orientation(points, t[0], t[1], t[2]) < 0;
    ASSERT_GT(replaced, 0u);
    ASSERT_EQ(turned, replaced) << "seed " << seed;
    const Triangles before = triangles;
    EXPECT_EQ(detail::flip_turned_triangles(points, triangles), 0u) << "seed " << seed;
    for (const auto& t : triangles) EXPECT_GT(orientation(points, t[0], t[1], t[2]), 0);
    EXPECT_EQ(border(triangles), border(before));
    for (int k = 0; k < 200; ++k) {
      const Vec3 q{(n - 1) * random.next(), (n - 1) * random.next(), 0};
      EXPECT_EQ(winding(points, triangles, q), winding(points, before, q));
    }
  }
}

// A fold (a triangle turned over that no flip takes back without another turning) is left,
// and counted.
TEST(PlaneFlips, AFoldNoFlipMendsIsLeftAndCounted) {
  // A fan of four triangles around a centre outside its square: the centre's star folds.
  const std::vector<Vec3> points = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, {2, 0.5, 0}};
  Triangles triangles = {{0, 1, 4}, {1, 2, 4}, {2, 3, 4}, {3, 0, 4}};
  const Triangles before = triangles;
  const std::size_t left = detail::flip_turned_triangles(points, triangles);
  std::size_t turned = 0;
  for (const auto& t : triangles) turned += orientation(points, t[0], t[1], t[2]) < 0;
  EXPECT_EQ(left, turned);
  EXPECT_GT(left, 0u);
  EXPECT_EQ(border(triangles), border(before));
  for (const Vec3 q : {Vec3{0.5, 0.5, 0}, Vec3{1.5, 0.5, 0}, Vec3{0.9, 0.1, 0}})
    EXPECT_EQ(winding(points, triangles, q), winding(points, before, q));
}

}  // namespace
}  // namespace tpmsfill
