// The marching-cubes table checked against what its output is valid by (mc_tables.hpp,
// mc_table_violations). The cube's numbering and the face rule are derived here again from
// their definitions, not read from the table, so that a wrong entry or a wrong edge or face
// list shows; marching_cubes() runs this once before it promises anything by construction.
#include <algorithm>
#include <array>
#include <map>
#include <numeric>
#include <string>
#include <vector>

#include "sampling/mc_tables.hpp"

namespace tpmsfill::detail {
namespace {

using Corner = std::array<int, 3>;

Corner corner_at(int c) {
  return {c & 1, c >> 1 & 1, c >> 2 & 1};
}

// The corners of edge e as the numbering defines it: e = 4a + ub + 2vb.
std::array<int, 2> edge_ends(int e) {
  const int a = e / 4, u = (a + 1) % 3, v = (a + 2) % 3;
  const int c0 = (e & 1) << u | (e >> 1 & 1) << v;
  return {c0, c0 | 1 << a};
}

bool edge_on_face(int e, int f) {
  for (int c : edge_ends(e))
    if (corner_at(c)[f / 2] != f % 2) return false;
  return true;
}

// The face both edges lie on, or -1.
int common_face(int a, int b) {
  for (int f = 0; f < 6; ++f)
    if (edge_on_face(a, f) && edge_on_face(b, f)) return f;
  return -1;
}

int edge_between(int c0, int c1) {
  for (int e = 0; e < 12; ++e) {
    const auto ends = edge_ends(e);
    if ((ends[0] == c0 && ends[1] == c1) || (ends[0] == c1 && ends[1] == c0)) return e;
  }
  return -1;
}

std::string where(int config, int decisions) {
  return "configuration " + std::to_string(config) + ", decisions " + std::to_string(decisions);
}

// The cube's edge and face lists as the table holds them, against their definitions: edges by
// their numbering, faces as the four corners of face f = 2a + s, counter-clockwise seen from
// outside (their turn points along the outward normal).
void check_numbering(const McTables& t, std::vector<std::string>& out) {
  for (int e = 0; e < 12; ++e)
    if (t.edge_corners[e][0] != edge_ends(e)[0] || t.edge_corners[e][1] != edge_ends(e)[1])
      out.push_back("edge " + std::to_string(e) + " does not join the corners its number names");
  for (int f = 0; f < 6; ++f) {
    const auto& q = t.face_corners[f];
    bool on_face = true;
    for (int c : q) on_face &= corner_at(c)[f / 2] == f % 2;
    const Corner p0 = corner_at(q[0]), p1 = corner_at(q[1]), p2 = corner_at(q[2]);
    const int u[3] = {p1[0] - p0[0], p1[1] - p0[1], p1[2] - p0[2]};
    const int w[3] = {p2[0] - p1[0], p2[1] - p1[1], p2[2] - p1[2]};
    const int n[3] = {u[1] * w[2] - u[2] * w[1], u[2] * w[0] - u[0] * w[2],
                      u[0] * w[1] - u[1] * w[0]};
    const int outward = f % 2 ? 1 : -1;
    bool around = on_face && n[f / 2] == outward;
    for (int i = 0; i < 4; ++i) around &= edge_between(q[i], q[(i + 1) % 4]) >= 0;
    if (!around)
      out.push_back("face " + std::to_string(f) +
                    "'s corners are not its four, counter-clockwise from outside");
  }
}

// The face rule (mc_tables.cpp, step 1): the directed segments (from edge, to edge) on face f.
std::vector<std::array<int, 2>> face_segments(const McTables& t, int config, int decisions, int f) {
  const auto& q = t.face_corners[f];
  auto in = [&](int i) { return (config >> q[(i + 4) % 4] & 1) != 0; };
  auto edge = [&](int i) { return edge_between(q[(i + 4) % 4], q[(i + 5) % 4]); };
  std::vector<std::array<int, 2>> segments;
  const bool ambiguous = in(0) == in(2) && in(1) == in(3) && in(0) != in(1);
  if (ambiguous) {
    const bool connected = decisions >> f & 1;
    for (int i = 0; i < 4; ++i) {
      if (in(i) && !connected) segments.push_back({edge(i - 1), edge(i)});
      if (!in(i) && connected) segments.push_back({edge(i), edge(i - 1)});
    }
    return segments;
  }
  int entering = -1, exiting = -1;
  for (int i = 0; i < 4; ++i) {
    if (!in(i) && in(i + 1)) entering = edge(i);
    if (in(i) && !in(i + 1)) exiting = edge(i);
  }
  if (entering >= 0) segments.push_back({entering, exiting});
  return segments;
}

// Whether the open edges of `a` and those of `b` lie strictly on either side of a plane
// n . x = d / 2 with n in {-1, 0, 1}^3 (the cube is the unit cube).
bool separated(const std::vector<int>& a, const std::vector<int>& b) {
  for (int nx = -1; nx <= 1; ++nx)
    for (int ny = -1; ny <= 1; ++ny)
      for (int nz = -1; nz <= 1; ++nz)
        for (int d = -6; d <= 6; ++d) {
          auto below = [&](const std::vector<int>& edges, int sign) {
            for (int e : edges) {
              int at[2];
              for (int i = 0; i < 2; ++i) {
                const Corner p = corner_at(edge_ends(e)[i]);
                at[i] = sign * (2 * (nx * p[0] + ny * p[1] + nz * p[2]) - d);
              }
              if (at[0] > 0 || at[1] > 0 || (at[0] == 0 && at[1] == 0)) return false;
            }
            return true;
          };
          if (below(a, 1) && below(b, -1)) return true;
        }
  return false;
}

void check_entry(const McTables& t, int config, int decisions, std::vector<std::string>& out) {
  const McCase& mc = t.cases[static_cast<std::size_t>(config | decisions << 8)];
  const std::string at = where(config, decisions);
  auto fail = [&](const std::string& what) { out.push_back(at + ": " + what); };
  const int n = mc.triangle_count;
  const int slots = 12 + mc.centroid_count;
  if (n > 12 || mc.centroid_count > 2) return fail("more triangles or centroids than a cube holds");

  // 1. slots
  unsigned crossed = 0, used = 0;
  for (int e = 0; e < 12; ++e)
    if ((config >> edge_ends(e)[0] & 1) != (config >> edge_ends(e)[1] & 1)) crossed |= 1u << e;
  for (int i = 0; i < n; ++i) {
    const auto& tri = mc.triangles[i];
    for (int k = 0; k < 3; ++k) {
      if (tri[k] >= slots) return fail("a triangle uses a slot that does not exist");
      if (tri[k] < 12) used |= 1u << tri[k];
    }
    if (tri[0] == tri[1] || tri[1] == tri[2] || tri[0] == tri[2])
      return fail("a triangle repeats a slot");
    for (int f = 0; f < 6; ++f)
      if (tri[0] < 12 && tri[1] < 12 && tri[2] < 12 && edge_on_face(tri[0], f) &&
          edge_on_face(tri[1], f) && edge_on_face(tri[2], f))
        fail("a triangle lies in face " + std::to_string(f));
  }
  if (used != crossed) fail("the triangles do not use exactly the crossed edges");
  if (t.crossed_edges[config] != crossed) fail("the crossed-edge mask is wrong");

  // 2, 3. directed edges
  std::map<std::array<int, 2>, int> walked;
  for (int i = 0; i < n; ++i)
    for (int k = 0; k < 3; ++k) ++walked[{mc.triangles[i][k], mc.triangles[i][(k + 1) % 3]}];
  for (int f = 0; f < 6; ++f)
    for (const auto& s : face_segments(t, config, decisions, f))
      if (walked.count(s) == 0)
        fail("segment " + std::to_string(s[0]) + "-" + std::to_string(s[1]) + " of face " +
             std::to_string(f) + " is no triangle's edge in its direction");
  for (const auto& [e, count] : walked) {
    if (count != 1) fail("a directed edge is walked twice");
    const int f = e[0] < 12 && e[1] < 12 ? common_face(e[0], e[1]) : -1;
    if (f >= 0) {
      const auto s = face_segments(t, config, decisions, f);
      if (std::find(s.begin(), s.end(), e) == s.end())
        fail("edge " + std::to_string(e[0]) + "-" + std::to_string(e[1]) + " lies in face " +
             std::to_string(f) + " but is not one of its segments in its direction");
    } else if (walked.count({e[1], e[0]}) == 0) {
      fail("inner edge " + std::to_string(e[0]) + "-" + std::to_string(e[1]) +
           " is not walked back");
    }
  }

  // 4. one fan around every slot
  for (int s = 0; s < slots; ++s) {
    std::map<int, int> next;  // the link: b -> c for each triangle (s, b, c)
    std::map<int, int> into;
    for (int i = 0; i < n; ++i)
      for (int k = 0; k < 3; ++k)
        if (mc.triangles[i][k] == s) {
          const int b = mc.triangles[i][(k + 1) % 3], c = mc.triangles[i][(k + 2) % 3];
          if (next.count(b) || into.count(c)) fail("slot " + std::to_string(s) + " is pinched");
          next[b] = c;
          into[c] = b;
        }
    if (next.empty()) {
      if (s >= 12) fail("centroid " + std::to_string(s - 12) + " has no triangle");
      continue;
    }
    int start = next.begin()->first;  // a path starts where nothing leads in
    for (const auto& [b, c] : next)
      if (!into.count(b)) start = b;
    std::size_t steps = 0;
    int b = start;
    while (next.count(b) && steps <= next.size()) {
      ++steps;
      b = next[b];
      if (b == start) break;
    }
    const bool cycle = b == start;
    if (steps != next.size() || cycle != (s >= 12))
      fail("the triangles around slot " + std::to_string(s) + " are not one " +
           (s >= 12 ? "closed fan" : "fan between two face segments"));
  }

  // 5. pieces separated by planes
  std::vector<int> piece(static_cast<std::size_t>(n));
  std::iota(piece.begin(), piece.end(), 0);
  auto find = [&](int x) {
    while (piece[x] != x) x = piece[x] = piece[piece[x]];
    return x;
  };
  auto share_edge = [&](int i, int j) {
    int shared = 0;
    for (int a : mc.triangles[i])
      for (int b : mc.triangles[j]) shared += a == b;
    return shared >= 2;
  };
  for (int i = 0; i < n; ++i)
    for (int j = i + 1; j < n; ++j)
      if (share_edge(i, j)) piece[find(j)] = find(i);
  std::map<int, std::vector<int>> edges_of;
  for (int i = 0; i < n; ++i)
    for (int s : mc.triangles[i])
      if (s < 12) edges_of[find(i)].push_back(s);
  for (auto x = edges_of.begin(); x != edges_of.end(); ++x)
    for (auto y = std::next(x); y != edges_of.end(); ++y)
      if (!separated(x->second, y->second)) fail("two pieces of the cube are not separated");

  // 6. pairs in a piece that share no edge lie in one fan
  for (int c = 0; c < mc.centroid_count; ++c)
    for (int i = 0; i < n; ++i) {
      const bool in_range = i >= mc.fan_first[c] && i < mc.fan_first[c] + mc.fan_size[c];
      const auto& tri = mc.triangles[i];
      const bool uses = std::find(tri.begin(), tri.end(), 12 + c) != tri.end();
      if (in_range != uses) fail("centroid " + std::to_string(c) + "'s fan range is wrong");
    }
  for (int i = 0; i < n; ++i)
    for (int j = i + 1; j < n; ++j) {
      if (find(i) != find(j) || share_edge(i, j)) continue;
      bool one_fan = false;
      for (int c = 0; c < mc.centroid_count; ++c)
        one_fan |= i >= mc.fan_first[c] && j < mc.fan_first[c] + mc.fan_size[c];
      if (!one_fan)
        fail("triangles " + std::to_string(i) + " and " + std::to_string(j) +
             " of one piece share no edge and are not in one fan");
    }
}

}  // namespace

std::vector<std::string> mc_table_violations(const McTables& tables) {
  std::vector<std::string> out;
  check_numbering(tables, out);
  if (tables.cases.size() != 256 * 64) {
    out.push_back("the table does not hold 256 x 64 entries");
    return out;
  }
  for (int config = 0; config < 256; ++config)
    for (int decisions = 0; decisions < 64; ++decisions)
      if (mc_decisions_realizable(tables, static_cast<unsigned>(config),
                                  static_cast<unsigned>(decisions)))
        check_entry(tables, config, decisions, out);
  return out;
}

}  // namespace tpmsfill::detail
