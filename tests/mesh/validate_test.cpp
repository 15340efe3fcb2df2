// Stage "validate": geometric truths about meshes made in code, and agreement of the cell-grid
// self-intersection search with the general one.
#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <tpmsfill/check.hpp>
#include <tpmsfill/error.hpp>
#include <tpmsfill/mesh/components.hpp>
#include <tpmsfill/mesh/validate.hpp>
#include <tpmsfill/sampling/marching_cubes.hpp>
#include <unordered_map>

#include "mesh/validate_window.hpp"
#include "test_util.hpp"

using namespace tpmsfill;
using test::concat;
using test::flip;

namespace {

bool mentions(const MeshValidity& r, const std::string& words) {
  for (const std::string& p : r.problems())
    if (p.find(words) != std::string::npos) return true;
  return false;
}

void expect_valid(const MeshValidity& r) {
  EXPECT_TRUE(r.valid());
  EXPECT_TRUE(r.problems().empty()) << r.problems().front();
  EXPECT_EQ(r.border_edges, 0u);
  EXPECT_EQ(r.non_manifold_edges, 0u);
  EXPECT_EQ(r.non_manifold_vertices, 0u);
  EXPECT_EQ(r.inconsistent_edges, 0u);
  EXPECT_EQ(r.degenerate_triangles, 0u);
  EXPECT_EQ(r.duplicate_points, 0u);
  EXPECT_EQ(r.self_intersecting_pairs, std::uint64_t{0});
  EXPECT_EQ(r.outward, true);
  EXPECT_TRUE(r.border_edge_examples.empty());
  EXPECT_TRUE(r.non_manifold_edge_examples.empty());
  EXPECT_TRUE(r.inconsistent_edge_examples.empty());
  EXPECT_TRUE(r.non_manifold_vertex_examples.empty());
}

ValidateOptions with_grid(const Grid& grid, std::size_t max_examples = 10) {
  ValidateOptions o;
  o.cell_grid = grid;
  o.max_examples = max_examples;
  return o;
}

ValidateOptions general(std::size_t max_examples = 10) {
  ValidateOptions o;
  o.max_examples = max_examples;
  return o;
}

/// Marching tetrahedra of the solid f < 0 over the Kuhn split of every grid cell into six
/// tetrahedra (the main diagonal in every cell, so neighbours agree on face diagonals).
/// Stands in for marching cubes: every triangle lies in one closed cell, vertices are shared
/// by grid edge (the mesh is indexed, no welding), and the result is a closed 2-manifold
/// without self-intersections (the zero set of a piecewise-linear function), oriented outward,
/// when f > 0 on the grid's boundary nodes and no node has f == 0.
template <class F>
TriangleSoup marching_tetrahedra(const Grid& g, const F& f) {
  const int nx = g.dims[0], ny = g.dims[1], nz = g.dims[2];
  std::vector<double> lower(static_cast<std::size_t>(nx) * ny), upper(lower.size());
  auto layer = [&](int k, std::vector<double>& out) {
    for (int j = 0; j < ny; ++j)
      for (int i = 0; i < nx; ++i) out[i + static_cast<std::size_t>(nx) * j] = f(g.node(i, j, k));
  };
  static constexpr int kPerm[6][2] = {{0, 1}, {0, 2}, {1, 0}, {1, 2}, {2, 0}, {2, 1}};
  std::unordered_map<std::uint64_t, std::uint32_t> vertex_of_edge;
  TriangleSoup s;
  layer(0, lower);
  for (int k = 0; k + 1 < nz; ++k) {
    layer(k + 1, upper);
    for (int j = 0; j + 1 < ny; ++j)
      for (int i = 0; i + 1 < nx; ++i) {
        auto value = [&](const std::array<int, 3>& c) {
          const auto& l = c[2] ? upper : lower;
          return l[(i + c[0]) + static_cast<std::size_t>(nx) * (j + c[1])];
        };
        int negative = 0;
        for (int c = 0; c < 8; ++c) negative += value({c & 1, (c >> 1) & 1, c >> 2}) < 0;
        if (negative == 0 || negative == 8) continue;
        for (const auto& perm : kPerm) {
          // Corners along a monotone path from (0,0,0) to (1,1,1).
          std::array<std::array<int, 3>, 4> c{};
          c[1] = c[0];
          c[1][perm[0]] = 1;
          c[2] = c[1];
          c[2][perm[1]] = 1;
          c[3] = {1, 1, 1};
          std::array<double, 4> v{};
          std::vector<int> in, out;
          for (int q = 0; q < 4; ++q) {
            v[q] = value(c[q]);
            (v[q] < 0 ? in : out).push_back(q);
          }
          if (in.empty() || out.empty()) continue;
          // Edge (a, b) with a < b along the path, so c[a] <= c[b] componentwise.
          auto vertex = [&](int x, int y) {
            const int a = std::min(x, y), b = std::max(x, y);
            const std::uint64_t node = g.index(i + c[a][0], j + c[a][1], k + c[a][2]);
            const int code =
                (c[b][0] - c[a][0]) + 2 * (c[b][1] - c[a][1]) + 4 * (c[b][2] - c[a][2]);
            const auto [it, fresh] = vertex_of_edge.try_emplace(
                node * 8 + code, static_cast<std::uint32_t>(s.points.size()));
            if (fresh) {
              const Vec3 pa = g.node(i + c[a][0], j + c[a][1], k + c[a][2]);
              const Vec3 pb = g.node(i + c[b][0], j + c[b][1], k + c[b][2]);
              s.points.push_back(pa + (v[a] / (v[a] - v[b])) * (pb - pa));
            }
            return it->second;
          };
          std::vector<std::array<std::array<int, 2>, 3>> tris;
          if (in.size() == 1)
            tris.push_back({{{in[0], out[0]}, {in[0], out[1]}, {in[0], out[2]}}});
          else if (in.size() == 3)
            tris.push_back({{{out[0], in[0]}, {out[0], in[1]}, {out[0], in[2]}}});
          else
            tris = {{{{in[0], out[0]}, {in[0], out[1]}, {in[1], out[1]}}},
                    {{{in[0], out[0]}, {in[1], out[1]}, {in[1], out[0]}}}};
          for (auto& t : tris) {
            // Orientation from the edge midpoints (exact in doubled integer coordinates); the
            // sign is the same for every crossing position: inside corner behind the normal.
            std::array<std::array<long, 3>, 3> m{};
            for (int e = 0; e < 3; ++e)
              for (int a = 0; a < 3; ++a) m[e][a] = c[t[e][0]][a] + c[t[e][1]][a];
            std::array<long, 3> u{}, w{}, r{};
            for (int a = 0; a < 3; ++a) {
              u[a] = m[1][a] - m[0][a];
              w[a] = m[2][a] - m[0][a];
              r[a] = 2 * c[in[0]][a] - m[0][a];
            }
            const long det = r[0] * (u[1] * w[2] - u[2] * w[1]) -
                             r[1] * (u[0] * w[2] - u[2] * w[0]) +
                             r[2] * (u[0] * w[1] - u[1] * w[0]);
            if (det > 0) std::swap(t[1], t[2]);
            s.triangles.push_back(
                {vertex(t[0][0], t[0][1]), vertex(t[1][0], t[1][1]), vertex(t[2][0], t[2][1])});
          }
        }
      }
    lower.swap(upper);
  }
  return s;
}

/// A grid around a box, padded so every boundary node is outside. The origin is offset by
/// odd fractions of a cell so that no node lands on a surface centred in the box (a zero
/// sample would make marching tetrahedra emit degenerate triangles and duplicate points).
Grid grid_around(Vec3 min, Vec3 max, double spacing) {
  Grid g;
  g.spacing = spacing;
  g.origin = min - spacing * Vec3{2.0123, 2.0371, 2.0517};
  for (int a = 0; a < 3; ++a)
    g.dims[a] = static_cast<int>(std::ceil((max[a] - min[a]) / spacing)) + 5;
  return g;
}

TriangleSoup tet_sphere(const Grid& g, Vec3 c, double r) {
  return marching_tetrahedra(g, [&](Vec3 p) { return norm(p - c) - r; });
}

}  // namespace

TEST(Validate, SphereIsValid) {
  const TriangleSoup sphere = test::make_sphere({1, 2, 3}, 5.0, 3);
  const MeshValidity r = validate_mesh(sphere);
  expect_valid(r);
  EXPECT_EQ(r.vertices, 642u);
  EXPECT_EQ(r.triangles, 1280u);
  EXPECT_EQ(r.components, 1u);
  EXPECT_NEAR(*r.volume, test::signed_volume(sphere), 1e-9 * test::signed_volume(sphere));
  EXPECT_NEAR(r.area, 4 * std::numbers::pi * 25, 0.02 * 4 * std::numbers::pi * 25);
}

TEST(Validate, TorusIsValidWithItsVolume) {
  const double R = 3, rr = 1;
  const MeshValidity r = validate_mesh(test::make_torus(R, rr, 128, 64));
  expect_valid(r);
  EXPECT_EQ(r.components, 1u);
  const double exact = 2 * std::numbers::pi * std::numbers::pi * R * rr * rr;
  EXPECT_NEAR(*r.volume, exact, 0.01 * exact);  // inscribed polygons lose ~0.2%
  EXPECT_LT(*r.volume, exact);
}

TEST(Validate, BoxIsValidWithExactVolume) {
  const MeshValidity r = validate_mesh(test::make_box({0, 0, 0}, {10, 20, 30}));
  expect_valid(r);
  EXPECT_EQ(r.volume, 6000.0);
  EXPECT_DOUBLE_EQ(r.area, 2 * (10 * 20 + 20 * 30 + 10 * 30));
}

TEST(Validate, BoxWithMissingTriangleHasBorderEdges) {
  TriangleSoup box = test::make_box({0, 0, 0}, {1, 1, 1});
  box.triangles.erase(box.triangles.begin() + 5);
  const MeshValidity r = validate_mesh(box);
  EXPECT_FALSE(r.valid());
  EXPECT_FALSE(r.closed());
  EXPECT_EQ(r.border_edges, 3u);
  ASSERT_EQ(r.border_edge_examples.size(), 3u);
  for (const EdgeLocation& e : r.border_edge_examples) {  // the named triangle walks the edge
    const Triangle& t = box.triangles[e.triangle];
    int walks = 0;
    for (int k = 0; k < 3; ++k)
      walks += box.points[t[k]] == e.ends[0] && box.points[t[(k + 1) % 3]] == e.ends[1];
    EXPECT_EQ(walks, 1);
  }
  EXPECT_EQ(r.inconsistent_edges, 0u);
  EXPECT_TRUE(mentions(r, "3 border edges: the mesh is not closed"));
  const MeshValidity hole = validate_mesh(test::make_box_with_hole({0, 0, 0}, {1, 1, 1}));
  EXPECT_EQ(hole.border_edges, 4u);
}

TEST(Validate, FlippedTriangleGivesInconsistentEdges) {
  const MeshValidity r = validate_mesh(flip(test::make_box({0, 0, 0}, {1, 1, 1}), 3));
  EXPECT_FALSE(r.valid());
  EXPECT_TRUE(r.closed());
  EXPECT_TRUE(r.manifold());
  EXPECT_EQ(r.inconsistent_edges, 3u);
  EXPECT_TRUE(mentions(r, "3 inconsistently oriented edges"));
}

TEST(Validate, WholeMeshFlippedIsNotOutward) {
  const TriangleSoup sphere = test::make_sphere({0, 0, 0}, 2.0, 2);
  const MeshValidity r = validate_mesh(flip(sphere));
  EXPECT_FALSE(r.valid());
  EXPECT_EQ(r.outward, false);
  EXPECT_TRUE(r.closed());
  EXPECT_TRUE(r.manifold());
  EXPECT_EQ(r.inconsistent_edges, 0u);
  EXPECT_LT(*r.volume, 0);
  EXPECT_DOUBLE_EQ(*r.volume, -*validate_mesh(sphere).volume);
  EXPECT_TRUE(mentions(r, "inside out"));
}

TEST(Validate, NestedShellOrientedInwardIsStillOutward) {
  // A hollow ball: the inner shell's normals point into the cavity (negative volume).
  const TriangleSoup hollow =
      concat(test::make_sphere({0, 0, 0}, 3.0, 2), flip(test::make_sphere({0, 0, 0}, 1.0, 2)));
  const MeshValidity r = validate_mesh(hollow);
  expect_valid(r);
  EXPECT_EQ(r.components, 2u);
}

TEST(Validate, OverlappingSpheresIntersectAndAgreeWithCheckMesh) {
  const TriangleSoup two =
      concat(test::make_sphere({0, 0, 0}, 1.0, 3), test::make_sphere({0.7, 0.1, 0.05}, 1.0, 3));
  const MeshValidity r = validate_mesh(two, general(1000000));
  ASSERT_TRUE(r.self_intersecting_pairs);
  EXPECT_GT(*r.self_intersecting_pairs, 0u);
  EXPECT_FALSE(r.valid());
  EXPECT_EQ(r.components, 2u);
  EXPECT_TRUE(mentions(r, "self-intersecting triangle pairs"));
  const std::uint32_t n = 1280;  // triangles of the first sphere
  EXPECT_TRUE(
      std::is_sorted(r.self_intersection_examples.begin(), r.self_intersection_examples.end()));
  for (const auto& [i, j] : r.self_intersection_examples) {
    EXPECT_LT(i, n);
    EXPECT_GE(j, n);
  }
  // check_mesh answers with CGAL's PMP::self_intersections on the same mesh.
  CheckOptions co;
  co.max_examples = 1000000;
  const MeshCheck c = check_mesh(two, co);
  EXPECT_EQ(c.self_intersecting_pairs, r.self_intersecting_pairs);
  EXPECT_EQ(c.self_intersection_examples, r.self_intersection_examples);
  // Examples are capped, the count is not.
  const MeshValidity capped = validate_mesh(two);
  EXPECT_EQ(capped.self_intersecting_pairs, r.self_intersecting_pairs);
  ASSERT_EQ(capped.self_intersection_examples.size(), 10u);
  EXPECT_TRUE(std::equal(capped.self_intersection_examples.begin(),
                         capped.self_intersection_examples.end(),
                         r.self_intersection_examples.begin()));
}

TEST(Validate, SharedEdgePairsCountOnlyWhenFoldedOver) {
  // Triangle 0 and a second triangle on its edge (0, 1); coplanar on the other side is a
  // normal neighbour, coplanar on the same side overlaps, bent out of the plane does not.
  const Vec3 a{0, 0, 0}, b{1, 0, 0}, c{0, 1, 0};
  auto pair_with = [&](Vec3 d) {
    TriangleSoup s;
    s.points = {a, b, c, d};
    s.triangles = {{0, 1, 2}, {1, 0, 3}};
    return s;
  };
  Grid one_cell;
  one_cell.origin = {-5, -5, -5};
  one_cell.spacing = 10;
  one_cell.dims = {2, 2, 2};
  for (const ValidateOptions& o : {general(), with_grid(one_cell)}) {
    EXPECT_EQ(validate_mesh(pair_with({0.5, -1, 0}), o).self_intersecting_pairs, 0u);
    EXPECT_EQ(validate_mesh(pair_with({0.5, 0.5, 1}), o).self_intersecting_pairs, 0u);
    const MeshValidity folded = validate_mesh(pair_with({0.25, 0.5, 0}), o);
    EXPECT_EQ(folded.self_intersecting_pairs, 1u);
    EXPECT_EQ(folded.searched_by_cells, o.cell_grid.has_value());
    EXPECT_EQ(folded.self_intersection_examples,
              (std::vector<std::array<std::uint32_t, 2>>{{0, 1}}));
  }
}

TEST(Validate, SharedVertexPairsCountOnlyWhenTheyMeetElsewhere) {
  auto pair_with = [](Vec3 d, Vec3 e) {
    TriangleSoup s;
    s.points = {{0, 0, 0}, {2, 0, 0}, {0, 2, 0}, d, e};
    s.triangles = {{0, 1, 2}, {0, 3, 4}};
    return s;
  };
  Grid one_cell;
  one_cell.origin = {-5, -5, -5};
  one_cell.spacing = 10;
  one_cell.dims = {2, 2, 2};
  for (const ValidateOptions& o : {general(), with_grid(one_cell)}) {
    // The second triangle's far edge pierces the first.
    EXPECT_EQ(validate_mesh(pair_with({0.5, 0.5, -1}, {0.5, 0.5, 1}), o).self_intersecting_pairs,
              1u);
    // Only the corner in common.
    EXPECT_EQ(validate_mesh(pair_with({-1, -1, 1}, {-1, 0, 1}), o).self_intersecting_pairs, 0u);
    // Coplanar, overlapping wedges.
    EXPECT_EQ(validate_mesh(pair_with({1, 0.2, 0}, {0.2, 1, 0}), o).self_intersecting_pairs, 1u);
  }
}

TEST(Validate, BowTieHasANonManifoldVertex) {
  const MeshValidity r = validate_mesh(test::make_bow_tie());
  EXPECT_FALSE(r.valid());
  EXPECT_TRUE(r.closed());
  EXPECT_EQ(r.non_manifold_edges, 0u);
  EXPECT_EQ(r.non_manifold_vertices, 1u);
  EXPECT_FALSE(r.manifold());
  EXPECT_EQ(r.components, 1u);
  EXPECT_TRUE(mentions(r, "1 non-manifold vertex"));
}

TEST(Validate, EdgeOfThreeTrianglesIsNonManifold) {
  TriangleSoup s;
  s.points = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}};
  s.triangles = {{0, 1, 2}, {1, 0, 3}, {0, 1, 4}};
  const MeshValidity r = validate_mesh(s);
  EXPECT_EQ(r.non_manifold_edges, 1u);
  EXPECT_EQ(r.border_edges, 6u);
  ASSERT_EQ(r.non_manifold_edge_examples.size(), 1u);
  // Walked as its lowest-index triangle, 0, walks it.
  EXPECT_EQ(r.non_manifold_edge_examples[0].ends,
            (std::array<Vec3, 2>{Vec3{0, 0, 0}, Vec3{1, 0, 0}}));
  EXPECT_EQ(r.non_manifold_edge_examples[0].triangle, 0u);
}

TEST(Validate, DuplicatePointsAreFlagged) {
  TriangleSoup sphere = test::make_sphere({0, 0, 0}, 1.0, 2);
  // An unreferenced copy is harmless.
  TriangleSoup extra = sphere;
  extra.points.push_back(sphere.points[5]);
  expect_valid(validate_mesh(extra));
  // A referenced copy: the mesh is torn at that point.
  TriangleSoup torn = sphere;
  torn.points.push_back(sphere.points[torn.triangles[0][0]]);
  torn.triangles[0][0] = static_cast<std::uint32_t>(torn.points.size() - 1);
  const MeshValidity r = validate_mesh(torn);
  EXPECT_EQ(r.duplicate_points, 1u);
  EXPECT_EQ(r.border_edges, 4u);
  EXPECT_FALSE(r.valid());
  EXPECT_TRUE(mentions(r, "1 duplicate point"));
  // -0.0 and +0.0 are the same position.
  TriangleSoup zero;
  zero.points = {{0.0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {-0.0, 0, 0}, {0, 0, 1}};
  zero.triangles = {{0, 1, 2}, {3, 2, 4}};
  EXPECT_EQ(validate_mesh(zero).duplicate_points, 1u);
}

TEST(Validate, DegenerateTrianglesAreFlagged) {
  TriangleSoup s = test::make_box({0, 0, 0}, {1, 1, 1});
  s.points.push_back({0.5, 0, 0});  // on the edge (0,0,0)-(1,0,0)
  const auto mid = static_cast<std::uint32_t>(s.points.size() - 1);
  s.triangles.push_back({0, 0, 1});  // repeated corner
  // Find the box's points at (0,0,0) and (1,0,0).
  std::uint32_t p0 = 0, p1 = 0;
  for (std::uint32_t i = 0; i < 8; ++i) {
    if (s.points[i] == Vec3{0, 0, 0}) p0 = i;
    if (s.points[i] == Vec3{1, 0, 0}) p1 = i;
  }
  s.triangles.push_back({p0, mid, p1});  // collinear
  const MeshValidity r = validate_mesh(s);
  EXPECT_EQ(r.degenerate_triangles, 2u);
  EXPECT_EQ(r.degenerate_triangle_examples, (std::vector<std::uint32_t>{12, 13}));
  EXPECT_TRUE(mentions(r, "2 degenerate triangles"));
}

TEST(Validate, EmptyMeshAndBadIndices) {
  const MeshValidity r = validate_mesh(TriangleSoup{});
  EXPECT_FALSE(r.valid());
  EXPECT_TRUE(mentions(r, "no triangles"));
  TriangleSoup bad;
  bad.points = {{0, 0, 0}};
  bad.triangles = {{0, 0, 1}};
  EXPECT_THROW(validate_mesh(bad), InputError);
  EXPECT_THROW(mesh_components(bad), InputError);
}

TEST(Validate, ProgressCanCancel) {
  struct Stop : Progress {
    bool report(double) override { return false; }
  } stop;
  ValidateOptions o;
  o.progress = &stop;
  EXPECT_THROW(validate_mesh(test::make_sphere({0, 0, 0}, 1, 4), o), Cancelled);
}

TEST(Validate, NotSearchingLeavesSelfIntersectionsUnset) {
  ValidateOptions o;
  o.self_intersections = false;
  const TriangleSoup two =
      concat(test::make_sphere({0, 0, 0}, 1.0, 2), test::make_sphere({0.5, 0, 0}, 1.0, 2));
  const MeshValidity r = validate_mesh(two, o);
  EXPECT_FALSE(r.self_intersecting_pairs.has_value());
  EXPECT_TRUE(r.valid());  // unsearched self-intersections count as none
}

// --- the cell-grid search ------------------------------------------------------------------

TEST(Validate, CellGridFindsExactlyTheCraftedPairs) {
  Grid g;
  g.origin = {0, 0, 0};
  g.spacing = 1;
  g.dims = {10, 10, 10};
  TriangleSoup s;
  auto add = [&](Vec3 a, Vec3 b, Vec3 c) {
    const auto n = static_cast<std::uint32_t>(s.points.size());
    s.points.insert(s.points.end(), {a, b, c});
    s.triangles.push_back({n, n + 1, n + 2});
  };
  // 0, 1: face-adjacent cells (0,0,0) and (1,0,0); 0's corner touches 1, which lies in the
  // plane x = 1 (its centroid is on the cell face).
  add({0.2, 0.5, 0.2}, {1.0, 0.5, 0.5}, {0.2, 0.5, 0.8});
  add({1, 0.2, 0.2}, {1, 0.8, 0.2}, {1, 0.5, 0.9});
  // 2, 3: edge-adjacent cells (3,0,0) and (4,1,0), meeting on the cells' common edge.
  add({3.5, 0.5, 0.3}, {4.0, 1.0, 0.5}, {3.5, 0.5, 0.7});
  add({4, 1, 0.2}, {4.5, 1.5, 0.5}, {4, 1, 0.8});
  // 4, 5: two cells apart, parallel, close but apart.
  add({6.1, 0.1, 0.1}, {6.9, 0.1, 0.1}, {6.5, 0.9, 0.1});
  add({8.1, 0.1, 0.1}, {8.9, 0.1, 0.1}, {8.5, 0.9, 0.1});
  // 6, 7: the same cell, crossing.
  add({0.1, 5.1, 5.5}, {0.9, 5.1, 5.5}, {0.5, 5.9, 5.5});
  add({0.5, 5.5, 5.1}, {0.5, 5.2, 5.9}, {0.5, 5.8, 5.9});
  // 8, 9: diagonally adjacent cells (0,8,8) and (1,9,9), boxes touching, triangles apart.
  add({0.1, 8.1, 8.9}, {1.0, 9.0, 9.0}, {0.1, 8.9, 8.9});
  add({1.0, 9.2, 9.0}, {1.9, 9.0, 9.9}, {1.9, 9.5, 9.9});
  const std::vector<std::array<std::uint32_t, 2>> expected{{0, 1}, {2, 3}, {6, 7}};
  const MeshValidity cells = validate_mesh(s, with_grid(g));
  const MeshValidity all = validate_mesh(s, general());
  EXPECT_EQ(cells.self_intersecting_pairs, 3u);
  EXPECT_TRUE(cells.searched_by_cells);
  EXPECT_FALSE(all.searched_by_cells);
  EXPECT_EQ(cells.self_intersection_examples, expected);
  EXPECT_EQ(all.self_intersection_examples, expected);
  // A triangle spanning several cells breaks the promise: the general search takes over.
  add({0.5, 5.5, 5.5}, {2.5, 5.5, 5.5}, {0.5, 7.5, 5.5});  // 10: crosses 7, touches 6's plane
  const MeshValidity broken = validate_mesh(s, with_grid(g));
  EXPECT_EQ(broken.self_intersection_examples,
            validate_mesh(s, general()).self_intersection_examples);
  EXPECT_GT(*broken.self_intersecting_pairs, 3u);
  EXPECT_FALSE(broken.searched_by_cells);
}

TEST(Validate, MarchingTetrahedraSphereIsValidOnBothPaths) {
  const Vec3 c{0.13, -0.21, 0.37};
  const double radius = 6.3;
  const Grid g =
      grid_around(c - Vec3{radius, radius, radius}, c + Vec3{radius, radius, radius}, 0.5);
  const TriangleSoup sphere = tet_sphere(g, c, radius);
  ASSERT_GT(sphere.triangles.size(), 10000u);
  const MeshValidity cells = validate_mesh(sphere, with_grid(g));
  expect_valid(cells);
  EXPECT_TRUE(cells.searched_by_cells);
  EXPECT_EQ(cells.components, 1u);
  const double exact = 4.0 / 3.0 * std::numbers::pi * radius * radius * radius;
  EXPECT_NEAR(*cells.volume, exact, 0.01 * exact);
  const MeshValidity all = validate_mesh(sphere, general());
  expect_valid(all);
  EXPECT_EQ(all.volume, cells.volume);
}

TEST(Validate, MarchingTetrahedraGyroidBallIsValid) {
  // A gyroid network clipped to a ball: many components touching the grid diagonals.
  const Grid g = grid_around({-6, -6, -6}, {6, 6, 6}, 0.25);
  const TriangleSoup lattice = marching_tetrahedra(g, [](Vec3 p) {
    const double k = 2 * std::numbers::pi / 4.0;
    const double gyroid = std::cos(k * p.x) * std::sin(k * p.y) +
                          std::cos(k * p.y) * std::sin(k * p.z) +
                          std::cos(k * p.z) * std::sin(k * p.x) + 0.3;
    return std::max(norm(p - Vec3{0.01, 0.02, 0.03}) - 5.0, gyroid / k);
  });
  ASSERT_GT(lattice.triangles.size(), 50000u);
  const MeshValidity cells = validate_mesh(lattice, with_grid(g));
  expect_valid(cells);
  EXPECT_TRUE(cells.searched_by_cells);
  const MeshValidity all = validate_mesh(lattice, general());
  EXPECT_EQ(all.self_intersecting_pairs, std::uint64_t{0});
  // What check_mesh says about the same mesh.
  const MeshCheck c = check_mesh(lattice);
  EXPECT_TRUE(c.valid()) << (c.problems().empty() ? "" : c.problems().front());
  EXPECT_EQ(c.components, cells.components);
}

TEST(Validate, CellGridAgreesWithGeneralSearchOnOverlappingSpheres) {
  const Grid g = grid_around({-5, -5, -5}, {7, 5, 5}, 0.5);
  const TriangleSoup two =
      concat(tet_sphere(g, {0.11, 0.07, 0.03}, 4.2), tet_sphere(g, {2.71, 0.33, -0.19}, 3.7));
  const MeshValidity cells = validate_mesh(two, with_grid(g, 1000000));
  const MeshValidity all = validate_mesh(two, general(1000000));
  ASSERT_TRUE(cells.self_intersecting_pairs);
  EXPECT_GT(*cells.self_intersecting_pairs, 100u);
  EXPECT_EQ(cells.self_intersecting_pairs, all.self_intersecting_pairs);
  EXPECT_EQ(cells.self_intersection_examples, all.self_intersection_examples);
  EXPECT_EQ(cells.components, 2u);
  EXPECT_TRUE(cells.searched_by_cells);
}

// --- components ----------------------------------------------------------------------------

TEST(Validate, ComponentsOfTwoSpheres) {
  const TriangleSoup small = test::make_sphere({0, 0, 0}, 1.0, 2);
  const TriangleSoup big = test::make_sphere({10, 0, 0}, 2.0, 3);
  const TriangleSoup both = concat(small, big);
  const Components c = mesh_components(both);
  ASSERT_EQ(c.info.size(), 2u);
  EXPECT_EQ(c.info[0].triangles, small.triangles.size());
  EXPECT_EQ(c.info[1].triangles, big.triangles.size());
  EXPECT_EQ(c.info[0].first_triangle, 0u);
  EXPECT_EQ(c.info[1].first_triangle, small.triangles.size());
  EXPECT_NEAR(c.info[0].volume, test::signed_volume(small), 1e-9);
  EXPECT_NEAR(c.info[1].volume, test::signed_volume(big), 1e-8);
  EXPECT_NEAR(c.info[0].area + c.info[1].area, validate_mesh(both).area, 1e-9);
  for (std::size_t t = 0; t < both.triangles.size(); ++t)
    EXPECT_EQ(c.triangle_component[t], t < small.triangles.size() ? 0u : 1u);

  const TriangleSoup only_big = keep_components(both, c, {false, true});
  EXPECT_EQ(only_big.points, big.points);
  EXPECT_EQ(only_big.triangles, big.triangles);
  const TriangleSoup only_small = keep_components(both, c, {true, false});
  EXPECT_EQ(only_small.points, small.points);
  EXPECT_EQ(only_small.triangles, small.triangles);
  const TriangleSoup all = keep_components(both, c, {true, true});
  EXPECT_EQ(all.triangles, both.triangles);
  EXPECT_THROW(keep_components(both, c, {true}), InputError);
}

TEST(Validate, ComponentsNumberedByFirstTriangle) {
  // Interleave two boxes' triangles: numbering follows the first triangle of each.
  const TriangleSoup a = test::make_box({0, 0, 0}, {1, 1, 1});
  const TriangleSoup b = test::make_box({5, 0, 0}, {6, 1, 1});
  TriangleSoup mixed = concat(b, a);                   // points of b first
  std::swap(mixed.triangles[0], mixed.triangles[12]);  // triangle 0 now belongs to a
  const Components c = mesh_components(mixed);
  ASSERT_EQ(c.info.size(), 2u);
  EXPECT_EQ(c.triangle_component[0], 0u);
  EXPECT_EQ(c.triangle_component[1], 1u);
  EXPECT_DOUBLE_EQ(c.info[0].volume, 1.0);
  EXPECT_EQ(c.info[1].first_triangle, 1u);
  // Keeping component 0 (box a) keeps a's points in their relative order.
  const TriangleSoup kept = keep_components(mixed, c, {true, false});
  EXPECT_EQ(kept.points, a.points);
  EXPECT_EQ(kept.triangles.size(), 12u);
  expect_valid(validate_mesh(kept));
}

// --- determinism ---------------------------------------------------------------------------

TEST(Validate, SameReportAtOneAndTwoThreads) {
  const Grid g = grid_around({-5, -5, -5}, {7, 5, 5}, 0.4);
  const TriangleSoup two =
      concat(tet_sphere(g, {0.11, 0.07, 0.03}, 4.2), tet_sphere(g, {2.71, 0.33, -0.19}, 3.7));
  auto run = [&](int threads, const ValidateOptions& o) {
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism, threads);
    return validate_mesh(two, o);
  };
  for (const ValidateOptions& o : {with_grid(g, 50), general(50)}) {
    const MeshValidity one = run(1, o), many = run(2, o);
    EXPECT_EQ(one.volume, many.volume);
    EXPECT_EQ(one.area, many.area);
    EXPECT_EQ(one.self_intersecting_pairs, many.self_intersecting_pairs);
    EXPECT_EQ(one.self_intersection_examples, many.self_intersection_examples);
    EXPECT_EQ(one.components, many.components);
    EXPECT_EQ(one.border_edge_examples, many.border_edge_examples);
    EXPECT_EQ(one.non_manifold_edge_examples, many.non_manifold_edge_examples);
    EXPECT_EQ(one.inconsistent_edge_examples, many.inconsistent_edge_examples);
    EXPECT_EQ(one.non_manifold_vertex_examples, many.non_manifold_vertex_examples);
  }
}

// --- timing (printed, not asserted): --gtest_also_run_disabled_tests -------------------------

namespace {
using Clock = std::chrono::steady_clock;
double ms(Clock::time_point a, Clock::time_point b) {
  return std::chrono::duration<double, std::milli>(b - a).count();
}
/// About 10^6 triangles, each in one cell of `grid` (spacing 1).
TriangleSoup million_triangle_sphere(Grid& grid) {
  const Vec3 c{0.13, -0.21, 0.37};
  const double radius = 95;
  grid = grid_around(c - Vec3{radius, radius, radius}, c + Vec3{radius, radius, radius}, 1.0);
  const auto t0 = Clock::now();
  TriangleSoup sphere = tet_sphere(grid, c, radius);
  std::printf("marching-tetrahedra sphere: %zu triangles, %zu points (%.0f ms to make)\n",
              sphere.triangles.size(), sphere.points.size(), ms(t0, Clock::now()));
  return sphere;
}
}  // namespace

TEST(Validate, DISABLED_TimingCellGrid) {
  Grid g;
  const TriangleSoup sphere = million_triangle_sphere(g);
  ValidateOptions topology_only;
  topology_only.self_intersections = false;
  for (int round = 0; round < 3; ++round) {
    auto t0 = Clock::now();
    const MeshValidity top = validate_mesh(sphere, topology_only);
    auto t1 = Clock::now();
    const MeshValidity cells = validate_mesh(sphere, with_grid(g));
    auto t2 = Clock::now();
    std::printf(
        "validate without SI: %.0f ms; with cell-grid SI: %.0f ms (valid %d, by cells %d)\n",
        ms(t0, t1), ms(t1, t2), cells.valid(), cells.searched_by_cells);
    (void)top;
  }
}

TEST(Validate, DISABLED_TimingGeneral) {
  Grid g;
  const TriangleSoup sphere = million_triangle_sphere(g);
  auto t0 = Clock::now();
  const MeshValidity all = validate_mesh(sphere, general());
  auto t1 = Clock::now();
  std::printf("same mesh, general SI: %.0f ms (valid %d)\n", ms(t0, t1), all.valid());
  const TriangleSoup ico = test::make_sphere({0, 0, 0}, 1, 8);
  t0 = Clock::now();
  const MeshValidity r8 = validate_mesh(ico);
  t1 = Clock::now();
  std::printf("make_sphere level 8 (%zu triangles), general SI: %.0f ms (valid %d)\n",
              ico.triangles.size(), ms(t0, t1), r8.valid());
}

// validate_window, as fill_to_file uses it: records of a few cell layers of a marching-cubes
// mesh, each validated with the last cell layer of the record below and the first node layer
// of the one above. Whatever defects the mesh has, the windows' counts add up to
// validate_mesh's on the whole mesh.
TEST(ValidateWindow, WindowsAddUpToTheWholeMesh) {
  const Grid grid{{-1, -1, -1}, 0.1, {21, 19, 25}};
  const Field f = test::wavy_field(grid);
  SlabMarchingCubes mc(grid);
  TriangleSoup mesh;
  mc.add(f, 25, mesh);
  const std::size_t nt = mesh.triangles.size();
  ASSERT_GT(nt, 1000u);
  // Defects that keep every triangle in its cell layer: dropped triangles (border edges), one
  // turned over (inconsistent edges, and not outward), two doubled (non-manifold edges), and
  // points moved onto others of their node layer (duplicates, degenerate triangles,
  // intersections; their triangles stay within their cell layers, as windows need).
  std::vector<Triangle> tris = mesh.triangles;
  std::vector<bool> keep(nt, true);
  keep[nt / 3] = keep[nt / 2] = false;
  std::swap(tris[nt / 5][0], tris[nt / 5][1]);
  const std::uint64_t mid_layer = mc.first_point(12), next_layer = mc.first_point(13);
  mesh.points[mid_layer + 7] = mesh.points[mid_layer + 3];
  mesh.points[next_layer + 2] = mesh.points[next_layer + 11];
  std::vector<std::uint32_t> layer_of(nt);  // each triangle's cell layer
  for (int k = 0; k + 1 < 25; ++k)
    for (std::uint64_t t = mc.first_triangle(k); t < mc.first_triangle(k + 1); ++t)
      layer_of[t] = static_cast<std::uint32_t>(k);
  // Doubled triangles go at the end of their layer, where marching cubes would have put them.
  for (std::size_t t : {nt / 4, 2 * nt / 3}) {
    const std::uint32_t k = layer_of[t];
    const auto at = static_cast<std::ptrdiff_t>(mc.first_triangle(static_cast<int>(k) + 1));
    tris.insert(tris.begin() + at, tris[t]);
    keep.insert(keep.begin() + at, true);
    layer_of.insert(layer_of.begin() + at, k);
  }
  std::vector<std::uint64_t> layer_start(26, tris.size());  // first triangle of each cell layer
  for (std::size_t t = tris.size(); t-- > 0;) layer_start[layer_of[t]] = t;
  for (int k = 24; k >= 0; --k) layer_start[k] = std::min(layer_start[k], layer_start[k + 1]);

  TriangleSoup whole{mesh.points, {}};
  for (std::size_t t = 0; t < tris.size(); ++t)
    if (keep[t]) whole.triangles.push_back(tris[t]);
  const MeshValidity expected = validate_mesh(whole, {.cell_grid = grid});
  ASSERT_GT(expected.border_edges, 0u);
  ASSERT_GT(expected.non_manifold_edges, 0u);
  ASSERT_GT(expected.inconsistent_edges, 0u);
  ASSERT_GT(expected.duplicate_points, 0u);
  ASSERT_GT(expected.self_intersecting_pairs.value_or(0), 0u);

  for (int per : {1, 3, 7}) {
    SCOPED_TRACE("records of " + std::to_string(per) + " cell layers");
    detail::WindowValidation sum;
    std::uint64_t pairs = 0, degenerate = 0, vertices = 0;
    for (int r0 = 0; r0 < 24; r0 += per) {
      const int r1 = std::min(r0 + per, 24);
      const bool last = r1 == 24;
      const std::uint64_t first = mc.first_point(std::max(r0 - 1, 0));
      const std::uint64_t end = mc.first_point(last ? 25 : r1 + 1);
      TriangleSoup window;
      window.points.assign(mesh.points.begin() + static_cast<std::ptrdiff_t>(first),
                           mesh.points.begin() + static_cast<std::ptrdiff_t>(end));
      auto add = [&](std::uint64_t b, std::uint64_t e) {
        for (std::uint64_t t = b; t < e; ++t)
          if (keep[t])
            window.triangles.push_back({static_cast<std::uint32_t>(tris[t][0] - first),
                                        static_cast<std::uint32_t>(tris[t][1] - first),
                                        static_cast<std::uint32_t>(tris[t][2] - first)});
      };
      if (r0 > 0) add(layer_start[r0 - 1], layer_start[r0]);
      const std::size_t carried = window.triangles.size();
      add(layer_start[r0], layer_start[r1]);
      const std::uint64_t owned_end = mc.first_point(last ? 25 : r1);
      const detail::WindowValidation w = detail::validate_window(
          window, {mc.first_point(r0) - first, owned_end - first}, carried, grid, 10, true);
      vertices += w.vertices;
      degenerate += w.degenerate;
      pairs += w.intersecting_pairs;
      sum.border += w.border;
      sum.non_manifold += w.non_manifold;
      sum.inconsistent += w.inconsistent;
      sum.pinched += w.pinched;
      sum.duplicates += w.duplicates;
      // Each example edge names a window triangle that walks it as its ends say.
      for (const auto* examples :
           {&w.border_examples, &w.non_manifold_examples, &w.inconsistent_examples})
        for (const EdgeLocation& e : *examples) {
          ASSERT_LT(e.triangle, window.triangles.size());
          const Triangle& t = window.triangles[e.triangle];
          int walks = 0;
          for (int k = 0; k < 3; ++k)
            walks += window.points[t[k]] == e.ends[0] && window.points[t[(k + 1) % 3]] == e.ends[1];
          EXPECT_GE(walks, 1);
        }
    }
    EXPECT_EQ(vertices, expected.vertices);
    EXPECT_EQ(degenerate, expected.degenerate_triangles);
    EXPECT_EQ(sum.border, expected.border_edges);
    EXPECT_EQ(sum.non_manifold, expected.non_manifold_edges);
    EXPECT_EQ(sum.inconsistent, expected.inconsistent_edges);
    EXPECT_EQ(sum.pinched, expected.non_manifold_vertices);
    EXPECT_EQ(sum.duplicates, expected.duplicate_points);
    EXPECT_EQ(pairs, *expected.self_intersecting_pairs);
  }
}
