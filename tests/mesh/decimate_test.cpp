// Stage "decimate": geometric truths. A finely tessellated sphere and box lose most of their
// triangles, stay valid (validate_mesh and the independent check_mesh), every point of the
// result lies within the tolerance of the input and every point of the input within the
// tolerance of the result (measured here with CGAL's AABB tree, not with the stage's own
// figures), the volume moves by less than the tolerance times the area; a
// filled lattice stays valid; the result does not depend on the thread count; an invalid input
// and bad options are refused. Real meshes from libcgal-demo when present.
#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_tree.h>
#include <CGAL/AABB_triangle_primitive.h>
#include <CGAL/Simple_cartesian.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <map>
#include <tpmsfill/check.hpp>
#include <tpmsfill/decimate.hpp>
#include <tpmsfill/error.hpp>
#include <tpmsfill/fill.hpp>
#include <tpmsfill/io.hpp>
#include <tpmsfill/mesh/validate.hpp>
#include <vector>

#include "test_util.hpp"

using namespace tpmsfill;
namespace fs = std::filesystem;

namespace {

// Plain double arithmetic is enough for a distance, and a tree type of its own: the library's
// detail::surface_distances instantiates the Epick tree with CGAL_LINKED_WITH_TBB (a mutex
// inside), which this file is not compiled with, and one symbol for two layouts deadlocks.
using K = CGAL::Simple_cartesian<double>;
using Tri = K::Triangle_3;
using Tree = CGAL::AABB_tree<
    CGAL::AABB_traits<K, CGAL::AABB_triangle_primitive<K, std::vector<Tri>::const_iterator>>>;

K::Point_3 pt(Vec3 p) {
  return {p.x, p.y, p.z};
}

// Largest distance from the points of `from`'s triangles (each one's barycentric grid of
// order 8: 45 points) to `to`'s surface: a sampled one-sided Hausdorff distance, measured
// independently of the stage and more densely than its report.
double max_distance(const TriangleSoup& from, const TriangleSoup& to) {
  std::vector<Tri> triangles;
  for (const Triangle& t : to.triangles)
    triangles.emplace_back(pt(to.points[t[0]]), pt(to.points[t[1]]), pt(to.points[t[2]]));
  Tree tree(triangles.begin(), triangles.end());
  tree.accelerate_distance_queries();
  double worst = 0;
  for (const Triangle& t : from.triangles) {
    const Vec3 a = from.points[t[0]], b = from.points[t[1]], c = from.points[t[2]];
    constexpr int n = 8;
    for (int i = 0; i <= n; ++i)
      for (int j = 0; i + j <= n; ++j) {
        const Vec3 q = (1.0 / n) * (static_cast<double>(i) * a + static_cast<double>(j) * b +
                                    static_cast<double>(n - i - j) * c);
        worst = std::max(worst, std::sqrt(tree.squared_distance(pt(q))));
      }
  }
  return worst;
}

// A cube of side `side` whose every face is an n x n grid of squares, two triangles each,
// welded and oriented outward.
TriangleSoup tessellated_cube(double side, int n) {
  TriangleSoup cube;
  std::map<std::array<int, 3>, std::uint32_t> ids;
  auto id = [&](std::array<int, 3> g) {
    auto [it, added] = ids.try_emplace(g, static_cast<std::uint32_t>(cube.points.size()));
    if (added) cube.points.push_back({side * g[0] / n, side * g[1] / n, side * g[2] / n});
    return it->second;
  };
  for (int axis = 0; axis < 3; ++axis)
    for (int end : {0, n}) {
      const int u = (axis + 1) % 3, v = (axis + 2) % 3;
      for (int i = 0; i < n; ++i)
        for (int j = 0; j < n; ++j) {
          std::array<std::uint32_t, 4> q;
          const int du[4] = {0, 1, 1, 0}, dv[4] = {0, 0, 1, 1};
          for (int k = 0; k < 4; ++k) {
            std::array<int, 3> g{};
            g[axis] = end;
            g[u] = i + du[k];
            g[v] = j + dv[k];
            q[k] = id(g);
          }
          // (u, v, axis) is right-handed: counter-clockwise in (u, v) faces +axis.
          if (end == n) {
            cube.triangles.push_back({q[0], q[1], q[2]});
            cube.triangles.push_back({q[0], q[2], q[3]});
          } else {
            cube.triangles.push_back({q[0], q[2], q[1]});
            cube.triangles.push_back({q[0], q[3], q[2]});
          }
        }
    }
  return cube;
}

// The input is rounded to float first (DecimateOptions::rounding): its points move by
// up to 2^-24 of their magnitude, far below any tolerance here.
double slack(double tolerance) {
  return tolerance * (1 + 1e-4) + 1e-6;
}

// The truths every decimation must keep.
void expect_valid_within(const TriangleSoup& input, const DecimateResult& r, double tolerance) {
  EXPECT_TRUE(r.report.validation.valid())
      << testing::PrintToString(r.report.validation.problems());
  const MeshValidity v = validate_mesh(r.mesh);
  EXPECT_TRUE(v.valid()) << testing::PrintToString(v.problems());
  EXPECT_EQ(v.self_intersecting_pairs.value_or(1), 0u);
  const MeshCheck c = check_mesh(r.mesh);  // the independent checker
  EXPECT_TRUE(c.valid()) << testing::PrintToString(c.problems());
  EXPECT_EQ(r.report.triangles_after, r.mesh.triangles.size());
  // The result and the input lie within the tolerance of each other, both ways (the proven
  // Hausdorff bound).
  EXPECT_LE(max_distance(r.mesh, input), slack(tolerance));
  EXPECT_LE(max_distance(input, r.mesh), slack(tolerance));
  EXPECT_LE(r.report.distance.hausdorff(), slack(tolerance));
  // The volume moves by at most the tolerance over the surface (a shell of width tolerance).
  EXPECT_LE(std::abs(r.report.volume_after - r.report.volume_before),
            tolerance * r.report.area_before);
  EXPECT_NEAR(r.report.volume_after, *v.volume, 1e-9 * std::abs(*v.volume));
}

}  // namespace

TEST(Decimate, FineSphereLosesMostTrianglesWithinTolerance) {
  const TriangleSoup sphere = test::make_sphere({1, 2, 3}, 10.0, 5);  // 20,480 triangles
  const double tolerance = 0.05;
  const DecimateResult r = decimate(sphere, {.tolerance = tolerance});
  EXPECT_EQ(r.report.triangles_before, sphere.triangles.size());
  EXPECT_LT(r.report.triangles_after * 4, r.report.triangles_before)
      << r.report.triangles_after << " triangles left";
  EXPECT_EQ(r.report.stop, DecimateStop::Tolerance);
  EXPECT_EQ(r.report.hausdorff_bound, tolerance);
  expect_valid_within(sphere, r, tolerance);
  // Still a sphere: genus 0, one component.
  const MeshCheck c = check_mesh(r.mesh);
  EXPECT_EQ(c.genus.value_or(-1), 0);
  EXPECT_EQ(c.components, 1u);
  EXPECT_TRUE(r.report.warnings.empty()) << testing::PrintToString(r.report.warnings);
}

TEST(Decimate, FlatFacesCollapseToAFewTrianglesAndKeepTheVolume) {
  const TriangleSoup cube = tessellated_cube(10.0, 8);  // 768 triangles
  ASSERT_TRUE(validate_mesh(cube).valid());
  const double tolerance = 0.01;
  const DecimateResult r = decimate(cube, {.tolerance = tolerance});
  EXPECT_LT(r.report.triangles_after, 100u);
  expect_valid_within(cube, r, tolerance);
  EXPECT_NEAR(r.report.volume_before, 1000.0, 1e-9);
  EXPECT_NEAR(r.report.volume_after, 1000.0, tolerance * 600);
  EXPECT_EQ(check_mesh(r.mesh).genus.value_or(-1), 0);
}

// A one-sided bound (the result near the input) lets a small spike be flattened: the flat
// face lies near the input everywhere. The two-sided bound keeps the spike's tip within the
// tolerance of the result.
TEST(Decimate, KeepsASpikeTallerThanTheTolerance) {
  TriangleSoup cube = tessellated_cube(10.0, 10);
  const double tolerance = 0.02;
  // The middle point of the top face (z = 10) rises by 10 tolerances.
  Vec3* tip = nullptr;
  for (Vec3& p : cube.points)
    if (p.x == 5.0 && p.y == 5.0 && p.z == 10.0) tip = &p;
  ASSERT_NE(tip, nullptr);
  tip->z += 10 * tolerance;
  const Vec3 top = *tip;
  ASSERT_TRUE(validate_mesh(cube).valid());
  const DecimateResult r = decimate(cube, {.tolerance = tolerance});
  expect_valid_within(cube, r, tolerance);
  EXPECT_LT(r.report.triangles_after * 4, r.report.triangles_before);
  double highest = 0;
  for (const Vec3& p : r.mesh.points) highest = std::max(highest, p.z);
  EXPECT_GE(highest, top.z - tolerance);
}

TEST(Decimate, StopsAtTheTarget) {
  const TriangleSoup sphere = test::make_sphere({0, 0, 0}, 10.0, 5);
  const DecimateResult r = decimate(sphere, {.tolerance = 0.5, .target_triangles = 5000});
  EXPECT_LE(r.report.triangles_after, 5000u);
  EXPECT_GT(r.report.triangles_after, 4000u);
  EXPECT_EQ(r.report.stop, DecimateStop::Target);
  expect_valid_within(sphere, r, 0.5);
}

TEST(Decimate, WarnsWhenTheTargetIsOutOfReach) {
  const TriangleSoup sphere = test::make_sphere({0, 0, 0}, 10.0, 4);
  const DecimateResult r = decimate(sphere, {.tolerance = 0.001, .target_triangles = 100});
  EXPECT_GT(r.report.triangles_after, 100u);
  EXPECT_EQ(r.report.stop, DecimateStop::Tolerance);
  ASSERT_EQ(r.report.warnings.size(), 1u);
  EXPECT_NE(r.report.warnings[0].find("the target of 100 triangles was not reached"),
            std::string::npos)
      << r.report.warnings[0];
  expect_valid_within(sphere, r, 0.001);
}

TEST(Decimate, StlSoupIsWeldedFirst) {
  const TriangleSoup sphere = test::make_sphere({0, 0, 0}, 10.0, 3);
  const DecimateResult r = decimate(test::unshare_points(sphere), {.tolerance = 0.05});
  EXPECT_EQ(r.report.merged_points, 3 * sphere.triangles.size() - r.report.vertices_before);
  expect_valid_within(sphere, r, 0.05);
}

TEST(Decimate, FilledLatticeStaysValid) {
  const TriangleSoup ball = test::make_sphere({0, 0, 0}, 3.0, 4);
  const FillResult filled = fill(ball, test::gyroid_options(2.0, 0.15));
  ASSERT_TRUE(filled.report.validation.valid());
  const double tolerance = 0.15 / 4;  // voxel / 4
  const DecimateResult r = decimate(filled.mesh, {.tolerance = tolerance});
  expect_valid_within(filled.mesh, r, tolerance);
  EXPECT_LT(r.report.triangles_after, r.report.triangles_before);
  // No collapse made triangles meet (the guard runs validation's own pair test), so the first
  // round's result was valid.
  EXPECT_EQ(r.report.rounds, 1);
  EXPECT_TRUE(r.report.invalid_pairs.empty());
  // The lattice keeps its pieces and its genus.
  const MeshCheck before = check_mesh(filled.mesh), after = check_mesh(r.mesh);
  EXPECT_EQ(after.components, before.components);
  EXPECT_EQ(after.genus, before.genus);
  EXPECT_NEAR(r.report.volume_change(), 0.0, 0.01);
}

TEST(Decimate, SameResultWhateverTheThreadCount) {
  const TriangleSoup ball = test::make_sphere({0, 0, 0}, 2.5, 4);
  const FillResult filled = fill(ball, test::gyroid_options(2.0, 0.2));
  DecimateResult one, many;
  {
    tbb::global_control serial(tbb::global_control::max_allowed_parallelism, 1);
    one = decimate(filled.mesh, {.tolerance = 0.05});
  }
  many = decimate(filled.mesh, {.tolerance = 0.05});
  EXPECT_EQ(one.mesh.triangles, many.mesh.triangles);
  EXPECT_TRUE(one.mesh.points == many.mesh.points);
  // Every figure but the wall time.
  one.report.seconds = many.report.seconds = 0;
  EXPECT_EQ(to_json(one.report), to_json(many.report));
}

TEST(Decimate, NewPointsAreFloats) {
  const TriangleSoup sphere = test::make_sphere({0.1, 0.2, 0.3}, 10.0, 4);
  const DecimateResult r = decimate(sphere, {.tolerance = 0.05});
  for (const Vec3& p : r.mesh.points)
    for (double c : {p.x, p.y, p.z}) ASSERT_EQ(c, static_cast<double>(static_cast<float>(c)));
}

TEST(Decimate, RefusesAnInvalidInputAndBadOptions) {
  const TriangleSoup open = test::make_box_with_hole({0, 0, 0}, {10, 10, 10});
  try {
    decimate(open, {.tolerance = 0.1});
    FAIL() << "an open box was decimated";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("border edge"), std::string::npos) << e.what();
  }
  const TriangleSoup box = test::make_box({0, 0, 0}, {1, 1, 1});
  EXPECT_THROW(decimate(box, {.tolerance = 0}), InputError);
  EXPECT_THROW(decimate(box, {.tolerance = -1}), InputError);
  EXPECT_THROW(decimate(box, {.tolerance = NAN}), InputError);
  EXPECT_THROW(decimate(box, {.tolerance = 0.1, .max_rounds = 0}), InputError);
}

TEST(Decimate, CancelledThroughProgress) {
  struct Stop : Progress {
    bool report(double) override { return false; }
  } stop;
  const TriangleSoup sphere = test::make_sphere({0, 0, 0}, 10.0, 5);
  EXPECT_THROW(decimate(sphere, {.tolerance = 0.05, .progress = &stop}), Cancelled);
}

TEST(Decimate, JsonHasTheFiguresAsked) {
  const TriangleSoup sphere = test::make_sphere({0, 0, 0}, 10.0, 4);
  const DecimateResult r = decimate(sphere, {.tolerance = 0.05});
  const std::string json = to_json(r.report);
  for (const char* key : {"\"triangles_before\"", "\"triangles_after\"", "\"hausdorff\"",
                          "\"volume_change\"", "\"hausdorff_bound\"", "\"valid\": true"})
    EXPECT_NE(json.find(key), std::string::npos) << key;
  EXPECT_NE(to_text(r.report).find("VALID"), std::string::npos);
}

// Every libcgal-demo mesh that is valid stays valid, within a tolerance of 0.2 % of its
// bounding-box diagonal.
TEST(Decimate, EveryValidCgalDemoMeshStaysValid) {
  const fs::path dir = TPMSFILL_CGAL_MESHES;
  if (!fs::exists(dir)) GTEST_SKIP() << dir << " is missing: install libcgal-demo";
  int decimated = 0;
  // Up to 400 kB (about 20,000 triangles): the larger ones belong to the benchmark
  // (docs/benchmarks.md).
  for (const fs::path& file : test::files_in(dir, 400'000)) {
    TriangleSoup soup;
    try {
      soup = read_mesh(file);
    } catch (const Error&) {
      continue;
    }
    if (!check_mesh(soup).valid()) continue;
    SCOPED_TRACE(file.filename().string());
    const Vec3 size = bounding_box(soup).size();
    const double tolerance = 0.002 * norm(size);
    const DecimateResult r = decimate(soup, {.tolerance = tolerance});
    EXPECT_TRUE(r.report.validation.valid());
    EXPECT_TRUE(check_mesh(r.mesh).valid());
    EXPECT_LE(r.report.triangles_after, r.report.triangles_before);
    EXPECT_LE(max_distance(r.mesh, soup), slack(tolerance));
    EXPECT_LE(max_distance(soup, r.mesh), slack(tolerance));
    ++decimated;
  }
  EXPECT_GT(decimated, 5);
}
