// Marching cubes: every corner configuration, random fields, analytic shapes. The checks are
// geometric truths (closed, manifold, oriented, volume, Euler characteristic, no triangle
// crossing a cube face), never stored outputs.
#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <algorithm>
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
#include <tpmsfill/sampling/marching_cubes.hpp>

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

// For every configuration and every decision set (realizable or not): the loops use each
// crossed edge once; triangle edges in a cube face are face segments; and the vertices of
// two loops of one cube lie on edges strictly separated by a plane, so the two disks (each in
// the convex hull of its loop) cannot meet, wherever the vertices sit on their edges.
TEST(MarchingCubesTable, LoopsPartitionEdgesAndAreSeparated) {
  const auto& t = detail::mc_tables();
  auto corner = [](int c) { return std::array<int, 3>{c & 1, c >> 1 & 1, c >> 2 & 1}; };
  auto on_face = [&](int e, int f) {
    for (int c : t.edge_corners[e])
      if (corner(c)[f / 2] != f % 2) return false;
    return true;
  };
  int multi_loop_cases = 0, unrealizable = 0;
  for (int config = 0; config < 256; ++config)
    for (int decisions = 0; decisions < 64; ++decisions) {
      if (decisions & ~t.ambiguous_faces[config]) continue;
      const int key = config | decisions << 8;
      const auto& loops = t.loops[key];
      const auto& mc = t.cases[key];
      std::set<int> crossed, used;
      for (int e = 0; e < 12; ++e)
        if ((config >> t.edge_corners[e][0] & 1) != (config >> t.edge_corners[e][1] & 1))
          crossed.insert(e);
      std::set<std::pair<int, int>> segments;
      for (const auto& loop : loops) {
        ASSERT_GE(loop.size(), 3u);
        for (std::size_t i = 0; i < loop.size(); ++i) {
          EXPECT_TRUE(used.insert(loop[i]).second);
          const int a = loop[i], b = loop[(i + 1) % loop.size()];
          segments.insert(std::minmax(a, b));
          bool share = false;
          for (int f = 0; f < 6; ++f) share |= on_face(a, f) && on_face(b, f);
          EXPECT_TRUE(share) << "loop step leaves the face";
        }
      }
      EXPECT_EQ(used, crossed) << "config " << config;
      for (int i = 0; i < mc.triangle_count; ++i) {
        const auto& tri = mc.triangles[i];
        for (int f = 0; f < 6; ++f) {
          int n = 0;
          for (int s : tri) n += s < 12 && on_face(s, f);
          EXPECT_LT(n, 3);
        }
        for (int j = 0; j < 3; ++j) {
          const int a = tri[j], b = tri[(j + 1) % 3];
          if (a >= 12 || b >= 12) continue;
          for (int f = 0; f < 6; ++f)
            if (on_face(a, f) && on_face(b, f)) {
              EXPECT_TRUE(segments.count(std::minmax(a, b))) << "chord in a face";
            }
        }
      }
      if (loops.size() > 1) ++multi_loop_cases;
      // On the two checkerboard configurations all six faces are ambiguous, and each pair of
      // opposite faces compares the same products: |inside values| P against |outside values|
      // Q. A pair with both faces connected (P > Q) and a pair with both separated (P <= Q)
      // never occur together; the decider's products are exact, so neither does it at run
      // time. Those decision sets are not required to be separable.
      if (t.ambiguous_faces[config] == 63) {
        bool both_connected = false, both_separated = false;
        for (int a = 0; a < 3; ++a) {
          const int pair = decisions >> (2 * a) & 3;
          both_connected |= pair == 3;
          both_separated |= pair == 0;
        }
        if (both_connected && both_separated) {
          ++unrealizable;
          continue;
        }
      }
      for (std::size_t x = 0; x < loops.size(); ++x)
        for (std::size_t y = x + 1; y < loops.size(); ++y) {
          bool found = false;
          for (int nx = -1; nx <= 1 && !found; ++nx)
            for (int ny = -1; ny <= 1 && !found; ++ny)
              for (int nz = -1; nz <= 1 && !found; ++nz)
                for (int d2 = -6; d2 <= 6 && !found; ++d2) {
                  auto side = [&](const std::vector<std::uint8_t>& loop, int sign) {
                    for (int e : loop) {
                      int at[2];
                      for (int i = 0; i < 2; ++i) {
                        auto p = corner(t.edge_corners[e][i]);
                        at[i] = sign * (2 * (nx * p[0] + ny * p[1] + nz * p[2]) - d2);
                      }
                      // Open edge strictly on the negative side.
                      if (at[0] > 0 || at[1] > 0 || (at[0] == 0 && at[1] == 0)) return false;
                    }
                    return true;
                  };
                  found = side(loops[x], 1) && side(loops[y], -1);
                }
          EXPECT_TRUE(found) << "config " << config << " decisions " << decisions << ": loops " << x
                             << ", " << y << " not separated by a plane";
        }
    }
  EXPECT_GT(multi_loop_cases, 0);
  // Per checkerboard configuration: 64 - 27 (no pair connected) - 27 (none separated) + 8.
  EXPECT_EQ(unrealizable, 2 * 18);
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
  for (int rep = 0; rep < 3; ++rep) {
    const auto t0 = std::chrono::steady_clock::now();
    const TriangleSoup s = marching_cubes(field);
    const double ms =
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    std::printf("marching_cubes 400x400x220: %.1f ms, %zu points, %zu triangles, output %.0f MB\n",
                ms, s.points.size(), s.triangles.size(),
                (s.points.size() * sizeof(Vec3) + s.triangles.size() * sizeof(Triangle)) / 1e6);
  }
}
