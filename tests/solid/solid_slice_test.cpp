// Direct slicing and iso-material surfaces of a fitted solid (solid_slice.hpp): the section's
// area matches the tets' own cross-section, it has no cracks (its only border edges lie on the
// cube's faces), its contours are closed and oriented, and iso-material vertices carry their
// material.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <tpmsfill/error.hpp>
#include <tpmsfill/solid/cube_map.hpp>
#include <tpmsfill/solid/solid_slice.hpp>
#include <tpmsfill/solid/thb_basis.hpp>

#include "test_util.hpp"

namespace tpmsfill {
namespace {

TetMesh warped_blob() {
  TetMesh blob = test::make_tet_grid({0, 0, 0}, {20, 10, 10}, {10, 5, 5}, 0.1);
  for (Vec3& p : blob.points)
    p = Vec3{p.x + 2 * std::sin(0.3 * p.y), p.y + 1.5 * std::sin(0.2 * p.z + 0.1 * p.x),
             p.z * (1 + 0.03 * p.x) + 0.5 * std::sin(0.4 * p.x)};
  for (const Vec3& p : blob.points) blob.material.push_back(norm(p - Vec3{4, 5, 5}));
  return blob;
}

// Every edge of the section is used by two triangles, but those on the cube's faces (the
// solid's boundary), used by one: no cracks between cells.
void expect_crack_free(const SolidLevelSet& mesh) {
  std::map<std::pair<std::uint32_t, std::uint32_t>, int> uses;
  for (const auto& t : mesh.triangles)
    for (int e = 0; e < 3; ++e) {
      const std::uint32_t a = t[e], b = t[(e + 1) % 3];
      ++uses[{std::min(a, b), std::max(a, b)}];
    }
  auto on_cube_face = [&](std::uint32_t v) {
    for (double x : mesh.uvw[v])
      if (x == 0 || x == 1) return true;
    return false;
  };
  std::size_t border = 0;
  for (const auto& [edge, count] : uses) {
    EXPECT_LE(count, 2);
    if (count == 1) {
      ++border;
      EXPECT_TRUE(on_cube_face(edge.first) && on_cube_face(edge.second))
          << "a border edge inside the cube: a crack";
    }
  }
  EXPECT_GT(border, 0u);
}

TEST(SolidSlice, SectionAreaMatchesTheTetsAndHasNoCracks) {
  const TetMesh blob = warped_blob();
  const SolidFit fit = fit_solid_spline(blob, map_to_cube(blob));
  for (double z : {2.0, 5.0, 8.5}) {
    const SolidSection s = slice_solid(fit.spline, z, {.tau = 0.05});
    ASSERT_FALSE(s.mesh.triangles.empty()) << z;
    const double expected = test::tet_section_area(blob, z);
    EXPECT_NEAR(s.area, expected, 0.01 * expected) << "z = " << z;
    EXPECT_EQ(s.flipped, 0u);
    expect_crack_free(s.mesh);
    // The contours: closed, the outer one counter-clockwise, enclosing the section's area.
    double contour_area = 0;
    for (const Contour& c : s.contours) contour_area += c.area;
    EXPECT_NEAR(contour_area, s.area, 1e-9 * s.area);
    ASSERT_EQ(s.contours.size(), 1u);
    EXPECT_TRUE(s.contours[0].outer());
    for (std::size_t v = 0; v < s.mesh.points.size(); ++v) {
      EXPECT_EQ(s.mesh.points[v].z, z);
      // Material per vertex: the spline's M there (the distance to (4, 5, 5), fitted).
      EXPECT_NEAR(s.mesh.material[v], evaluate_solid(fit.spline, s.mesh.uvw[v]).material, 1e-9);
    }
  }
  // Below and above the solid: nothing.
  EXPECT_TRUE(slice_solid(fit.spline, -5).mesh.triangles.empty());
  EXPECT_TRUE(slice_solid(fit.spline, 50).contours.empty());
}

TEST(SolidSlice, SmallerTauMeansFinerCellsAndTheBoxIsExact) {
  TetMesh box = test::make_tet_grid({0, 0, 0}, {30, 20, 10}, {6, 4, 2}, 0.1);
  const SolidFit fit = fit_solid_spline(box, map_to_cube(box), {.refinements = 0});
  const SolidSection coarse = slice_solid(fit.spline, 4, {.tau = 10});
  const SolidSection fine = slice_solid(fit.spline, 4, {.tau = 0.1});
  EXPECT_GT(fine.mesh.level, coarse.mesh.level);
  EXPECT_GT(fine.mesh.triangles.size(), coarse.mesh.triangles.size());
  // G is the box's affine map: every section is the 30 x 20 rectangle.
  EXPECT_NEAR(coarse.area, 600, 1e-6);
  EXPECT_NEAR(fine.area, 600, 1e-6);
  expect_crack_free(fine.mesh);
  EXPECT_THROW(slice_solid(fit.spline, 4, {.tau = -1}), InputError);
  EXPECT_THROW(iso_material_surface(fit.spline, 1), InputError);  // no material
}

// A fold-free block whose x grows like e^(4u), so that τ keeps leaves of several levels side
// by side (their volume grows 55-fold along u), and whose z = 10 w + 4 v is linear: each
// section is a plane in the parameter cube, its part of a leaf a rectangle in (u, v) that G
// maps onto a rectangle, so no triangle may turn over. M = u + 2 v + 3 w, a plane too.
SolidSpline graded_block() {
  SolidSpline block{tensor_basis(10), {}, {}};
  for (const auto& g : greville_points(block.basis)) {
    block.geometry.push_back({2 * std::exp(4 * g[0]), 10 * g[1], 10 * g[2] + 4 * g[1]});
    block.material.push_back(g[0] + 2 * g[1] + 3 * g[2]);
  }
  return block;
}

std::size_t turned_or_flat(const SolidLevelSet& mesh) {
  std::size_t count = 0;
  for (const auto& t : mesh.triangles) {
    const Vec3 a = mesh.points[t[0]], b = mesh.points[t[1]], c = mesh.points[t[2]];
    count += !((b.x - a.x) * (c.y - a.y) - (c.x - a.x) * (b.y - a.y) > 0);
  }
  return count;
}

TEST(SolidSlice, LeavesOfDifferentLevelsMeetWithoutCracks) {
  const SolidSpline block = graded_block();
  const double width = 2 * (std::exp(4.0) - 1);  // the ends of x interpolate their controls
  // z = 2.5 runs along grid lines (10 w + 4 v = 2.5 at w = 1/64, v = 75/128, and more), whose
  // samples are all on the level set: the points on such a line make triangles flat to
  // rounding, either way up, as one level's marching cubes did (163 turned over then), but no
  // crack and no triangle turned over by more than rounding.
  for (double z : {2.3, 2.5, 7.1, 11.7}) {
    const SolidSliceOptions options{.tau = 0.05};
    const SolidSection s = slice_solid(block, z, options);
    ASSERT_FALSE(s.mesh.triangles.empty()) << z;
    expect_crack_free(s.mesh);
    if (z != 2.5) {
      EXPECT_EQ(s.flipped, 0u) << z;
      EXPECT_EQ(turned_or_flat(s.mesh), 0u) << z;
    }
    for (const auto& t : s.mesh.triangles) {
      const Vec3 a = s.mesh.points[t[0]], b = s.mesh.points[t[1]], c = s.mesh.points[t[2]];
      EXPECT_GT((b.x - a.x) * (c.y - a.y) - (c.x - a.x) * (b.y - a.y), -1e-12) << z;
    }
    // 10 w + 4 v = z for some w in [0, 1]: y = 10 v from max(0, z − 10) to min(1, z / 4) · 10.
    const double height = 10 * (std::min(1.0, z / 4) - std::max(0.0, (z - 10) / 4));
    EXPECT_NEAR(s.area, width * height, 1e-7 * width * height) << z;
    ASSERT_EQ(s.contours.size(), 1u);
    // One level throughout (every leaf split to the deepest level kept) makes more triangles.
    const SolidSection uniform = slice_solid(block, z, {.tau = 1e-12, .max_level = s.mesh.level});
    EXPECT_EQ(uniform.mesh.level, s.mesh.level);
    EXPECT_NEAR(uniform.area, s.area, 1e-9 * s.area);
    EXPECT_LT(s.mesh.triangles.size(), uniform.mesh.triangles.size()) << z;
    EXPECT_LT(s.mesh.cells, uniform.mesh.cells) << z;
  }
}

TEST(SolidSlice, IsoMaterialSurfacesOfMixedLevelsHaveNoCracks) {
  const SolidSpline block = graded_block();
  for (double m : {0.7, 2.2, 4.9}) {
    const SolidLevelSet s = iso_material_surface(block, m, {.tau = 0.05});
    ASSERT_FALSE(s.triangles.empty()) << m;
    expect_crack_free(s);
    for (std::size_t v = 0; v < s.points.size(); ++v) EXPECT_NEAR(s.material[v], m, 1e-6);
    const SolidLevelSet uniform =
        iso_material_surface(block, m, {.tau = 1e-12, .max_level = s.level});
    EXPECT_LT(s.triangles.size(), uniform.triangles.size()) << m;
  }
}

TEST(SolidSlice, IsoMaterialSurfacesCarryTheirValueAndNest) {
  const TetMesh blob = warped_blob();
  const SolidFit fit = fit_solid_spline(blob, map_to_cube(blob));
  double previous_mean = 0;
  // (Radii of a tet or two would meet the cone's apex, which a cubic rounds off.)
  for (double m : {5.0, 7.0, 9.0}) {
    const SolidLevelSet s = iso_material_surface(fit.spline, m, {.tau = 0.05});
    ASSERT_FALSE(s.triangles.empty()) << m;
    double mean = 0;
    for (const Vec3& p : s.points) mean += norm(p - Vec3{4, 5, 5}) / s.points.size();
    // The material is the distance to (4, 5, 5): the surface lies near the sphere of radius m.
    EXPECT_NEAR(mean, m, 0.05 * m);
    EXPECT_GT(mean, previous_mean);  // nested: each further out than the last
    previous_mean = mean;
    // Every vertex satisfies M = m (edge points by regula falsi, loop centroids by Newton).
    for (std::size_t v = 0; v < s.points.size(); ++v) {
      EXPECT_NEAR(s.material[v], m, 1e-6);
      EXPECT_NEAR(evaluate_solid(fit.spline, s.uvw[v]).material, m, 1e-6);
    }
    expect_crack_free(s);
  }
}

// Winding number of the contours about p.
int winding(const std::vector<Contour>& contours, Vec2 p) {
  int w = 0;
  for (const Contour& c : contours)
    for (std::size_t i = 0; i < c.points.size(); ++i) {
      const Vec2 a = c.points[i], b = c.points[(i + 1) % c.points.size()];
      const double side = (b.x - a.x) * (p.y - a.y) - (p.x - a.x) * (b.y - a.y);
      if (a.y <= p.y && b.y > p.y && side > 0) ++w;
      if (a.y > p.y && b.y <= p.y && side < 0) --w;
    }
  return w;
}

// Whether segments ab and cd cross at a point inside both.
bool cross_properly(Vec2 a, Vec2 b, Vec2 c, Vec2 d) {
  auto orient = [](Vec2 p, Vec2 q, Vec2 r) {
    return (q.x - p.x) * (r.y - p.y) - (r.x - p.x) * (q.y - p.y);
  };
  return orient(a, b, c) * orient(a, b, d) < 0 && orient(c, d, a) * orient(c, d, b) < 0;
}

TEST(SolidSlice, WhereTheSolidFoldsTheContoursBoundWhatItCovers) {
  // A 10 mm cube whose spline has one control point on its face x = 10 pulled in past its
  // neighbours: G folds under that face, so some of the section's triangles come out turned
  // over and its border chains cross themselves. The contours must instead be simple and
  // bound every point some triangle covers, either way up.
  SolidSpline cube{tensor_basis(6), {}, {}};
  for (const auto& g : greville_points(cube.basis))
    cube.geometry.push_back(10.0 * Vec3{g[0], g[1], g[2]});
  std::size_t pulled = 0;
  double best = 1e300;
  const auto grevilles = greville_points(cube.basis);
  for (std::size_t f = 0; f < grevilles.size(); ++f) {
    const auto& g = grevilles[f];
    const double d = std::abs(g[0] - 1) + std::abs(g[1] - 0.5) + std::abs(g[2] - 0.5);
    if (d < best) best = d, pulled = f;
  }
  cube.geometry[pulled].x = 4;
  const SolidSection s = slice_solid(cube, cube.geometry[pulled].z, {.tau = 0.01});
  ASSERT_GT(s.flipped, 0u);
  double signed_sum = 0, unsigned_sum = 0;
  for (const auto& t : s.mesh.triangles) {
    const Vec3 a = s.mesh.points[t[0]], b = s.mesh.points[t[1]], c = s.mesh.points[t[2]];
    const double area = ((b.x - a.x) * (c.y - a.y) - (c.x - a.x) * (b.y - a.y)) / 2;
    signed_sum += area, unsigned_sum += std::abs(area);
    // Inside the region: each triangle's centre, unless the triangle is a sliver.
    const double longest = std::max({norm(b - a), norm(c - b), norm(a - c)});
    if (std::abs(area) > 1e-4 * longest * longest) {
      const Vec3 m = (1.0 / 3) * (a + b + c);
      EXPECT_NE(winding(s.contours, {m.x, m.y}), 0) << "a triangle outside the contours";
    }
  }
  double contour_area = 0;
  for (const Contour& c : s.contours) contour_area += c.area;
  EXPECT_NEAR(s.area, contour_area, 1e-12 * s.area);
  EXPECT_GT(s.area, signed_sum);  // the notch a fold made is filled
  EXPECT_LE(s.area, unsigned_sum * (1 + 1e-9));
  // Simple: no two contour edges cross.
  std::vector<std::pair<Vec2, Vec2>> edges;
  for (const Contour& c : s.contours)
    for (std::size_t i = 0; i < c.points.size(); ++i)
      edges.push_back({c.points[i], c.points[(i + 1) % c.points.size()]});
  std::size_t crossings = 0;
  for (std::size_t i = 0; i < edges.size(); ++i)
    for (std::size_t j = i + 1; j < edges.size(); ++j)
      crossings += cross_properly(edges[i].first, edges[i].second, edges[j].first, edges[j].second);
  EXPECT_EQ(crossings, 0u);
}

}  // namespace
}  // namespace tpmsfill
