// The marching-cubes table, built from one rule instead of typed in (Lorensen & Cline's 256
// cases, plus the ambiguous-face variants).
//
// For every corner configuration and every outcome of the asymptotic decider on its ambiguous
// faces:
// 1. On each face, walk the corners counter-clockwise seen from outside. A crossed face edge is
//    "entering" when the walk goes from an outside to an inside corner, "exiting" otherwise.
//    Each face segment runs from an entering edge to an exiting edge: with one or three inside
//    corners there is one of each; on an ambiguous face the segments either cut off the two
//    inside corners (separated) or the two outside corners (connected).
// 2. A cube edge lies on two faces, which walk it in opposite directions, so it is entering on
//    exactly one: following "next edge" from each crossed edge links the segments into disjoint
//    closed loops on the cube surface, oriented with the inside on a fixed side.
// 3. Each loop becomes a disk: three edges give one triangle; four give two triangles split
//    along a diagonal, which always passes through the cube interior (opposite vertices of a
//    four-loop never share a face); five or more give a fan from an extra vertex at the loop's
//    centroid, strictly inside the cube, which is embedded because every ray from an interior
//    point meets the convex cube surface once.
// No triangle edge lies in a cube face unless it is a face segment, so the surface meets each
// cube face exactly in that face's segments, which both cubes sharing the face build alike.
#include "sampling/mc_tables.hpp"

#include <mutex>
#include <stdexcept>

namespace tpmsfill::detail {
namespace {

int corner_bit(int corner, int axis) {
  return (corner >> axis) & 1;
}

int edge_between(int c0, int c1) {
  const int diff = c0 ^ c1;
  const int a = diff == 1 ? 0 : (diff == 2 ? 1 : 2);
  const int u = (a + 1) % 3, v = (a + 2) % 3;
  return 4 * a + corner_bit(c0, u) + 2 * corner_bit(c0, v);
}

McTables build() {
  McTables t;
  for (int e = 0; e < 12; ++e) {
    const int a = e / 4, u = (a + 1) % 3, v = (a + 2) % 3;
    const int c0 = ((e & 1) << u) | (((e >> 1) & 1) << v);
    t.edge_corners[e] = {static_cast<std::uint8_t>(c0), static_cast<std::uint8_t>(c0 | 1 << a)};
  }
  for (int f = 0; f < 6; ++f) {
    const int a = f / 2, s = f % 2, u = (a + 1) % 3, v = (a + 2) % 3;
    // (u, v) = (0,0) (1,0) (1,1) (0,1) turns around +a; the face at s = 0 looks along -a.
    const int uv[4][2] = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
    for (int i = 0; i < 4; ++i) {
      const int* p = uv[s == 1 ? i : (4 - i) % 4];
      t.face_corners[f][i] = static_cast<std::uint8_t>(s << a | p[0] << u | p[1] << v);
    }
  }
  for (int config = 0; config < 256; ++config)
    for (int e = 0; e < 12; ++e)
      if (corner_bit(config, t.edge_corners[e][0]) != corner_bit(config, t.edge_corners[e][1]))
        t.crossed_edges[config] |= static_cast<std::uint16_t>(1 << e);
  for (int config = 0; config < 256; ++config)
    for (int f = 0; f < 6; ++f) {
      const auto& q = t.face_corners[f];
      const int in[4] = {corner_bit(config, q[0]), corner_bit(config, q[1]),
                         corner_bit(config, q[2]), corner_bit(config, q[3])};
      if (in[0] == in[2] && in[1] == in[3] && in[0] != in[1])
        t.ambiguous_faces[config] |= static_cast<std::uint8_t>(1 << f);
    }

  t.cases.resize(256 * 64);
  t.loops.resize(256 * 64);
  for (int config = 0; config < 256; ++config)
    for (int decisions = 0; decisions < 64; ++decisions) {
      if (decisions & ~t.ambiguous_faces[config]) continue;
      int next[12];
      for (int& n : next) n = -1;
      for (int f = 0; f < 6; ++f) {
        const auto& q = t.face_corners[f];
        auto in = [&](int i) { return corner_bit(config, q[(i + 4) % 4]) == 1; };
        auto edge = [&](int i) { return edge_between(q[(i + 4) % 4], q[(i + 5) % 4]); };
        if (t.ambiguous_faces[config] >> f & 1) {
          const bool connected = decisions >> f & 1;
          for (int i = 0; i < 4; ++i) {
            if (in(i) && !connected) next[edge(i - 1)] = edge(i);  // cut off inside corner i
            if (!in(i) && connected) next[edge(i)] = edge(i - 1);  // cut off outside corner i
          }
        } else {
          int entering = -1, exiting = -1;
          for (int i = 0; i < 4; ++i) {
            if (!in(i) && in(i + 1)) entering = edge(i);
            if (in(i) && !in(i + 1)) exiting = edge(i);
          }
          if (entering >= 0) next[entering] = exiting;
        }
      }
      const int key = config | decisions << 8;
      McCase& c = t.cases[key];
      bool seen[12] = {};
      for (int start = 0; start < 12; ++start) {
        if (next[start] < 0 || seen[start]) continue;
        std::vector<std::uint8_t> loop;
        for (int e = start; !seen[e]; e = next[e]) {
          seen[e] = true;
          loop.push_back(static_cast<std::uint8_t>(e));
        }
        t.loops[key].push_back(loop);
        auto add = [&](int a, int b, int d) {
          c.triangles[c.triangle_count++] = {static_cast<std::uint8_t>(a),
                                             static_cast<std::uint8_t>(b),
                                             static_cast<std::uint8_t>(d)};
        };
        const int n = static_cast<int>(loop.size());
        if (n == 3) {
          add(loop[0], loop[1], loop[2]);
        } else if (n == 4) {
          add(loop[0], loop[1], loop[2]);
          add(loop[0], loop[2], loop[3]);
        } else {
          if (c.centroid_count == c.centroid_edges.size())
            throw std::logic_error("mc_tables: more than two long loops in a cube");
          const int centre = 12 + c.centroid_count;
          for (int e : loop)
            c.centroid_edges[c.centroid_count] |= static_cast<std::uint16_t>(1 << e);
          c.fan_first[c.centroid_count] = c.triangle_count;
          c.fan_size[c.centroid_count] = static_cast<std::uint8_t>(n);
          ++c.centroid_count;
          for (int i = 0; i < n; ++i) add(loop[i], loop[(i + 1) % n], centre);
        }
      }
    }
  return t;
}

}  // namespace

bool mc_decisions_realizable(const McTables& tables, unsigned config, unsigned decisions) {
  if (decisions & ~tables.ambiguous_faces[config]) return false;
  if (tables.ambiguous_faces[config] != 63) return true;
  bool both_connected = false, both_separated = false;
  for (int a = 0; a < 3; ++a) {
    const unsigned pair = decisions >> (2 * a) & 3;
    both_connected |= pair == 3;
    both_separated |= pair == 0;
  }
  return !(both_connected && both_separated);
}

const McTables& mc_tables() {
  static const McTables tables = build();  // C++11 magic static: built once, thread-safe
  return tables;
}

}  // namespace tpmsfill::detail
