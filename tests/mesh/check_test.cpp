// Stage "check": geometric truths about meshes made in code.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>
#include <tpmsfill/check.hpp>
#include <tpmsfill/error.hpp>
#include <tpmsfill/mesh/validate.hpp>

#include "test_util.hpp"

using namespace tpmsfill;
using test::concat;
using test::flip;
using test::make_box;

namespace {

const TriangleSoup kBox = make_box({0, 0, 0}, {10, 20, 30});

// The facts every valid mesh shares.
void expect_valid(const MeshCheck& c) {
  EXPECT_TRUE(c.valid());
  EXPECT_TRUE(c.problems().empty()) << c.problems().front();
  EXPECT_TRUE(c.closed());
  EXPECT_TRUE(c.manifold());
  EXPECT_TRUE(c.consistently_oriented());
  EXPECT_EQ(c.holes, 0u);
  EXPECT_EQ(c.degenerate_triangles, 0u);
  EXPECT_EQ(c.duplicate_triangles, 0u);
  EXPECT_EQ(c.self_intersecting_pairs, std::uint64_t{0});
  EXPECT_EQ(c.outward, true);
}

bool mentions(const MeshValidity& c, const std::string& words) {
  for (const std::string& p : c.problems())
    if (p.find(words) != std::string::npos) return true;
  return false;
}

}  // namespace

TEST(CheckMesh, BoxIsValid) {
  const MeshCheck c = check_mesh(kBox);
  expect_valid(c);
  EXPECT_EQ(c.points, 8u);
  EXPECT_EQ(c.triangles, 12u);
  EXPECT_EQ(c.vertices, 8u);
  EXPECT_EQ(c.duplicate_points, 0u);
  EXPECT_EQ(c.unreferenced_points, 0u);
  EXPECT_EQ(c.edges, 18u);
  EXPECT_EQ(c.volume, 6000.0);  // exact: every product is exact in double
  EXPECT_EQ(c.genus, 0);
  EXPECT_EQ(c.components, 1u);
  EXPECT_EQ(c.edge_components, 1u);
  EXPECT_DOUBLE_EQ(c.area, 2 * (10 * 20 + 20 * 30 + 10 * 30));
  EXPECT_EQ(c.bbox.min, (Vec3{0, 0, 0}));
  EXPECT_EQ(c.bbox.max, (Vec3{10, 20, 30}));
}

TEST(CheckMesh, SphereIsValidWithThePolyhedronsVolume) {
  const TriangleSoup sphere = test::make_sphere({1, 2, 3}, 5.0, 3);
  const MeshCheck c = check_mesh(sphere);
  expect_valid(c);
  EXPECT_EQ(c.genus, 0);
  ASSERT_TRUE(c.volume);
  EXPECT_NEAR(*c.volume, test::signed_volume(sphere), 1e-9 * test::signed_volume(sphere));
  EXPECT_NEAR(*c.volume, 4.0 / 3.0 * 3.14159265358979 * 125, 0.02 * 4 / 3 * 3.1416 * 125);
  EXPECT_EQ(c.vertices, 642u);  // 10 * 4^3 + 2
}

TEST(CheckMesh, TorusHasGenusOne) {
  const MeshCheck c = check_mesh(test::make_torus(3, 1, 48, 24));
  expect_valid(c);
  EXPECT_EQ(c.genus, 1);
  EXPECT_EQ(c.components, 1u);
}

TEST(CheckMesh, BoxWithHoleIsOpen) {
  const MeshCheck c = check_mesh(test::make_box_with_hole({0, 0, 0}, {1, 1, 1}));
  EXPECT_FALSE(c.valid());
  EXPECT_FALSE(c.closed());
  EXPECT_EQ(c.border_edges, 4u);
  EXPECT_EQ(c.holes, 1u);
  EXPECT_EQ(c.border_edge_examples.size(), 4u);
  EXPECT_FALSE(c.volume);
  EXPECT_FALSE(c.outward);
  EXPECT_FALSE(c.genus);
  ASSERT_FALSE(c.problems().empty());
  EXPECT_EQ(c.problems().front(), "4 border edges in 1 hole: the mesh is open");
  // Every border edge lies on the missing +x side and belongs to a triangle of the soup.
  for (const EdgeLocation& e : c.border_edge_examples) {
    EXPECT_EQ(e.ends[0].x, 1.0);
    EXPECT_EQ(e.ends[1].x, 1.0);
    EXPECT_LT(e.triangle, 10u);
  }
}

TEST(CheckMesh, OverlappingBoxesSelfIntersect) {
  const MeshCheck c = check_mesh(concat(kBox, make_box({5, 5, 5}, {15, 25, 35})));
  EXPECT_FALSE(c.valid());
  EXPECT_EQ(c.components, 2u);
  EXPECT_EQ(c.edge_components, 2u);
  ASSERT_TRUE(c.self_intersecting_pairs);
  EXPECT_GT(*c.self_intersecting_pairs, 0u);
  ASSERT_FALSE(c.self_intersection_examples.empty());
  for (const auto& [i, j] : c.self_intersection_examples) {
    EXPECT_LT(i, 12u);  // one triangle from each box
    EXPECT_GE(j, 12u);
  }
  EXPECT_TRUE(mentions(c, "self-intersecting triangle pair"));
  // Not searched: unset, and then it does not count against the verdict.
  const MeshCheck quick =
      check_mesh(concat(kBox, make_box({5, 5, 5}, {15, 25, 35})), {.self_intersections = false});
  EXPECT_FALSE(quick.self_intersecting_pairs);
  EXPECT_TRUE(quick.self_intersection_examples.empty());
  EXPECT_TRUE(quick.valid());
}

TEST(CheckMesh, DisjointBoxesAreValid) {
  const MeshCheck c = check_mesh(concat(kBox, make_box({20, 0, 0}, {30, 10, 10})));
  expect_valid(c);
  EXPECT_EQ(c.components, 2u);
  EXPECT_EQ(c.edge_components, 2u);
  EXPECT_EQ(c.volume, 7000.0);
  EXPECT_EQ(c.genus, 0);
}

TEST(CheckMesh, NestedBoxWithInnerFlippedIsAHollowSolid) {
  const TriangleSoup inner = make_box({2, 2, 2}, {8, 18, 28});
  const MeshCheck hollow = check_mesh(concat(kBox, flip(inner)));
  expect_valid(hollow);
  EXPECT_EQ(hollow.components, 2u);
  EXPECT_DOUBLE_EQ(*hollow.volume, 6000.0 - 6 * 16 * 26);

  const MeshCheck wrong = check_mesh(concat(kBox, inner));
  EXPECT_FALSE(wrong.valid());
  EXPECT_TRUE(wrong.consistently_oriented());
  EXPECT_EQ(wrong.outward, false);
  EXPECT_GT(*wrong.volume, 0);  // positive, yet the inner shell faces the wrong way
  EXPECT_TRUE(mentions(wrong, "oriented the wrong way"));
}

TEST(CheckMesh, BowTieHasOneNonManifoldVertex) {
  const MeshCheck c = check_mesh(test::make_bow_tie());
  EXPECT_FALSE(c.valid());
  EXPECT_TRUE(c.closed());
  EXPECT_EQ(c.non_manifold_edges, 0u);
  EXPECT_EQ(c.non_manifold_vertices, 1u);
  EXPECT_FALSE(c.manifold());
  EXPECT_EQ(c.components, 1u);
  EXPECT_EQ(c.edge_components, 2u);
  ASSERT_EQ(c.non_manifold_vertex_examples.size(), 1u);
  EXPECT_EQ(c.non_manifold_vertex_examples[0], (Vec3{0, 0, 0}));
  EXPECT_FALSE(c.volume);
  EXPECT_TRUE(mentions(c, "1 non-manifold vertex"));
  // The two tetrahedra only touch at the apex they share: a pinched vertex, not an intersection.
  EXPECT_EQ(c.self_intersecting_pairs, std::uint64_t{0});
}

// check and validate decide self-intersections with one pair test: on soups whose points are
// already shared (validate takes the indices as given), they find the same pairs, wherever the
// soup sits, and shapes that only touch (a shared edge or corner) are not pairs.
TEST(CheckMesh, FindsTheSelfIntersectionsValidationFinds) {
  const TriangleSoup crossing =
      concat(test::make_sphere({0, 0, 0}, 1, 3), test::make_torus(0.8, 0.3, 32, 16));
  const TriangleSoup boxes = concat(kBox, make_box({5, 5, 5}, {15, 25, 35}));
  // Two boxes along one edge, x = 10 and y = 20: touching, not crossing. Their copies of the
  // edge's points are separate points, which check merges and validate does not.
  const TriangleSoup touching = concat(kBox, make_box({10, 20, 0}, {20, 40, 30}));
  for (const Vec3 at : {Vec3{0, 0, 0}, Vec3{150, 150, 0}, Vec3{0, 0, -1000}, Vec3{-350, 20, 400},
                        Vec3{1e5, -1e5, 3e4}}) {
    for (const TriangleSoup* shape : {&crossing, &boxes, &touching}) {
      TriangleSoup soup = *shape;
      for (Vec3& p : soup.points) p = p + at;
      const MeshCheck c = check_mesh(soup, {.max_examples = 1000000});
      ASSERT_TRUE(c.self_intersecting_pairs);
      if (shape == &touching) {
        EXPECT_EQ(*c.self_intersecting_pairs, 0u);
        EXPECT_EQ(c.non_manifold_edges, 1u);
        continue;
      }
      ValidateOptions every;
      every.max_examples = 1000000;
      const MeshValidity v = validate_mesh(soup, every);
      ASSERT_TRUE(v.self_intersecting_pairs);
      EXPECT_GT(*c.self_intersecting_pairs, 0u);
      EXPECT_EQ(*c.self_intersecting_pairs, *v.self_intersecting_pairs)
          << "at (" << at.x << ", " << at.y << ", " << at.z << ")";
      EXPECT_EQ(c.self_intersection_examples, v.self_intersection_examples);
    }
  }
}

// check and validate report through one type with one verdict: on meshes whose points are
// already shared, the validity facts agree wherever the mesh sits; where a soup repeats its
// points, check merges them (valid) and validate, taking the indices as given, names them.
TEST(CheckMesh, CheckAndValidateGiveOneVerdict) {
  TriangleSoup hollow = kBox;  // a box with a box-shaped cavity
  TriangleSoup inner = flip(make_box({2, 2, 2}, {8, 18, 28}));
  hollow = concat(hollow, inner);
  TriangleSoup torn = kBox;  // one missing triangle
  torn.triangles.pop_back();
  const std::vector<TriangleSoup> shapes = {
      kBox,
      test::make_sphere({0, 0, 0}, 1, 3),
      test::make_torus(3, 1, 48, 24),
      hollow,
      torn,
      flip(kBox),
      flip(kBox, 4),
      test::make_bow_tie(),
      concat(kBox, make_box({5, 5, 5}, {15, 25, 35})),
      concat(test::make_sphere({0, 0, 0}, 1, 3), test::make_torus(0.8, 0.3, 32, 16))};
  for (const Vec3 at : {Vec3{0, 0, 0}, Vec3{150, 150, 0}, Vec3{-350, 20, 400}}) {
    for (std::size_t i = 0; i < shapes.size(); ++i) {
      TriangleSoup soup = shapes[i];
      for (Vec3& p : soup.points) p = p + at;
      SCOPED_TRACE("shape " + std::to_string(i) + " at x = " + std::to_string(at.x));
      const MeshCheck c = check_mesh(soup);
      const MeshValidity v = validate_mesh(soup);
      EXPECT_TRUE(c.merged_points);
      EXPECT_FALSE(v.merged_points);
      EXPECT_EQ(c.valid(), v.valid());
      EXPECT_EQ(c.problems().empty(), v.problems().empty());
      EXPECT_EQ(c.problems().size(), v.problems().size());
      EXPECT_EQ(c.border_edges, v.border_edges);
      EXPECT_EQ(c.non_manifold_edges, v.non_manifold_edges);
      EXPECT_EQ(c.non_manifold_vertices, v.non_manifold_vertices);
      EXPECT_EQ(c.inconsistent_edges, v.inconsistent_edges);
      EXPECT_EQ(c.degenerate_triangles, v.degenerate_triangles);
      EXPECT_EQ(c.self_intersecting_pairs, v.self_intersecting_pairs);
      EXPECT_EQ(c.components, v.components);
      EXPECT_EQ(c.border_edge_examples, v.border_edge_examples);
      EXPECT_EQ(c.inconsistent_edge_examples, v.inconsistent_edge_examples);
      EXPECT_EQ(c.non_manifold_vertex_examples, v.non_manifold_vertex_examples);
      EXPECT_NEAR(c.area, v.area, 1e-12 * c.area);
      if (c.volume) {
        EXPECT_NEAR(*c.volume, *v.volume, 1e-9 * std::fabs(*c.volume));
      }
      EXPECT_TRUE(!c.outward || c.outward == v.outward);
    }
  }
  // The same box with every triangle's own points (as STL stores it).
  const TriangleSoup stl = test::unshare_points(kBox);
  const MeshCheck c = check_mesh(stl);
  const MeshValidity v = validate_mesh(stl);
  EXPECT_TRUE(c.valid());
  EXPECT_EQ(c.duplicate_points, 28u);
  EXPECT_FALSE(v.valid());
  EXPECT_EQ(v.duplicate_points, 28u);
  EXPECT_TRUE(mentions(v, "28 duplicate points"));
}

TEST(CheckMesh, OneFlippedFaceGivesThreeInconsistentEdges) {
  const MeshCheck c = check_mesh(flip(kBox, 4));
  EXPECT_FALSE(c.valid());
  EXPECT_TRUE(c.closed());
  EXPECT_TRUE(c.manifold());
  EXPECT_EQ(c.inconsistent_edges, 3u);
  EXPECT_FALSE(c.consistently_oriented());
  ASSERT_EQ(c.inconsistent_edge_examples.size(), 3u);
  EXPECT_FALSE(c.volume);
  EXPECT_EQ(c.holes, 0u);  // CGAL orients the soup before counting border cycles
  EXPECT_EQ(c.self_intersecting_pairs, std::uint64_t{0});
  EXPECT_TRUE(mentions(c, "3 inconsistently oriented edges"));
}

TEST(CheckMesh, FlippedBoxIsInsideOut) {
  const MeshCheck c = check_mesh(flip(kBox));
  EXPECT_FALSE(c.valid());
  EXPECT_TRUE(c.consistently_oriented());
  EXPECT_TRUE(c.closed());
  EXPECT_EQ(c.volume, -6000.0);
  EXPECT_EQ(c.outward, false);
  ASSERT_EQ(c.problems().size(), 1u);
  EXPECT_EQ(c.problems()[0], "the mesh is inside out: its normals point inward (volume -6000)");
}

TEST(CheckMesh, UnsharedPointsAreMerged) {
  const MeshCheck c = check_mesh(test::unshare_points(kBox));
  expect_valid(c);
  EXPECT_EQ(c.points, 36u);
  EXPECT_EQ(c.vertices, 8u);
  EXPECT_EQ(c.duplicate_points, 28u);
  EXPECT_EQ(c.edges, 18u);
  EXPECT_EQ(c.volume, 6000.0);
  EXPECT_EQ(c.genus, 0);
}

TEST(CheckMesh, NegativeZeroIsTheSamePosition) {
  TriangleSoup box = test::unshare_points(kBox);
  for (Vec3& p : box.points)
    if (p.x == 0) p.x = -0.0;
  box.points[0].x = 0.0;
  EXPECT_EQ(check_mesh(box).vertices, 8u);
}

TEST(CheckMesh, UnreferencedPointsAreCounted) {
  TriangleSoup box = kBox;
  box.points.push_back({100, 100, 100});
  box.points.push_back({0, 0, 0});  // same position as point 0, not used
  const MeshCheck c = check_mesh(box);
  expect_valid(c);
  EXPECT_EQ(c.unreferenced_points, 2u);
  EXPECT_EQ(c.duplicate_points, 1u);
  EXPECT_EQ(c.vertices, 8u);
  EXPECT_EQ(c.bbox.max, (Vec3{10, 20, 30}));  // of referenced points only
}

TEST(CheckMesh, RepeatedCornerIsDegenerate) {
  TriangleSoup box = kBox;
  box.triangles.push_back({0, 0, 1});
  const MeshCheck c = check_mesh(box);
  EXPECT_FALSE(c.valid());
  EXPECT_EQ(c.degenerate_triangles, 1u);
  EXPECT_EQ(c.degenerate_triangle_examples, std::vector<std::uint32_t>{12});
  // Left out of the edge topology: the box around it is still closed and oriented.
  EXPECT_TRUE(c.closed());
  EXPECT_TRUE(c.manifold());
  EXPECT_EQ(c.edges, 18u);
  EXPECT_EQ(c.volume, 6000.0);
  EXPECT_EQ(c.outward, true);
  EXPECT_EQ(c.self_intersecting_pairs, std::uint64_t{0});
  EXPECT_TRUE(mentions(c, "1 degenerate triangle"));
}

TEST(CheckMesh, CollinearCornersAreDegenerate) {
  // A sliver on the box's bottom edge from (0,0,0) to (10,0,0): exactly collinear corners.
  TriangleSoup soup = kBox;
  soup.points.push_back({5, 0, 0});
  soup.triangles.push_back({0, 8, 1});
  const MeshCheck c = check_mesh(soup);
  EXPECT_FALSE(c.valid());
  EXPECT_EQ(c.degenerate_triangles, 1u);
  EXPECT_EQ(c.degenerate_triangle_examples, std::vector<std::uint32_t>{12});
  EXPECT_EQ(c.border_edges, 2u);  // (0,8) and (8,1) have one triangle; (0,1) now has three
  EXPECT_EQ(c.non_manifold_edges, 1u);
}

TEST(CheckMesh, DuplicateTriangleIsFound) {
  TriangleSoup box = kBox;
  box.triangles.push_back({box.triangles[3][1], box.triangles[3][2], box.triangles[3][0]});
  const MeshCheck c = check_mesh(box);
  EXPECT_FALSE(c.valid());
  EXPECT_EQ(c.duplicate_triangles, 1u);
  EXPECT_EQ(c.duplicate_triangle_examples, std::vector<std::uint32_t>{12});
  EXPECT_EQ(c.non_manifold_edges, 3u);  // each of its edges now has three triangles
  EXPECT_EQ(c.holes, 0u);               // CGAL's repair drops the copy
  EXPECT_EQ(c.edge_components, 1u);
  EXPECT_TRUE(mentions(c, "1 duplicate triangle"));
}

TEST(CheckMesh, ThreeTrianglesOnOneEdgeMakeANonManifoldEdge) {
  TriangleSoup fin;
  fin.points = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}};
  fin.triangles = {{0, 1, 2}, {1, 0, 3}, {0, 1, 4}};
  const MeshCheck c = check_mesh(fin);
  EXPECT_FALSE(c.valid());
  EXPECT_EQ(c.non_manifold_edges, 1u);
  EXPECT_EQ(c.non_manifold_vertices, 0u);  // a vertex on a non-manifold edge is not counted
  EXPECT_EQ(c.border_edges, 6u);
  EXPECT_EQ(c.edges, 7u);
  EXPECT_EQ(c.components, 1u);
  EXPECT_EQ(c.edge_components, 3u);  // nothing joins the fins but the non-manifold edge
  EXPECT_EQ(c.holes, 3u);            // CGAL splits that edge: three separate triangles
  ASSERT_EQ(c.non_manifold_edge_examples.size(), 1u);
  const EdgeLocation& e = c.non_manifold_edge_examples[0];
  EXPECT_TRUE((e.ends[0] == Vec3{0, 0, 0} && e.ends[1] == Vec3{1, 0, 0}) ||
              (e.ends[0] == Vec3{1, 0, 0} && e.ends[1] == Vec3{0, 0, 0}));
  EXPECT_TRUE(mentions(c, "1 non-manifold edge"));
}

TEST(CheckMesh, OutOfRangeIndexThrows) {
  TriangleSoup box = kBox;
  box.triangles[5][1] = 8;
  EXPECT_THROW(check_mesh(box), InputError);
}

TEST(CheckMesh, EmptySoupIsNotValid) {
  const MeshCheck c = check_mesh(TriangleSoup{});
  EXPECT_FALSE(c.valid());
  EXPECT_EQ(c.triangles, 0u);
  EXPECT_EQ(c.components, 0u);
  EXPECT_FALSE(c.volume);
  EXPECT_TRUE(c.bbox.empty());
  EXPECT_EQ(c.problems(), std::vector<std::string>{"the mesh has no triangles"});
  const auto j = nlohmann::json::parse(to_json(c));
  EXPECT_TRUE(j["bbox"].is_null());
}

TEST(CheckMesh, ExamplesAreCapped) {
  TriangleSoup strip;  // 30 separate triangles: 90 border edges
  for (std::uint32_t i = 0; i < 30; ++i) {
    strip.points.push_back({double(i), 0, 0});
    strip.points.push_back({double(i), 1, 0});
    strip.points.push_back({double(i), 0, 1});
    strip.triangles.push_back({3 * i, 3 * i + 1, 3 * i + 2});
  }
  const MeshCheck c = check_mesh(strip, {.max_examples = 4});
  EXPECT_EQ(c.border_edges, 90u);
  EXPECT_EQ(c.holes, 30u);
  EXPECT_EQ(c.components, 30u);
  EXPECT_EQ(c.border_edge_examples.size(), 4u);
}

TEST(CheckMesh, JsonHasTheStructsFacts) {
  TriangleSoup soup =
      concat(test::make_box_with_hole({0, 0, 0}, {1, 1, 1}), make_box({0.5, 0.5, 0.5}, {3, 3, 3}));
  soup.triangles.push_back({0, 0, 1});
  const MeshCheck c = check_mesh(soup);
  const auto j = nlohmann::json::parse(to_json(c));
  EXPECT_EQ(j["valid"], c.valid());
  EXPECT_EQ(j["problems"].get<std::vector<std::string>>(), c.problems());
  EXPECT_EQ(j["points"], c.points);
  EXPECT_EQ(j["triangles"], c.triangles);
  EXPECT_EQ(j["vertices"], c.vertices);
  EXPECT_EQ(j["duplicate_points"], c.duplicate_points);
  EXPECT_EQ(j["unreferenced_points"], c.unreferenced_points);
  EXPECT_EQ(j["bbox"]["min"], nlohmann::json({0.0, 0.0, 0.0}));
  EXPECT_EQ(j["bbox"]["max"], nlohmann::json({3.0, 3.0, 3.0}));
  EXPECT_EQ(j["degenerate_triangles"], c.degenerate_triangles);
  EXPECT_EQ(j["duplicate_triangles"], c.duplicate_triangles);
  EXPECT_EQ(j["edges"], c.edges);
  EXPECT_EQ(j["border_edges"], c.border_edges);
  EXPECT_EQ(j["holes"], c.holes);
  EXPECT_EQ(j["non_manifold_edges"], c.non_manifold_edges);
  EXPECT_EQ(j["non_manifold_vertices"], c.non_manifold_vertices);
  EXPECT_EQ(j["inconsistent_edges"], c.inconsistent_edges);
  EXPECT_EQ(j["consistently_oriented"], c.consistently_oriented());
  EXPECT_EQ(j["closed"], c.closed());
  EXPECT_EQ(j["manifold"], c.manifold());
  EXPECT_EQ(j["components"], c.components);
  EXPECT_EQ(j["edge_components"], c.edge_components);
  EXPECT_EQ(j["self_intersecting_pairs"], *c.self_intersecting_pairs);
  EXPECT_EQ(j["area"].get<double>(), c.area);  // full precision survives the round trip
  EXPECT_TRUE(j["volume"].is_null());
  EXPECT_TRUE(j["outward"].is_null());
  EXPECT_TRUE(j["genus"].is_null());
  const auto& ex = j["examples"];
  ASSERT_EQ(ex["border_edges"].size(), c.border_edge_examples.size());
  EXPECT_EQ(ex["border_edges"][0]["triangle"], c.border_edge_examples[0].triangle);
  EXPECT_EQ(ex["border_edges"][0]["a"][0].get<double>(), c.border_edge_examples[0].ends[0].x);
  EXPECT_EQ(ex["degenerate_triangles"].get<std::vector<std::uint32_t>>(),
            c.degenerate_triangle_examples);
  ASSERT_EQ(ex["self_intersections"].size(), c.self_intersection_examples.size());
  EXPECT_EQ(ex["self_intersections"][0][1], c.self_intersection_examples[0][1]);
  EXPECT_TRUE(ex["non_manifold_vertices"].is_array());
  EXPECT_TRUE(ex["non_manifold_edges"].is_array());
  EXPECT_TRUE(ex["inconsistent_edges"].is_array());
  EXPECT_TRUE(ex["duplicate_triangles"].is_array());

  const auto valid = nlohmann::json::parse(to_json(check_mesh(kBox)));
  EXPECT_EQ(valid["valid"], true);
  EXPECT_EQ(valid["volume"], 6000.0);
  EXPECT_EQ(valid["outward"], true);
  EXPECT_EQ(valid["genus"], 0);
  EXPECT_TRUE(valid["problems"].empty());
}

TEST(CheckMesh, SameResultTwice) {
  // Sphere and torus intersect; one flipped face; every example kept.
  TriangleSoup soup =
      concat(test::make_sphere({0, 0, 0}, 1, 3), test::make_torus(0.8, 0.3, 32, 16));
  soup = flip(soup, 17);
  const MeshCheck a = check_mesh(soup, {.max_examples = 100000});
  const MeshCheck b = check_mesh(soup, {.max_examples = 100000});
  EXPECT_GT(*a.self_intersecting_pairs, 0u);
  EXPECT_EQ(a.self_intersection_examples.size(), *a.self_intersecting_pairs);
  EXPECT_EQ(a.self_intersection_examples, b.self_intersection_examples);
  EXPECT_EQ(to_json(a), to_json(b));
  // The same soup stored STL-style has the same facts, apart from the points.
  const MeshCheck c = check_mesh(test::unshare_points(soup), {.max_examples = 100000});
  EXPECT_EQ(c.self_intersection_examples, a.self_intersection_examples);
  EXPECT_EQ(c.inconsistent_edges, a.inconsistent_edges);
  EXPECT_EQ(c.edges, a.edges);
  EXPECT_EQ(c.vertices, a.vertices);
  EXPECT_DOUBLE_EQ(c.area, a.area);
}

// A sliver whose corners are 3 µm apart is sound in doubles anywhere, but 100 m from the
// origin a float's step is 7.8 µm: STL's floats put two corners on one point. The check says
// so with the numbers and what to do; at the origin, and in formats of doubles, it says
// nothing.
TEST(CheckRounding, SliversFarOutAreCountedAsTheFileHoldsThem) {
  for (const double offset : {0.0, 10.0, 1e5, -1e5}) {
    TriangleSoup sliver = test::make_box({0, 0, 0}, {1, 1, 1});
    const auto first = static_cast<std::uint32_t>(sliver.points.size());
    sliver.points.insert(sliver.points.end(), {{5, 0, 0}, {5.003, 0, 0}, {5, 1, 0}});
    sliver.triangles.push_back({first, first + 1, first + 2});
    for (Vec3& p : sliver.points) p.x += offset;
    const bool far = std::fabs(offset) > 1e4;
    for (const CoordinateRounding rounding :
         {CoordinateRounding::None, CoordinateRounding::Float, CoordinateRounding::ThreeMf}) {
      const RoundingCheck r = check_rounding(sliver, rounding);
      EXPECT_EQ(r.degenerate, 0u) << offset;
      const bool lost = far && rounding != CoordinateRounding::None;
      EXPECT_EQ(r.held_degenerate, lost ? 1u : 0u) << offset;
      EXPECT_EQ(r.warning.empty(), !lost) << offset << ": " << r.warning;
      if (lost) {
        EXPECT_NE(r.warning.find("1 triangles are degenerate"), std::string::npos) << r.warning;
        const std::string reach = offset > 0 ? "100005 mm" : "100000 mm";
        EXPECT_NE(r.warning.find(reach + " from the origin"), std::string::npos) << r.warning;
        EXPECT_NE(r.warning.find("write PLY, OBJ or OFF"), std::string::npos) << r.warning;
      }
    }
  }
}
