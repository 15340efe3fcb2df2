// Marching cubes: every corner configuration, random fields, analytic shapes. The checks are
// geometric truths (closed, manifold, oriented, volume, Euler characteristic, no triangle
// crossing a cube face), never stored outputs.
#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <algorithm>
#include <bit>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <functional>
#include <map>
#include <numeric>
#include <random>
#include <set>
#include <tpmsfill/error.hpp>
#include <tpmsfill/field.hpp>
#include <tpmsfill/mesh/components.hpp>
#include <tpmsfill/mesh/validate.hpp>
#include <tpmsfill/sampling/marching_cubes.hpp>

#include "mesh/internal/self_intersections.hpp"
#include "sampling/mc_tables.hpp"
#include "test_util.hpp"

using namespace tpmsfill;

namespace {

constexpr double kPi = 3.14159265358979323846;

Field sample(Grid grid, const std::function<double(Vec3)>& f) {
  Field field{grid, std::vector<float>(grid.node_count())};
  for (int k = 0; k < grid.dims[2]; ++k)
    for (int j = 0; j < grid.dims[1]; ++j)
      for (int i = 0; i < grid.dims[0]; ++i)
        field.values[grid.index(i, j, k)] = static_cast<float>(f(grid.node(i, j, k)));
  return field;
}

// Nodes on the grid's six faces set outside, as the guarantees require.
void force_border_outside(Field& field, float value = 1.0f) {
  const auto& d = field.grid.dims;
  for (int k = 0; k < d[2]; ++k)
    for (int j = 0; j < d[1]; ++j)
      for (int i = 0; i < d[0]; ++i)
        if (i == 0 || j == 0 || k == 0 || i == d[0] - 1 || j == d[1] - 1 || k == d[2] - 1)
          field.values[field.grid.index(i, j, k)] = value;
}

struct Topology {
  long vertices = 0, edges = 0, faces = 0, components = 0;
  long euler() const { return vertices - edges + faces; }
};

// Closed (each undirected edge in exactly two triangles), consistently oriented (each directed
// edge once), manifold at vertices (one cycle of triangles around each), every point used,
// no degenerate triangle. Returns V, E, F and the number of connected components.
Topology check_closed_manifold(const TriangleSoup& s, const std::string& what) {
  Topology topo;
  const std::size_t n = s.points.size();
  std::map<std::pair<std::uint32_t, std::uint32_t>, int> directed;
  std::vector<std::map<std::uint32_t, std::uint32_t>> around(n);  // v: b -> c for triangle v,b,c
  std::vector<std::uint32_t> parent(n);
  std::iota(parent.begin(), parent.end(), 0u);
  std::function<std::uint32_t(std::uint32_t)> find = [&](std::uint32_t x) {
    return parent[x] == x ? x : parent[x] = find(parent[x]);
  };
  for (const Triangle& t : s.triangles) {
    EXPECT_TRUE(t[0] != t[1] && t[1] != t[2] && t[0] != t[2]) << what << ": repeated index";
    const Vec3 c = cross(s.points[t[1]] - s.points[t[0]], s.points[t[2]] - s.points[t[0]]);
    EXPECT_GT(norm(c), 0.0) << what << ": collinear triangle";
    for (int i = 0; i < 3; ++i) {
      const std::uint32_t a = t[i], b = t[(i + 1) % 3], d = t[(i + 2) % 3];
      EXPECT_EQ(++directed[std::make_pair(a, b)], 1) << what << ": directed edge used twice";
      EXPECT_TRUE(around[a].emplace(b, d).second) << what << ": non-manifold at vertex";
      parent[find(a)] = find(b);
    }
  }
  for (const auto& [e, count] : directed) {
    EXPECT_EQ(directed.count({e.second, e.first}), 1u) << what << ": open edge";
    if (e.first < e.second) ++topo.edges;
  }
  for (std::size_t v = 0; v < n; ++v) {
    EXPECT_FALSE(around[v].empty()) << what << ": unused point " << v;
    if (around[v].empty()) continue;
    // Follow b -> c: must return to the start after visiting every triangle at v.
    std::uint32_t b = around[v].begin()->first;
    std::size_t steps = 0;
    do {
      auto it = around[v].find(b);
      if (it == around[v].end()) break;
      b = it->second;
      ++steps;
    } while (b != around[v].begin()->first && steps <= around[v].size());
    EXPECT_EQ(steps, around[v].size()) << what << ": vertex " << v << " is not one fan";
    if (find(static_cast<std::uint32_t>(v)) == v) ++topo.components;
  }
  topo.vertices = static_cast<long>(n);
  topo.faces = static_cast<long>(s.triangles.size());
  return topo;
}

double area(const TriangleSoup& s) {
  double a = 0;
  for (const Triangle& t : s.triangles)
    a += 0.5 * norm(cross(s.points[t[1]] - s.points[t[0]], s.points[t[2]] - s.points[t[0]]));
  return a;
}

// Separating-axis test for two triangles that share no vertex: true when some axis among the
// two normals and the nine edge-edge cross products separates them strictly.
bool separated(const std::array<Vec3, 3>& a, const std::array<Vec3, 3>& b) {
  std::vector<Vec3> axes = {cross(a[1] - a[0], a[2] - a[0]), cross(b[1] - b[0], b[2] - b[0])};
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) axes.push_back(cross(a[(i + 1) % 3] - a[i], b[(j + 1) % 3] - b[j]));
  for (const Vec3& n : axes) {
    if (norm(n) == 0) continue;
    double amin = 1e300, amax = -1e300, bmin = 1e300, bmax = -1e300;
    for (const Vec3& p : a) amin = std::min(amin, dot(n, p)), amax = std::max(amax, dot(n, p));
    for (const Vec3& p : b) bmin = std::min(bmin, dot(n, p)), bmax = std::max(bmax, dot(n, p));
    if (amax < bmin || bmax < amin) return true;
  }
  return false;
}

// Structural non-intersection, per cube: every triangle lies in one closed cube; no triangle
// has its three corners on one cube face; a triangle edge lying in a cube face is also an edge
// of a triangle in the neighbouring cube across that face (a shared face segment); triangles of
// one cube that belong to different pieces (no shared vertex path) do not intersect.
void check_cubes(const TriangleSoup& s, const Grid& g, const std::string& what) {
  const double a = g.spacing;
  std::map<std::array<int, 3>, std::vector<std::size_t>> by_cube;
  std::vector<std::array<int, 3>> cube_of(s.triangles.size());
  for (std::size_t t = 0; t < s.triangles.size(); ++t) {
    const auto& tri = s.triangles[t];
    const Vec3 c = (1.0 / 3) * (s.points[tri[0]] + s.points[tri[1]] + s.points[tri[2]]);
    std::array<int, 3> cube;
    for (int ax = 0; ax < 3; ++ax)
      cube[ax] = static_cast<int>(std::floor((c[ax] - g.origin[ax]) / a));
    cube_of[t] = cube;
    by_cube[cube].push_back(t);
    // In the closed cube, and count corners on each of its faces.
    int on_face[6] = {};
    for (std::uint32_t v : tri)
      for (int ax = 0; ax < 3; ++ax) {
        const double lo = g.coordinate(ax, cube[ax]), hi = g.coordinate(ax, cube[ax] + 1);
        ASSERT_TRUE(s.points[v][ax] >= lo && s.points[v][ax] <= hi) << what << ": outside cube";
        on_face[2 * ax] += s.points[v][ax] == lo;
        on_face[2 * ax + 1] += s.points[v][ax] == hi;
      }
    for (int f = 0; f < 6; ++f) EXPECT_LT(on_face[f], 3) << what << ": triangle in a face";
  }
  std::map<std::pair<std::uint32_t, std::uint32_t>, std::vector<std::size_t>> edge_tris;
  for (std::size_t t = 0; t < s.triangles.size(); ++t)
    for (int i = 0; i < 3; ++i) {
      auto e = std::minmax(s.triangles[t][i], s.triangles[t][(i + 1) % 3]);
      edge_tris[{e.first, e.second}].push_back(t);
    }
  for (const auto& [e, tris] : edge_tris) {
    const auto& cube = cube_of[tris[0]];
    for (int ax = 0; ax < 3; ++ax)
      for (int side = 0; side < 2; ++side) {
        const double plane = g.coordinate(ax, cube[ax] + side);
        if (s.points[e.first][ax] != plane || s.points[e.second][ax] != plane) continue;
        // In a face: the other triangle must be across it.
        ASSERT_EQ(tris.size(), 2u);
        auto other = cube_of[tris[1]];
        auto expected = cube;
        expected[ax] += side ? 1 : -1;
        EXPECT_EQ(other, expected) << what << ": edge in a cube face is not a face segment";
      }
  }
  for (const auto& [cube, tris] : by_cube) {
    // Pieces inside this cube: connected through shared vertices.
    std::map<std::uint32_t, std::uint32_t> parent;
    std::function<std::uint32_t(std::uint32_t)> find = [&](std::uint32_t x) {
      auto it = parent.find(x);
      if (it == parent.end() || it->second == x) return parent[x] = x;
      return it->second = find(it->second);
    };
    for (std::size_t t : tris)
      for (int i = 0; i < 3; ++i) parent[find(s.triangles[t][i])] = find(s.triangles[t][0]);
    for (std::size_t x = 0; x < tris.size(); ++x)
      for (std::size_t y = x + 1; y < tris.size(); ++y) {
        const auto& p = s.triangles[tris[x]];
        const auto& q = s.triangles[tris[y]];
        if (find(p[0]) == find(q[0])) continue;
        EXPECT_TRUE(separated({s.points[p[0]], s.points[p[1]], s.points[p[2]]},
                              {s.points[q[0]], s.points[q[1]], s.points[q[2]]}))
            << what << ": pieces in one cube intersect";
      }
  }
}

void check_all(const TriangleSoup& s, const Grid& g, const std::string& what) {
  check_closed_manifold(s, what);
  EXPECT_GT(test::signed_volume(s), 0.0) << what;
  check_cubes(s, g, what);
}

}  // namespace

// --- the table itself ---------------------------------------------------------------------

// The rules marching_cubes_proved() relies on (mc_table_violations: the face rule, closed and
// oriented edges, one fan per vertex, pieces separated by planes, pairs without a shared edge
// only within a fan) hold over every entry the decider can reach.
TEST(MarchingCubesTable, KeepsEveryRuleItsProofNeeds) {
  const auto& t = detail::mc_tables();
  const std::vector<std::string> violations = detail::mc_table_violations(t);
  EXPECT_TRUE(violations.empty()) << violations.size() << ", the first: " << violations.front();
  int unrealizable = 0, fans = 0, several_pieces = 0;
  for (unsigned config = 0; config < 256; ++config)
    for (unsigned decisions = 0; decisions < 64; ++decisions) {
      if (decisions & ~t.ambiguous_faces[config]) continue;
      if (!detail::mc_decisions_realizable(t, config, decisions)) {
        ++unrealizable;
        continue;
      }
      const auto& mc = t.cases[config | decisions << 8];
      fans += mc.centroid_count > 0;
      several_pieces += t.loops[config | decisions << 8].size() > 1;
    }
  // Per checkerboard configuration: 64 - 27 (no pair connected) - 27 (none separated) + 8.
  EXPECT_EQ(unrealizable, 2 * 18);
  EXPECT_GT(fans, 0);
  EXPECT_GT(several_pieces, 0);
}

// A copy of the table with one entry (or list) broken in one way: the checker names it, so a
// proof is never given by a table that does not keep its rules.
TEST(MarchingCubesTable, BrokenEntriesAreCaught) {
  auto violations_after = [](const std::function<void(detail::McTables&)>& breaking) {
    detail::McTables t = detail::mc_tables();
    breaking(t);
    return detail::mc_table_violations(t);
  };
  unsigned fan_key = 0, two_triangle_key = 0;
  const auto& real = detail::mc_tables();
  for (unsigned key = 0; key < real.cases.size(); ++key) {
    if (!fan_key && real.cases[key].centroid_count == 1) fan_key = key;
    if (!two_triangle_key && real.cases[key].triangle_count == 2 &&
        real.cases[key].centroid_count == 0)
      two_triangle_key = key;
  }
  ASSERT_NE(fan_key, 0u);
  ASSERT_NE(two_triangle_key, 0u);
  const std::vector<std::pair<const char*, std::function<void(detail::McTables&)>>> breaks = {
      {"a triangle turned over",
       [](auto& t) { std::swap(t.cases[1].triangles[0][1], t.cases[1].triangles[0][2]); }},
      {"a vertex on an uncrossed edge", [](auto& t) { t.cases[1].triangles[0][0] = 11; }},
      {"a triangle left out", [&](auto& t) { --t.cases[two_triangle_key].triangle_count; }},
      {"a fan's range one short", [&](auto& t) { --t.cases[fan_key].fan_size[0]; }},
      {"a fan's triangle turned over",
       [&](auto& t) {
         auto& tri = t.cases[fan_key].triangles[t.cases[fan_key].fan_first[0]];
         std::swap(tri[0], tri[1]);
       }},
      {"two edges' corners swapped",
       [](auto& t) { std::swap(t.edge_corners[0], t.edge_corners[1]); }},
      {"a face's corners clockwise",
       [](auto& t) { std::reverse(t.face_corners[2].begin(), t.face_corners[2].end()); }},
      {"a crossed-edge mask", [](auto& t) { t.crossed_edges[5] ^= 1; }},
  };
  for (const auto& [what, breaking] : breaks)
    EXPECT_FALSE(violations_after(breaking).empty()) << what;

  // Caught by both ways: the broken table's mesh goes unproved, and the search finds its defect.
  detail::McTables turned = detail::mc_tables();
  std::swap(turned.cases[1].triangles[0][1], turned.cases[1].triangles[0][2]);
  const Grid grid{{0, 0, 0}, 1.0, {5, 5, 5}};
  Field field{grid, std::vector<float>(grid.node_count(), 1.0f)};
  field.values[grid.index(2, 2, 2)] = -1.0f;  // corner 0 of cube (2, 2, 2): entry 1
  const ProvedMesh broken = detail::marching_cubes_proved(field, {}, turned);
  EXPECT_FALSE(broken.proof.has_value());
  EXPECT_NE(broken.unproved.find("table"), std::string::npos) << broken.unproved;
  const MeshValidity searched = validate_mesh(broken.mesh, {.cell_grid = grid});
  EXPECT_FALSE(searched.valid());
  EXPECT_GT(searched.inconsistent_edges, 0u);
  const ProvedMesh fine = marching_cubes_proved(field);
  ASSERT_TRUE(fine.proof.has_value()) << fine.unproved;
  EXPECT_TRUE(validate_mesh(fine.mesh, {.proof = &*fine.proof}).valid());
}

// The proof's claim within a cube, tried on every reachable entry: wherever the vertices sit
// on their edges (at the clamp next to either node, or anywhere between), with each centroid at
// its loop's mean, no two triangles of the cube meet beyond what they share (the exact pair
// test of validation) and none is degenerate.
TEST(MarchingCubesTable, NoTwoTrianglesOfACubeMeetWhereverTheVerticesSit) {
  const auto& t = detail::mc_tables();
  std::mt19937 rng(2024);
  std::uniform_real_distribution<double> u(0, 1);
  long pairs = 0;
  for (unsigned config = 1; config < 255; ++config)
    for (unsigned decisions = 0; decisions < 64; ++decisions) {
      if (!detail::mc_decisions_realizable(t, config, decisions)) continue;
      const auto& mc = t.cases[config | decisions << 8];
      for (int trial = 0; trial < 12; ++trial) {
        std::vector<Vec3> p(14);
        for (int e = 0; e < 12; ++e) {
          double s = trial == 0 ? 1e-4 : trial == 1 ? 1 - 1e-4 : u(rng);
          if (trial >= 2 && trial < 6)
            s = u(rng) < 0.5 ? 1e-4 * (1 + u(rng)) : 1 - 1e-4 * (1 + u(rng));
          const int c0 = t.edge_corners[e][0], c1 = t.edge_corners[e][1];
          const Vec3 a{double(c0 & 1), double(c0 >> 1 & 1), double(c0 >> 2)};
          const Vec3 b{double(c1 & 1), double(c1 >> 1 & 1), double(c1 >> 2)};
          p[e] = a + s * (b - a);
        }
        for (int c = 0; c < mc.centroid_count; ++c) {
          Vec3 sum;
          for (int e = 0; e < 12; ++e)
            if (mc.centroid_edges[c] >> e & 1) sum = sum + p[e];
          p[12 + c] = (1.0 / std::popcount(unsigned{mc.centroid_edges[c]})) * sum;
        }
        const std::string what = "configuration " + std::to_string(config) + ", decisions " +
                                 std::to_string(decisions) + ", trial " + std::to_string(trial);
        for (int i = 0; i < mc.triangle_count; ++i) {
          const Triangle a{mc.triangles[i][0], mc.triangles[i][1], mc.triangles[i][2]};
          EXPECT_GT(norm(cross(p[a[1]] - p[a[0]], p[a[2]] - p[a[0]])), 0.0) << what;
          for (int j = i + 1; j < mc.triangle_count; ++j, ++pairs) {
            const Triangle b{mc.triangles[j][0], mc.triangles[j][1], mc.triangles[j][2]};
            EXPECT_FALSE(detail::triangle_pair_intersects(a, b, p))
                << what << ": triangles " << i << " and " << j << " meet";
          }
        }
        if (::testing::Test::HasFailure()) return;
      }
    }
  EXPECT_GT(pairs, 100000);
}

// --- all 256 configurations in a padded block -----------------------------------------------

// Configuration bits on the 2x2x2 inner nodes of a 4x4x4 grid, magnitudes varied so that every
// ambiguous face is seen decided both ways. Inside corners group by cube edges and by face
// diagonals the decider connects; each group bounds one sphere (χ = 2 per component).
TEST(MarchingCubes, AllConfigurationsBothDecisions) {
  const Grid grid{{0, 0, 0}, 1.0, {4, 4, 4}};
  const auto& t = detail::mc_tables();
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> log_mag(std::log(0.02), std::log(50.0));
  for (int config = 0; config < 256; ++config) {
    int seen[6][2] = {};
    for (int trial = 0; trial < 48; ++trial) {
      Field field{grid, std::vector<float>(grid.node_count(), 1.0f)};
      float value[8];
      for (int c = 0; c < 8; ++c) {
        const float m = static_cast<float>(std::exp(log_mag(rng)));
        value[c] = (config >> c & 1) ? -m : m;
        field.values[grid.index(1 + (c & 1), 1 + (c >> 1 & 1), 1 + (c >> 2))] = value[c];
      }
      // Groups of inside corners, joined by cube edges and connected face diagonals.
      int group[8];
      std::iota(group, group + 8, 0);
      std::function<int(int)> find = [&](int x) {
        return group[x] == x ? x : group[x] = find(group[x]);
      };
      for (int e = 0; e < 12; ++e) {
        const int a = t.edge_corners[e][0], b = t.edge_corners[e][1];
        if ((config >> a & 1) && (config >> b & 1)) group[find(a)] = find(b);
      }
      for (int f = 0; f < 6; ++f) {
        if (!(t.ambiguous_faces[config] >> f & 1)) continue;
        const auto& q = t.face_corners[f];
        const bool first = config >> q[0] & 1;
        const double in =
            first ? double(value[q[0]]) * value[q[2]] : double(value[q[1]]) * value[q[3]];
        const double out =
            first ? double(value[q[1]]) * value[q[3]] : double(value[q[0]]) * value[q[2]];
        const bool connected = in > out;
        ++seen[f][connected];
        if (connected) group[find(first ? q[0] : q[1])] = find(first ? q[2] : q[3]);
      }
      int groups = 0;
      for (int c = 0; c < 8; ++c) groups += (config >> c & 1) && find(c) == c;

      const TriangleSoup s = marching_cubes(field);
      const std::string what = "config " + std::to_string(config);
      const Topology topo = check_closed_manifold(s, what);
      EXPECT_EQ(topo.components, groups) << what;
      EXPECT_EQ(topo.euler(), 2 * groups) << what;
      if (config != 0) {
        EXPECT_GT(test::signed_volume(s), 0.0) << what;
      }
      check_cubes(s, grid, what);
      if (::testing::Test::HasFailure()) return;
    }
    for (int f = 0; f < 6; ++f)
      if (t.ambiguous_faces[config] >> f & 1) {
        EXPECT_TRUE(seen[f][0] && seen[f][1]) << "config " << config << " face " << f;
      }
  }
}

// --- random fields --------------------------------------------------------------------------

TEST(MarchingCubes, RandomSmoothFields) {
  std::mt19937 rng(12345);
  std::uniform_real_distribution<double> u(0, 1);
  for (int n = 0; n < 120; ++n) {
    const int dims = 12 + static_cast<int>(u(rng) * 12);
    const Grid grid{{-0.3, 1.7, 2.25}, 0.5 + u(rng), {dims, dims + 1, dims - 1}};
    std::function<double(Vec3)> f;
    const Vec3 size = grid.node(dims - 1, dims, dims - 2) - grid.origin;
    if (n % 2 == 0) {  // sum of Gaussians
      struct Blob {
        Vec3 c;
        double r, w;
      };
      std::vector<Blob> blobs;
      for (int b = 0; b < 6; ++b)
        blobs.push_back({grid.origin + Vec3{u(rng) * size.x, u(rng) * size.y, u(rng) * size.z},
                         (0.05 + 0.2 * u(rng)) * size.x, 0.5 + u(rng)});
      f = [blobs](Vec3 p) {
        double s = 0.6;
        for (const Blob& b : blobs) s -= b.w * std::exp(-dot(p - b.c, p - b.c) / (b.r * b.r));
        return s;
      };
    } else {  // trig field, coarse relative to its period: many ambiguous faces
      const double a = 0.5 + 2 * u(rng), b = 0.5 + 2 * u(rng), c = 0.5 + 2 * u(rng);
      const double ph = 6 * u(rng), off = u(rng) - 0.5;
      f = [=](Vec3 p) {
        return std::sin(a * p.x + ph) * std::cos(b * p.y) + std::sin(b * p.y) * std::cos(c * p.z) +
               std::sin(c * p.z) * std::cos(a * p.x) + off;
      };
    }
    Field field = sample(grid, f);
    force_border_outside(field);
    const TriangleSoup s = marching_cubes(field, {.iso = n % 3 == 0 ? 0.25f : 0.0f});
    check_all(s, grid, "field " + std::to_string(n));
    if (::testing::Test::HasFailure()) return;
  }
}

// Values in {-1, 0, 1}: many nodes exactly at the iso-value (outside) and many exact ties in
// the decider; the surface must still be a closed, oriented manifold.
TEST(MarchingCubes, NodesAtIsoValueAndDeciderTies) {
  std::mt19937 rng(99);
  for (int n = 0; n < 40; ++n) {
    const Grid grid{{0, 0, 0}, 1.0, {10, 9, 11}};
    Field field{grid, std::vector<float>(grid.node_count())};
    for (float& v : field.values) v = static_cast<float>(static_cast<int>(rng() % 3) - 1);
    force_border_outside(field, 0.0f);
    check_all(marching_cubes(field), grid, "field " + std::to_string(n));
    if (::testing::Test::HasFailure()) return;
  }
}

// --- the proof against the search (the oracle) ------------------------------------------------

// The verdict and every figure of the proof's report equal the full search's on `field`, and the
// proved mesh is marching_cubes()' bit for bit.
void expect_proof_agrees(const Field& field, const McOptions& o, const std::string& what) {
  const ProvedMesh proved = marching_cubes_proved(field, o);
  const TriangleSoup plain = marching_cubes(field, o);
  ASSERT_TRUE(proved.proof.has_value()) << what << ": " << proved.unproved;
  EXPECT_TRUE(proved.mesh.points == plain.points && proved.mesh.triangles == plain.triangles)
      << what;
  const MeshValidity a = validate_mesh(proved.mesh, {.proof = &*proved.proof});
  const MeshValidity b = validate_mesh(proved.mesh, {.cell_grid = field.grid});
  const MeshValidity c = validate_mesh(proved.mesh);  // the general search, no grid
  EXPECT_EQ(a.validated_by, ValidatedBy::Construction) << what;
  EXPECT_EQ(b.validated_by, ValidatedBy::Search) << what;
  for (const MeshValidity* s : {&b, &c}) {
    EXPECT_EQ(a.valid(), s->valid()) << what;
    EXPECT_EQ(a.problems(), s->problems()) << what;
    EXPECT_EQ(a.vertices, s->vertices) << what;
    EXPECT_EQ(a.components, s->components) << what;
    EXPECT_EQ(a.volume, s->volume) << what;
    EXPECT_EQ(a.area, s->area) << what;
    EXPECT_EQ(a.outward, s->outward) << what;
    EXPECT_EQ(a.self_intersecting_pairs, s->self_intersecting_pairs) << what;
    EXPECT_EQ(s->self_intersection_examples.size(), 0u) << what;
  }
  EXPECT_TRUE(a.valid() || proved.mesh.triangles.empty()) << what;
}

// Thousands of fields: every configuration with both decisions on each ambiguous face,
// smooth and trigonometric fields, vertices at the clamp next to the nodes, decider ties and
// nodes at the iso-value; near the origin and far from it, in doubles and as STL floats.
TEST(MarchingCubes, ProofAgreesWithTheSearch) {
  std::mt19937 rng(4242);
  std::uniform_real_distribution<double> u(0, 1);
  std::uniform_real_distribution<double> log_mag(std::log(1e-6), std::log(50.0));
  int fields = 0;
  for (int config = 0; config < 256; ++config)
    for (int trial = 0; trial < 8; ++trial, ++fields) {
      const Vec3 origin = trial % 2 ? Vec3{250.5, -180.25, 40} : Vec3{0, 0, 0};
      const Grid grid{origin, trial % 4 < 2 ? 1.0 : 0.05, {4, 4, 4}};
      Field field{grid, std::vector<float>(grid.node_count(), 1.0f)};
      for (int c = 0; c < 8; ++c) {
        const float m = static_cast<float>(std::exp(log_mag(rng)));
        field.values[grid.index(1 + (c & 1), 1 + (c >> 1 & 1), 1 + (c >> 2))] =
            (config >> c & 1) ? -m : m;
      }
      const McOptions o{.rounding =
                            trial % 3 ? CoordinateRounding::Float : CoordinateRounding::None};
      expect_proof_agrees(field, o,
                          "config " + std::to_string(config) + " trial " + std::to_string(trial));
      if (::testing::Test::HasFailure()) return;
    }
  for (int n = 0; n < 600; ++n, ++fields) {
    const int d = 6 + static_cast<int>(u(rng) * 8);
    const Vec3 origin = n % 2 ? Vec3{-310.2, 95.7, 12.3} : Vec3{0.1, 0.2, 0.3};
    const Grid grid{origin, 0.1 + u(rng), {d, d + 1, d - 1}};
    Field field{grid, std::vector<float>(grid.node_count())};
    const double a = 0.5 + 2 * u(rng), b = 0.5 + 2 * u(rng), c = 0.5 + 2 * u(rng);
    const double ph = 6 * u(rng), off = u(rng) - 0.5, step = grid.spacing;
    for (int k = 0; k < grid.dims[2]; ++k)
      for (int j = 0; j < grid.dims[1]; ++j)
        for (int i = 0; i < grid.dims[0]; ++i) {
          const double x = i * step, y = j * step, z = k * step;
          double v = std::sin(a * x + ph) * std::cos(b * y) + std::sin(b * y) * std::cos(c * z) +
                     std::sin(c * z) * std::cos(a * x) + off;
          if (n % 5 == 1) v = static_cast<double>(static_cast<int>(rng() % 3) - 1);  // ties
          if (n % 5 == 2 && u(rng) < 0.4) v = (v < 0 ? -1 : 1) * 1e-7 * u(rng);      // at the clamp
          field.values[grid.index(i, j, k)] = static_cast<float>(v);
        }
    const McOptions o{.iso = n % 7 == 0 ? 0.25f : 0.0f,
                      .rounding = n % 3 ? CoordinateRounding::Float : CoordinateRounding::None};
    force_border_outside(field, n % 5 == 1 ? o.iso : 1.0f);  // at the iso-value: outside
    expect_proof_agrees(field, o, "field " + std::to_string(n));
    if (::testing::Test::HasFailure()) return;
  }
  EXPECT_GE(fields, 2600);
}

// Where an assumption fails there is no proof, and the search says what is wrong.
TEST(MarchingCubes, NoProofWhenAnAssumptionFails) {
  const Grid grid{{0, 0, 0}, 1.0, {6, 6, 6}};
  Field open{grid, std::vector<float>(grid.node_count(), 1.0f)};
  open.values[grid.index(0, 2, 2)] = -1.0f;  // inside, on the border
  open.values[grid.index(1, 2, 2)] = -1.0f;
  const ProvedMesh a = marching_cubes_proved(open);
  EXPECT_FALSE(a.proof.has_value());
  EXPECT_NE(a.unproved.find("border"), std::string::npos) << a.unproved;
  EXPECT_GT(validate_mesh(a.mesh).border_edges, 0u);

  Field nan{grid, std::vector<float>(grid.node_count(), 1.0f)};
  nan.values[grid.index(2, 2, 2)] = -1.0f;
  nan.values[grid.index(3, 2, 2)] = std::numeric_limits<float>::quiet_NaN();
  const ProvedMesh b = marching_cubes_proved(nan);
  EXPECT_FALSE(b.proof.has_value());
  EXPECT_NE(b.unproved.find("vertex"), std::string::npos) << b.unproved;

  // A proof speaks of its own mesh only: another is searched.
  Field one{grid, std::vector<float>(grid.node_count(), 1.0f)};
  one.values[grid.index(2, 2, 2)] = -1.0f;
  const ProvedMesh c = marching_cubes_proved(one);
  ASSERT_TRUE(c.proof.has_value());
  TriangleSoup torn = c.mesh;
  torn.triangles.pop_back();
  const MeshValidity v = validate_mesh(torn, {.proof = &*c.proof});
  EXPECT_EQ(v.validated_by, ValidatedBy::Search);
  EXPECT_FALSE(v.valid());
  EXPECT_GT(v.border_edges, 0u);
}

// Dropping whole components keeps the proof, renumbered to the mesh that is left.
TEST(MarchingCubes, ProofCarriedToTheComponentsKept) {
  const Grid grid{{-1, -1, -1}, 0.25, {41, 21, 21}};
  Field field = sample(grid, [](Vec3 p) {
    const double a = norm(p - Vec3{1.5, 1.5, 1.5}) - 1.2, b = norm(p - Vec3{7.5, 1.5, 1.5}) - 0.6;
    return std::min(a, b);
  });
  force_border_outside(field);
  const ProvedMesh proved = marching_cubes_proved(field);
  ASSERT_TRUE(proved.proof.has_value()) << proved.unproved;
  const Components comps = mesh_components(proved.mesh);
  ASSERT_EQ(comps.info.size(), 2u);
  for (const std::vector<bool>& keep : {std::vector<bool>{true, false}, {false, true}}) {
    const TriangleSoup kept = keep_components(proved.mesh, comps, keep);
    const ConstructionProof proof = keep_components(*proved.proof, proved.mesh, comps, keep);
    EXPECT_EQ(proof.triangles, kept.triangles.size());
    EXPECT_EQ(proof.points, kept.points.size());
    const MeshValidity a = validate_mesh(kept, {.proof = &proof});
    const MeshValidity b = validate_mesh(kept);
    EXPECT_EQ(a.validated_by, ValidatedBy::Construction);
    EXPECT_TRUE(a.valid() && b.valid());
    EXPECT_EQ(a.components, 1u);
    EXPECT_EQ(a.volume, b.volume);
  }
  EXPECT_THROW(keep_components(ConstructionProof{1, 1}, proved.mesh, comps, {true, true}),
               InputError);
}

// --- analytic shapes ------------------------------------------------------------------------

TEST(MarchingCubes, SphereVolumeAreaAndOrientation) {
  const double r = 10;
  const Vec3 c{0.3, -0.2, 0.1};
  const Grid grid{{-15, -15, -15}, 1.0, {31, 31, 31}};
  const Field field = sample(grid, [&](Vec3 p) { return norm(p - c) - r; });
  const TriangleSoup s = marching_cubes(field);
  const Topology topo = check_closed_manifold(s, "sphere");
  EXPECT_EQ(topo.components, 1);
  EXPECT_EQ(topo.euler(), 2);
  EXPECT_NEAR(test::signed_volume(s), 4.0 / 3 * kPi * r * r * r, 0.01 * 4.0 / 3 * kPi * r * r * r);
  EXPECT_NEAR(area(s), 4 * kPi * r * r, 0.02 * 4 * kPi * r * r);
  // Normals point toward increasing field, i.e. away from the centre.
  for (const Triangle& t : s.triangles) {
    const Vec3 n = cross(s.points[t[1]] - s.points[t[0]], s.points[t[2]] - s.points[t[0]]);
    ASSERT_GT(dot(n, s.points[t[0]] - c), 0.0);
  }
  check_cubes(s, grid, "sphere");
}

TEST(MarchingCubes, TorusHasEulerCharacteristicZero) {
  const double R = 9, r = 3.5;
  const Grid grid{{-14, -14, -6}, 0.9, {32, 32, 14}};
  const Field field =
      sample(grid, [&](Vec3 p) { return std::hypot(std::hypot(p.x, p.y) - R, p.z) - r; });
  const TriangleSoup s = marching_cubes(field);
  const Topology topo = check_closed_manifold(s, "torus");
  EXPECT_EQ(topo.components, 1);
  EXPECT_EQ(topo.euler(), 0);
  EXPECT_NEAR(test::signed_volume(s), 2 * kPi * kPi * R * r * r, 0.02 * 2 * kPi * kPi * R * r * r);
}

// Vertex normals (area-weighted) agree with the gradient of a gyroid field.
TEST(MarchingCubes, NormalsFollowTheGradient) {
  const Grid grid{{0, 0, 0}, 0.25, {41, 37, 33}};
  auto f = [](Vec3 p) {
    return std::sin(p.x) * std::cos(p.y) + std::sin(p.y) * std::cos(p.z) +
           std::sin(p.z) * std::cos(p.x);
  };
  auto grad = [](Vec3 p) {
    return Vec3{std::cos(p.x) * std::cos(p.y) - std::sin(p.z) * std::sin(p.x),
                -std::sin(p.x) * std::sin(p.y) + std::cos(p.y) * std::cos(p.z),
                -std::sin(p.y) * std::sin(p.z) + std::cos(p.z) * std::cos(p.x)};
  };
  Field field = sample(grid, f);
  force_border_outside(field);
  const TriangleSoup s = marching_cubes(field);
  check_all(s, grid, "gyroid");
  std::vector<Vec3> normal(s.points.size());
  for (const Triangle& t : s.triangles) {
    const Vec3 n = cross(s.points[t[1]] - s.points[t[0]], s.points[t[2]] - s.points[t[0]]);
    for (std::uint32_t v : t) normal[v] = normal[v] + n;
  }
  int checked = 0;
  for (std::size_t v = 0; v < s.points.size(); ++v) {
    const Vec3 p = s.points[v], g = grad(p);
    // Away from the forced border and from near-critical points.
    if (norm(g) < 0.5 || p.x < 1 || p.y < 1 || p.z < 1 || p.x > 9 || p.y > 8 || p.z > 7) continue;
    EXPECT_GT(dot(normal[v], g), 0.0) << "vertex " << v;
    ++checked;
  }
  EXPECT_GT(checked, 100);
}

// --- determinism, errors, progress ----------------------------------------------------------

TEST(MarchingCubes, SameOutputForAnyThreadCount) {
  const Grid grid{{0, 0, 0}, 0.3, {60, 50, 70}};
  Field field = sample(grid, [](Vec3 p) {
    return std::sin(p.x) * std::cos(p.y) + std::sin(p.y) * std::cos(p.z) +
           std::sin(p.z) * std::cos(p.x) + 0.1;
  });
  force_border_outside(field);
  auto run = [&](int threads) {
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism, threads);
    return marching_cubes(field);
  };
  const TriangleSoup one = run(1), two = run(2), four = run(4);
  ASSERT_FALSE(one.triangles.empty());
  EXPECT_TRUE(one.points == two.points && one.triangles == two.triangles);
  EXPECT_TRUE(one.points == four.points && one.triangles == four.triangles);
}

TEST(MarchingCubes, FromASourceIsTheSampledFieldsMesh) {
  // Straight from the field seam, by slabs of layers: bit for bit the mesh of the sampled
  // field, for any thread count and for grids of 2 to 70 layers (slabs cut anywhere).
  const FieldSource gyroid = function_source([](Vec3 p) {
    const bool border = p.x < 0.1 || p.y < 0.1 || p.z < 0.1 || p.x > 17.6 || p.y > 14.6;
    if (border) return 1.0f;  // outside on the grid's faces but the top one, which is cut
    return static_cast<float>(std::sin(p.x) * std::cos(p.y) + std::sin(p.y) * std::cos(p.z) +
                              std::sin(p.z) * std::cos(p.x) + 0.1);
  });
  for (int layers : {2, 3, 9, 17, 70}) {
    const Grid grid{{0, 0, 0}, 0.3, {60, 50, layers}};
    const TriangleSoup sampled = marching_cubes(sample_field(gyroid, grid));
    for (int threads : {1, 4}) {
      tbb::global_control limit(tbb::global_control::max_allowed_parallelism, threads);
      const TriangleSoup direct = marching_cubes(gyroid, grid);
      EXPECT_TRUE(direct.points == sampled.points) << layers << " layers, " << threads;
      EXPECT_TRUE(direct.triangles == sampled.triangles) << layers << " layers, " << threads;
    }
    if (layers > 3) {
      EXPECT_GT(sampled.triangles.size(), 1000u);
    }
  }
  EXPECT_THROW(marching_cubes(FieldSource{}, Grid{{0, 0, 0}, 1.0, {3, 3, 3}}), InputError);
}

TEST(MarchingCubes, RejectsBadInput) {
  Field field{Grid{{0, 0, 0}, 1.0, {3, 3, 3}}, std::vector<float>(26, 1.0f)};
  EXPECT_THROW(marching_cubes(field), InputError);
  field.grid.dims = {1, 3, 9};
  field.values.resize(27);
  EXPECT_THROW(marching_cubes(field), InputError);
}

TEST(MarchingCubes, EmptyWhenNoCrossing) {
  const Field field{Grid{{0, 0, 0}, 1.0, {5, 4, 3}}, std::vector<float>(60, 1.0f)};
  const TriangleSoup s = marching_cubes(field);
  EXPECT_TRUE(s.points.empty());
  EXPECT_TRUE(s.triangles.empty());
}

TEST(MarchingCubes, ProgressCancels) {
  struct StopAtHalf : Progress {
    bool report(double fraction) override { return fraction < 0.5; }
  } stop;
  const Grid grid{{0, 0, 0}, 1.0, {20, 20, 200}};
  const Field field = sample(grid, [](Vec3 p) { return std::sin(p.x + p.y + p.z); });
  EXPECT_THROW(marching_cubes(field, {.progress = &stop}), Cancelled);
}

// Timing for the report (not asserted): a 400 x 400 x 220 gyroid, 20 voxels per period.
// Run with --gtest_also_run_disabled_tests --gtest_filter='*Benchmark*'.
TEST(MarchingCubes, DISABLED_BenchmarkGyroid400x400x220) {
  const Grid grid{{0, 0, 0}, 0.1, {400, 400, 220}};
  const double w = 2 * kPi / 2.0;
  Field field{grid, std::vector<float>(grid.node_count())};
  for (int k = 0; k < 220; ++k)
    for (int j = 0; j < 400; ++j)
      for (int i = 0; i < 400; ++i) {
        const Vec3 p = grid.node(i, j, k);
        field.values[grid.index(i, j, k)] = static_cast<float>(
            std::sin(w * p.x) * std::cos(w * p.y) + std::sin(w * p.y) * std::cos(w * p.z) +
            std::sin(w * p.z) * std::cos(w * p.x) + 1e-3);
      }
  force_border_outside(field);
  // Alternating, with STL's rounding as fill has it: the plain extraction and the proved one
  // (its checks' cost).
  const McOptions o{.rounding = CoordinateRounding::Float};
  for (int rep = 0; rep < 3; ++rep) {
    const auto t0 = std::chrono::steady_clock::now();
    const TriangleSoup s = marching_cubes(field, o);
    const auto t1 = std::chrono::steady_clock::now();
    const ProvedMesh proved = marching_cubes_proved(field, o);
    const auto t2 = std::chrono::steady_clock::now();
    std::printf(
        "marching_cubes 400x400x220: %.1f ms (proved: %.1f ms, %s), %zu points, %zu "
        "triangles, output %.0f MB\n",
        std::chrono::duration<double, std::milli>(t1 - t0).count(),
        std::chrono::duration<double, std::milli>(t2 - t1).count(),
        proved.proof ? "proof given" : proved.unproved.c_str(), s.points.size(), s.triangles.size(),
        (s.points.size() * sizeof(Vec3) + s.triangles.size() * sizeof(Triangle)) / 1e6);
  }
}
