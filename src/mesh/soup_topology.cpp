// Plain-data soup topology: every step is a sort of flat keys followed by a linear scan, so
// the result is the same whatever the thread count (keys are made unique with indices).
#include "mesh/soup_topology.hpp"

#include <tbb/parallel_sort.h>

#include <algorithm>
#include <bit>
#include <numeric>
#include <tuple>

#include "mesh/soup_indices.hpp"

namespace tpmsfill::detail {

namespace {

// Equal doubles get equal bits, except that -0.0 and +0.0 (equal values) differ: map -0 to +0.
std::uint64_t coordinate_key(double c) {
  return c == 0.0 ? 0u : std::bit_cast<std::uint64_t>(c);
}

struct PointKey {
  std::uint64_t x, y, z;
  std::uint32_t point;
  bool same_position(const PointKey& o) const { return x == o.x && y == o.y && z == o.z; }
  friend bool operator<(const PointKey& p, const PointKey& q) {
    return std::tie(p.x, p.y, p.z, p.point) < std::tie(q.x, q.y, q.z, q.point);
  }
};

struct HalfEdgeKey {
  std::uint64_t edge;  // a << 32 | b with a < b
  std::uint32_t triangle;
  std::uint8_t corner;
  bool forward;
  friend bool operator<(const HalfEdgeKey& p, const HalfEdgeKey& q) {
    return std::tie(p.edge, p.triangle, p.corner) < std::tie(q.edge, q.triangle, q.corner);
  }
};

struct TriangleKey {
  std::array<std::uint32_t, 3> sorted;
  std::uint32_t triangle;
  friend bool operator<(const TriangleKey& p, const TriangleKey& q) {
    return std::tie(p.sorted, p.triangle) < std::tie(q.sorted, q.triangle);
  }
};

}  // namespace

PointMerge merge_equal_points(const std::vector<Vec3>& points) {
  const std::size_t n = points.size();
  std::vector<PointKey> keys(n);
  for (std::size_t i = 0; i < n; ++i)
    keys[i] = {coordinate_key(points[i].x), coordinate_key(points[i].y),
               coordinate_key(points[i].z), static_cast<std::uint32_t>(i)};
  tbb::parallel_sort(keys.begin(), keys.end());

  // Each point's first occurrence (the group's smallest index, first after sorting).
  std::vector<std::uint32_t> first(n);
  for (std::size_t i = 0; i < n; ++i)
    first[keys[i].point] =
        (i > 0 && keys[i].same_position(keys[i - 1])) ? first[keys[i - 1].point] : keys[i].point;

  PointMerge merge;
  merge.vertex_of_point.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    if (first[i] == i) {
      merge.vertex_of_point[i] = static_cast<std::uint32_t>(merge.first_point.size());
      merge.first_point.push_back(static_cast<std::uint32_t>(i));
    } else {
      merge.vertex_of_point[i] = merge.vertex_of_point[first[i]];
    }
  }
  return merge;
}

namespace {

// analyze_soup() in four phases, each filling its part of the topology.

/// Corners as vertex ids, referenced vertices, repeated-corner and duplicate triangles.
void find_corners(const TriangleSoup& soup, SoupTopology& topo) {
  const std::size_t nt = soup.triangles.size();
  topo.corners.resize(nt);
  topo.flags.assign(nt, 0);
  topo.vertex_referenced.assign(topo.vertex_count, false);
  std::vector<TriangleKey> triangle_keys;
  triangle_keys.reserve(nt);
  for (std::size_t t = 0; t < nt; ++t) {
    auto& c = topo.corners[t];
    for (int k = 0; k < 3; ++k) {
      c[k] = topo.merge.vertex_of_point[soup.triangles[t][k]];
      topo.vertex_referenced[c[k]] = true;
    }
    if (repeated_corner(c)) {
      topo.flags[t] |= SoupTopology::kRepeatedCorner;
      continue;
    }
    TriangleKey key{c, static_cast<std::uint32_t>(t)};
    std::sort(key.sorted.begin(), key.sorted.end());
    triangle_keys.push_back(key);
  }
  tbb::parallel_sort(triangle_keys.begin(), triangle_keys.end());
  for (std::size_t i = 1; i < triangle_keys.size(); ++i)
    if (triangle_keys[i].sorted == triangle_keys[i - 1].sorted)
      topo.flags[triangle_keys[i].triangle] |= SoupTopology::kDuplicate;
}

/// The edge table: edges and their uses, sorted.
void build_edge_table(SoupTopology& topo) {
  const std::size_t nt = topo.corners.size();
  std::vector<HalfEdgeKey> half_edges;
  half_edges.reserve(3 * nt);
  for (std::size_t t = 0; t < nt; ++t) {
    if (topo.flags[t] & SoupTopology::kRepeatedCorner) continue;
    const auto& c = topo.corners[t];
    for (std::uint8_t k = 0; k < 3; ++k) {
      std::uint32_t from = c[k], to = c[(k + 1) % 3];
      bool forward = from < to;
      std::uint64_t key =
          forward ? (std::uint64_t{from} << 32 | to) : (std::uint64_t{to} << 32 | from);
      half_edges.push_back({key, static_cast<std::uint32_t>(t), k, forward});
    }
  }
  tbb::parallel_sort(half_edges.begin(), half_edges.end());
  topo.edge_uses.resize(half_edges.size());
  for (std::size_t i = 0; i < half_edges.size(); ++i) {
    const HalfEdgeKey& h = half_edges[i];
    topo.edge_uses[i] = {h.triangle, h.corner, h.forward};
    if (i == 0 || h.edge != half_edges[i - 1].edge)
      topo.edges.push_back({static_cast<std::uint32_t>(h.edge >> 32),
                            static_cast<std::uint32_t>(h.edge & 0xffffffffu),
                            static_cast<std::uint32_t>(i), 0, 0});
    Edge& e = topo.edges.back();
    ++e.use_count;
    if (!(topo.flags[h.triangle] & SoupTopology::kDuplicate)) ++e.kept_count;
  }
}

/// Fans per vertex, edge components and surface components.
void count_fans_and_components(SoupTopology& topo) {
  const std::size_t nt = topo.corners.size();
  // Corner slot 3t+k stands for triangle t at its corner k; slots of one fan get united.
  DisjointSets slots(3 * nt);
  DisjointSets kept_sets(nt), surface_sets(nt);
  std::vector<std::uint32_t> kept;
  for (const Edge& e : topo.edges) {
    const EdgeUse* uses = topo.edge_uses.data() + e.first_use;
    if (e.use_count >= 2) {
      auto slot_of = [](const EdgeUse& u, bool at_a) {
        // The use walks corner -> corner+1; a is at `corner` when the walk is forward.
        std::uint32_t k = (u.forward == at_a) ? u.corner : (u.corner + 1u) % 3u;
        return 3 * u.triangle + k;
      };
      for (std::uint32_t i = 1; i < e.use_count; ++i) {
        slots.unite(slot_of(uses[0], true), slot_of(uses[i], true));
        slots.unite(slot_of(uses[0], false), slot_of(uses[i], false));
      }
    }
    if (e.use_count == 2) surface_sets.unite(uses[0].triangle, uses[1].triangle);
    if (e.kept_count == 2) {
      kept.clear();
      for (std::uint32_t i = 0; i < e.use_count; ++i)
        if (!(topo.flags[uses[i].triangle] & SoupTopology::kDuplicate))
          kept.push_back(uses[i].triangle);
      kept_sets.unite(kept[0], kept[1]);
    }
  }
  topo.fans.assign(topo.vertex_count, 0);
  for (std::size_t t = 0; t < nt; ++t) {
    if (topo.flags[t] & SoupTopology::kRepeatedCorner) continue;
    for (std::uint32_t k = 0; k < 3; ++k) {
      auto slot = static_cast<std::uint32_t>(3 * t + k);
      if (slots.find(slot) == slot) ++topo.fans[topo.corners[t][k]];
    }
    auto tt = static_cast<std::uint32_t>(t);
    if (surface_sets.find(tt) == tt) ++topo.surface_components;
    if (!(topo.flags[t] & SoupTopology::kDuplicate) && kept_sets.find(tt) == tt)
      ++topo.edge_components;
  }
}

/// Vertex components, numbered in order of their smallest vertex id.
void label_vertex_components(SoupTopology& topo) {
  const std::uint32_t nv = topo.vertex_count;
  DisjointSets vertex_sets(nv);
  for (const auto& c : topo.corners) {
    vertex_sets.unite(c[0], c[1]);
    vertex_sets.unite(c[0], c[2]);
  }
  topo.vertex_component.assign(nv, kNoIndex);
  for (std::uint32_t v = 0; v < nv; ++v) {
    if (!topo.vertex_referenced[v]) continue;
    std::uint32_t root = vertex_sets.find(v);  // the set's smallest vertex id: seen first
    if (root == v) topo.vertex_component[v] = topo.vertex_components++;
    topo.vertex_component[v] = topo.vertex_component[root];
  }
}

}  // namespace

SoupTopology analyze_soup(const TriangleSoup& soup) {
  SoupTopology topo;
  topo.merge = merge_equal_points(soup.points);
  topo.vertex_count = static_cast<std::uint32_t>(topo.merge.first_point.size());
  find_corners(soup, topo);
  build_edge_table(topo);
  count_fans_and_components(topo);
  label_vertex_components(topo);
  return topo;
}

TriangleComponents triangle_components(const TriangleSoup& mesh) {
  DisjointSets sets(mesh.points.size());
  for (const Triangle& t : mesh.triangles) {
    sets.unite(t[0], t[1]);
    sets.unite(t[0], t[2]);
  }
  std::vector<std::uint32_t> id(mesh.points.size(), kNoIndex);
  TriangleComponents c;
  c.of_triangle.resize(mesh.triangles.size());
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
    const std::uint32_t root = sets.find(mesh.triangles[t][0]);
    if (id[root] == kNoIndex) id[root] = c.count++;
    c.of_triangle[t] = id[root];
  }
  return c;
}

}  // namespace tpmsfill::detail
