// Polygon triangulation: ear clipping in the Newell plane, fan fallback.
#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <numeric>

#include "io/internal/triangulate_polygon.hpp"

using namespace tpmsfill;

namespace {

std::vector<std::uint32_t> iota(std::size_t n) {
  std::vector<std::uint32_t> v(n);
  std::iota(v.begin(), v.end(), 0u);
  return v;
}

Vec3 triangle_area_vector(const std::vector<Vec3>& p, const Triangle& t) {
  return 0.5 * cross(p[t[1]] - p[t[0]], p[t[2]] - p[t[0]]);
}

// Every directed polygon edge appears once among the triangles' directed edges, and no edge
// is used twice in the same direction: the triangles tile the polygon with its winding.
void expect_edges_consistent(const std::vector<Triangle>& tris, std::size_t n) {
  std::map<std::pair<std::uint32_t, std::uint32_t>, int> directed;
  for (const Triangle& t : tris)
    for (int k = 0; k < 3; ++k) ++directed[{t[k], t[(k + 1) % 3]}];
  for (const auto& [edge, count] : directed)
    EXPECT_EQ(count, 1) << edge.first << "-" << edge.second;
  for (std::uint32_t i = 0; i < n; ++i)
    EXPECT_EQ((directed[{i, static_cast<std::uint32_t>((i + 1) % n)}]), 1) << "edge " << i;
}

}  // namespace

TEST(TriangulatePolygon, TrianglePassesThrough) {
  const std::vector<Vec3> p{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  std::vector<Triangle> out;
  EXPECT_TRUE(detail::triangulate_polygon(p, std::vector<std::uint32_t>{2, 0, 1}, out));
  EXPECT_EQ(out, (std::vector<Triangle>{{2, 0, 1}}));
}

TEST(TriangulatePolygon, ConcaveStarKeepsAreaAndOrientation) {
  // A 5-pointed star (10 corners, 5 reflex), tilted out of every axis plane, both windings.
  std::vector<Vec3> star;
  for (int i = 0; i < 10; ++i) {
    const double r = i % 2 ? 0.4 : 1.0, a = 2 * M_PI * i / 10;
    const double x = r * std::cos(a), y = r * std::sin(a);
    star.push_back({x, 0.6 * y, 0.8 * y + 0.1 * 0});
  }
  // Exact area from the shoelace formula in the (x, y) parameterisation, scaled by the tilt.
  double area2d = 0;
  for (int i = 0; i < 10; ++i) {
    const double r0 = i % 2 ? 0.4 : 1.0, r1 = (i + 1) % 2 ? 0.4 : 1.0;
    area2d += 0.5 * r0 * r1 * std::sin(2 * M_PI / 10);
  }
  const Vec3 normal{0, -0.8, 0.6};
  for (const bool reversed : {false, true}) {
    std::vector<std::uint32_t> polygon = iota(10);
    if (reversed) std::reverse(polygon.begin(), polygon.end());
    std::vector<Triangle> out;
    EXPECT_TRUE(detail::triangulate_polygon(star, polygon, out));
    ASSERT_EQ(out.size(), 8u);
    double area = 0;
    for (const Triangle& t : out) {
      const double along = dot(triangle_area_vector(star, t), normal);
      EXPECT_GT(reversed ? -along : along, 0);  // same winding as the polygon
      area += reversed ? -along : along;
    }
    EXPECT_NEAR(area, area2d, 1e-12);
    if (!reversed) expect_edges_consistent(out, 10);
  }
}

TEST(TriangulatePolygon, LShapeIsNotFanned) {
  // A fan from corner 0 would put a triangle outside this L; ear clipping must not.
  const std::vector<Vec3> l{{0, 0, 0}, {2, 0, 0}, {2, 1, 0}, {1, 1, 0}, {1, 2, 0}, {0, 2, 0}};
  for (std::uint32_t start = 0; start < 6; ++start) {
    std::vector<std::uint32_t> polygon;
    for (std::uint32_t i = 0; i < 6; ++i) polygon.push_back((start + i) % 6);
    std::vector<Triangle> out;
    EXPECT_TRUE(detail::triangulate_polygon(l, polygon, out));
    ASSERT_EQ(out.size(), 4u);
    double area = 0;
    for (const Triangle& t : out) {
      const double z = triangle_area_vector(l, t).z;
      EXPECT_GT(z, 0);
      area += z;
    }
    EXPECT_DOUBLE_EQ(area, 3.0);
  }
}

TEST(TriangulatePolygon, NonPlanarHexagonKeepsWinding) {
  // A saddle-like hexagon: corners alternately up and down.
  std::vector<Vec3> p;
  for (int i = 0; i < 6; ++i)
    p.push_back({std::cos(M_PI * i / 3), std::sin(M_PI * i / 3), i % 2 ? 0.4 : -0.4});
  std::vector<Triangle> out;
  EXPECT_TRUE(detail::triangulate_polygon(p, iota(6), out));
  ASSERT_EQ(out.size(), 4u);
  for (const Triangle& t : out) EXPECT_GT(triangle_area_vector(p, t).z, 0);
  expect_edges_consistent(out, 6);
}

TEST(TriangulatePolygon, CollinearCornersAreHandled) {
  // A rectangle with extra corners along its edges (CAD T-junctions).
  const std::vector<Vec3> p{{0, 0, 0}, {1, 0, 0}, {2, 0, 0}, {2, 1, 0}, {1, 1, 0}, {0, 1, 0}};
  std::vector<Triangle> out;
  EXPECT_TRUE(detail::triangulate_polygon(p, iota(6), out));
  ASSERT_EQ(out.size(), 4u);
  double area = 0;
  for (const Triangle& t : out) {
    EXPECT_GT(triangle_area_vector(p, t).z, 0);
    area += triangle_area_vector(p, t).z;
  }
  EXPECT_DOUBLE_EQ(area, 2.0);
}

TEST(TriangulatePolygon, DegenerateInputsFallBackToFan) {
  const std::vector<Vec3> p{{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, {2, 2, 2}};
  std::vector<Triangle> out;
  // Repeated index.
  EXPECT_FALSE(detail::triangulate_polygon(p, std::vector<std::uint32_t>{0, 1, 2, 1, 3}, out));
  EXPECT_EQ(out.size(), 3u);
  EXPECT_EQ(out[0], (Triangle{0, 1, 2}));
  // All corners on one line: zero Newell normal.
  const std::vector<Vec3> line{{0, 0, 0}, {1, 0, 0}, {2, 0, 0}, {3, 0, 0}};
  out.clear();
  EXPECT_FALSE(detail::triangulate_polygon(line, iota(4), out));
  EXPECT_EQ(out.size(), 2u);
  // Self-overlapping bow tie.
  const std::vector<Vec3> bow{{0, 0, 0}, {1, 1, 0}, {1, 0, 0}, {0, 1, 0}, {0.5, -1, 0}};
  out.clear();
  detail::triangulate_polygon(bow, iota(5), out);
  EXPECT_EQ(out.size(), 3u);
}

TEST(TriangulatePolygon, LargeConvexPolygonIsFast) {
  std::vector<Vec3> p;
  const std::size_t n = 20000;
  for (std::size_t i = 0; i < n; ++i)
    p.push_back({std::cos(2 * M_PI * i / n), std::sin(2 * M_PI * i / n), 0});
  std::vector<Triangle> out;
  EXPECT_TRUE(detail::triangulate_polygon(p, iota(n), out));
  EXPECT_EQ(out.size(), n - 2);
}
