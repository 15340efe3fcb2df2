// Inside/outside of broken meshes: clean_soup() + hole caps + the winding rule, checked node
// by node against the solid each mesh was made from (classified by parity while intact).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <numbers>
#include <random>
#include <tpmsfill/mesh/clean.hpp>
#include <tpmsfill/sampling/classify.hpp>
#include <tpmsfill/sampling/spatial.hpp>

#include "sampling/internal/cap_winding.hpp"
#include "test_util.hpp"

namespace tpmsfill {
namespace {

/// Winding number of triangle abc at p: signed solid angle / 4π (van Oosterom and Strackee),
/// positive when p is behind the triangle. The brute-force reference.
double triangle_winding(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c) {
  const Vec3 u = a - p, v = b - p, w = c - p;
  const double lu = norm(u), lv = norm(v), lw = norm(w);
  if (lu == 0 || lv == 0 || lw == 0) return 0;
  const double det = dot(u, cross(v, w));
  const double div = lu * lv * lw + dot(u, v) * lw + dot(u, w) * lv + dot(v, w) * lu;
  return 2.0 * std::atan2(det, div) / (4.0 * std::numbers::pi);
}

Occupancy winding_inside(const TriangleSoup& soup, const Grid& grid,
                         CleanReport* report = nullptr) {
  const CleanResult c = clean_soup(soup);
  if (report) *report = c.report;
  return classify_grid(build_index(c.soup, {.hole_caps = &c.caps}), grid,
                       {.rule = InsideRule::Winding});
}

/// The solid: union of the parity insides of closed, intact meshes.
Mask solid(const std::vector<TriangleSoup>& closed, const Grid& grid) {
  Mask m{grid, std::vector<std::uint8_t>(grid.node_count(), 0)};
  for (const TriangleSoup& s : closed) {
    const Occupancy o = classify_grid(build_index(s), grid, {.rule = InsideRule::Parity});
    for (std::size_t i = 0; i < m.values.size(); ++i) m.values[i] |= o.inside.values[i];
  }
  return m;
}

/// Fraction of nodes where the two masks agree.
double agreement(const Mask& a, const Mask& b) {
  std::size_t same = 0;
  for (std::size_t i = 0; i < a.values.size(); ++i) same += a.values[i] == b.values[i];
  return static_cast<double>(same) / static_cast<double>(a.values.size());
}

std::size_t count_inside(const Mask& m) {
  std::size_t n = 0;
  for (std::uint8_t v : m.values) n += v;
  return n;
}

/// A sphere of radius r at c with three round holes facing +x, −y, +z, each about 25° across
/// (1.7 mm for r = 4: many voxels wide). What a person draws across a hole is close to the
/// flat disk on its rim (exactly that for a hemisphere's), so the agreement with the intact
/// ball is bounded by the thin spherical segments beyond those disks (0.03 % of the grid).
TriangleSoup sphere_with_holes(Vec3 c, double r) {
  return test::without_triangles(test::make_sphere(c, r, 4), [&](const Vec3& p) {
    const Vec3 d = (1.0 / norm(p - c)) * (p - c);
    return d.x > 0.975 || d.y < -0.975 || d.z > 0.975;
  });
}

TEST(Winding, SphereWithHoles) {
  const Vec3 c{0.1, -0.2, 0.05};
  const TriangleSoup intact = test::make_sphere(c, 4.0, 4);
  const TriangleSoup holes = sphere_with_holes(c, 4.0);
  const Grid grid = test::grid_around(bounding_box(intact), 0.1, 0.3);
  CleanReport report;
  const Occupancy occ = winding_inside(holes, grid, &report);
  EXPECT_EQ(report.holes, 3u);
  EXPECT_GE(agreement(occ.inside, solid({intact}, grid)), 0.999);
  EXPECT_GT(occ.cap_evaluations, 0u);
  // Parity fails on the same input: rows through a hole see one crossing.
  const Occupancy parity = classify_grid(build_index(holes), grid, {.rule = InsideRule::Parity});
  EXPECT_LT(agreement(parity.inside, solid({intact}, grid)), 0.99);
}

TEST(Winding, BoxWithFlippedFaces) {
  const TriangleSoup box = test::make_box({0, 0, 0}, {2, 1.5, 1});
  TriangleSoup broken = test::flip(test::flip(test::flip(box, 0), 5), 9);
  const Grid grid = test::grid_around(bounding_box(box), 0.1, 0.25);
  CleanReport report;
  const Occupancy occ = winding_inside(broken, grid, &report);
  EXPECT_EQ(report.flipped_triangles, 3u);
  EXPECT_EQ(occ.inside.values, solid({box}, grid).values);
}

TEST(Winding, InterpenetratingSpheres) {
  const TriangleSoup a = test::make_sphere({-1, 0, 0}, 2.0, 4);
  const TriangleSoup b = test::make_sphere({1.2, 0.3, 0.1}, 1.8, 4);
  const Grid grid = test::grid_around(bounding_box(test::concat(a, b)), 0.1, 0.3);
  const Occupancy occ = winding_inside(test::concat(a, b), grid);
  EXPECT_EQ(occ.inside.values, solid({a, b}, grid).values);
  EXPECT_GT(occ.overlap_rows, 0u);
}

TEST(Winding, UnweldedInsideOutBoxSoup) {
  const TriangleSoup box = test::make_box({-1, 0, 0}, {1, 1, 3});
  const Grid grid = test::grid_around(bounding_box(box), 0.1, 0.25);
  CleanReport report;
  const Occupancy occ = winding_inside(test::flip(test::unshare_points(box)), grid, &report);
  EXPECT_EQ(report.reversed_pieces, 1u);
  EXPECT_EQ(report.merged_points, 36u - 8u);
  EXPECT_EQ(occ.inside.values, solid({box}, grid).values);
}

TEST(Winding, TorusWithASlit) {
  const TriangleSoup torus = test::make_torus(3, 1, 48, 24);
  // A strip of faces across the tube removed: two border loops facing each other.
  const TriangleSoup slit = test::without_triangles(
      torus, [](const Vec3& p) { return p.x > 0 && std::fabs(std::atan2(p.y, p.x)) < 0.06; });
  ASSERT_LT(slit.triangles.size(), torus.triangles.size());
  const Grid grid = test::grid_around(bounding_box(torus), 0.1, 0.3);
  CleanReport report;
  const Occupancy occ = winding_inside(slit, grid, &report);
  EXPECT_EQ(report.holes, 2u);
  EXPECT_GE(agreement(occ.inside, solid({torus}, grid)), 0.999);
}

TEST(Winding, EverythingAtOnce) {
  // Holes, flipped faces, unwelded points, an overlapping shell, duplicate and degenerate
  // triangles and a separate small part, in one soup.
  const Vec3 c{0, 0, 0};
  const TriangleSoup sphere = test::make_sphere(c, 4.0, 4);
  const TriangleSoup blob = test::make_sphere({3.5, 1, 0.5}, 1.5, 3);
  const TriangleSoup speck = test::make_box({6, 6, 6}, {6.5, 6.4, 6.3});
  TriangleSoup broken = test::unshare_points(sphere_with_holes(c, 4.0));
  for (long t : {3L, 50L, 51L, 400L, 1999L}) broken = test::flip(broken, t);
  broken = test::concat(broken, test::flip(blob, 7));
  broken = test::concat(broken, test::flip(speck));  // inside out
  const Triangle dup = broken.triangles[10];
  broken.triangles.push_back(dup);
  broken.triangles.push_back({dup[0], dup[0], dup[1]});  // repeated corner
  const Grid grid = test::grid_around(bounding_box(broken), 0.1, 0.3);
  CleanReport report;
  const Occupancy occ = winding_inside(broken, grid, &report);
  EXPECT_EQ(report.holes, 3u);
  EXPECT_EQ(report.duplicate_triangles, 1u);
  EXPECT_EQ(report.repeated_corner_triangles, 1u);
  EXPECT_GE(report.flipped_triangles, 6u);
  EXPECT_EQ(report.reversed_pieces, 1u);  // the speck
  EXPECT_GE(agreement(occ.inside, solid({sphere, blob, speck}, grid)), 0.999);
}

TEST(Winding, OpenSheetEnclosesNothing) {
  // A flat, tilted sheet (a folded one would partly enclose the space on its concave side),
  // its plane through no grid node (on the sheet itself w is ½).
  TriangleSoup sheet;
  auto z = [](double x, double y) { return 0.013 + 0.1234567 * x + 0.0537 * y; };
  // Corners off the grid's nodes (on its rim, w takes every value between 0 and 1).
  const double lo = 0.0137, hi = 2.0071;
  sheet.points = {
      {lo, lo, z(lo, lo)}, {hi, lo, z(hi, lo)}, {hi, hi, z(hi, hi)}, {lo, hi, z(lo, hi)}};
  sheet.triangles = {{0, 1, 2}, {0, 2, 3}};
  const Grid grid = test::grid_around(bounding_box(sheet), 0.1, 0.5);
  EXPECT_EQ(count_inside(winding_inside(sheet, grid).inside), 0u);
}

TEST(Winding, HalfOpenBowlIsClosedAcrossItsRim) {
  // A hemisphere (z ≤ 0) is a bowl; the winding number fills it up to the rim's plane.
  const TriangleSoup bowl = test::without_triangles(test::make_sphere({0, 0, 0}, 3.0, 5),
                                                    [](const Vec3& p) { return p.z > 0; });
  const Grid grid = test::grid_around(bounding_box(bowl), 0.1, 0.3);
  const Occupancy occ = winding_inside(bowl, grid);
  std::size_t checked = 0, right = 0;
  for (int k = 0; k < grid.dims[2]; ++k)
    for (int j = 0; j < grid.dims[1]; ++j)
      for (int i = 0; i < grid.dims[0]; ++i) {
        const Vec3 p = grid.node(i, j, k);
        const double r = norm(p);
        // Clear of the polygonal surface and of the rim's plane by a little.
        if (std::fabs(r - 3.0) < 0.05 || std::fabs(p.z) < 0.05) continue;
        const bool expected = r < 3.0 && p.z < 0;
        ++checked;
        right += occ.inside.values[grid.index(i, j, k)] == (expected ? 1 : 0);
      }
  EXPECT_GE(static_cast<double>(right) / static_cast<double>(checked), 0.999);
}

TEST(Winding, ModelWindingIsCrossingsPlusRimRemainder) {
  // w_M(p) summed over every model triangle equals J_M(p) (signed crossings from x = −∞)
  // plus R(p) from the rims alone; the hierarchy's R stays within 1e-3 of the exact one.
  const Vec3 c{0.1, -0.2, 0.05};
  const TriangleSoup model = sphere_with_holes(c, 2.0);
  const CleanResult cleaned = clean_soup(model);
  ASSERT_EQ(cleaned.report.holes, 3u);
  // The rims as build_index() finds them: the caps' border loops.
  const detail::CapWinding rims(cleaned.caps);  // as build_index() makes it
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-3, 3);
  double worst_identity = 0, worst_hierarchy = 0;
  for (int n = 0; n < 1500; ++n) {
    const Vec3 p = c + Vec3{u(rng), u(rng), u(rng)};
    double w = 0;
    int j = 0;
    for (const Triangle& t : cleaned.soup.triangles) {
      const std::array<Vec3, 3> v{cleaned.soup.points[t[0]], cleaned.soup.points[t[1]],
                                  cleaned.soup.points[t[2]]};
      w += triangle_winding(p, v[0], v[1], v[2]);
      // The +x line through p meets the triangle at x < p.x? (random p: no ties)
      const Vec3 n = cross(v[1] - v[0], v[2] - v[0]);
      if (n.x == 0) continue;
      const double x = p.x - dot(p - v[0], n) / n.x;  // where the line meets the plane
      const Vec3 q{x, p.y, p.z};
      const bool in = dot(cross(v[1] - v[0], q - v[0]), n) > 0 &&
                      dot(cross(v[2] - v[1], q - v[1]), n) > 0 &&
                      dot(cross(v[0] - v[2], q - v[2]), n) > 0;
      if (in && x < p.x) j += n.x < 0 ? 1 : -1;  // entering against the normal counts +1
    }
    const double exact = rims.remainder_exact(p);
    worst_identity = std::max(worst_identity, std::fabs(w - (j + exact)));
    worst_hierarchy = std::max(worst_hierarchy,
                               std::fabs(rims.remainder(p, rims.shadow_winding(p.y, p.z)) - exact));
  }
  EXPECT_LT(worst_identity, 1e-9);
  EXPECT_LT(worst_hierarchy, 1e-3);
  // Far from the caps (beyond the bound) they cannot reach ½.
  EXPECT_GE(rims.bound(c + Vec3{2.05, 0, 0}), 0.5);  // just off the +x hole
  EXPECT_LT(rims.bound(c + Vec3{20, 0, 0}), 0.5);
  EXPECT_LT(rims.row_bound(c.y + 20, c.z), 0.5);
}

}  // namespace
}  // namespace tpmsfill
