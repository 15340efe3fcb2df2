// Stage "clean": merge, drop, orient, turn outward, cap (see clean.hpp for the why).
//
// Everything works on the plain-data topology of detail/soup_topology (sorted flat keys, no
// hashing), so the result is the same whatever the thread count. A border is measured as a
// chain: each undirected edge gets the sum of its oriented uses (+1 walked a → b, −1 b → a);
// an edge is a border where that sum is not zero. The border of any set of triangles is a
// closed chain (as many border edges leave each vertex as enter it), so walking it always
// closes loops, whatever non-manifold edges or vertices the soup has.
#include "tpmsfill/clean.hpp"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <deque>
#include <utility>
#include <vector>

#include "detail/border_loops.hpp"
#include "detail/row_crossing.hpp"
#include "detail/soup_indices.hpp"
#include "detail/soup_topology.hpp"

namespace tpmsfill {
namespace {

using detail::Dart;
using detail::kNoIndex;
using detail::SoupTopology;

/// Cap triangles for a loop v0 → v1 → … (the model's border direction), reversed so that
/// the cap's border cancels the loop: one triangle for three corners, else a fan from the
/// corners' centroid. Appends to `caps` (points of its own).
void append_cap(const std::vector<Vec3>& points, const std::vector<std::uint32_t>& loop,
                TriangleSoup& caps) {
  const auto base = static_cast<std::uint32_t>(caps.points.size());
  for (std::uint32_t v : loop) caps.points.push_back(points[v]);
  const auto k = static_cast<std::uint32_t>(loop.size());
  if (k == 3) {
    caps.triangles.push_back({base, base + 2, base + 1});
    return;
  }
  Vec3 c{};
  for (std::uint32_t v : loop) c = c + points[v];
  caps.points.push_back((1.0 / k) * c);
  const std::uint32_t centre = base + k;
  for (std::uint32_t i = 0; i < k; ++i)
    caps.triangles.push_back({centre, base + (i + 1) % k, base + i});
}

double signed_volume6(const Vec3& o, const Vec3& a, const Vec3& b, const Vec3& c) {
  return dot(a - o, cross(b - o, c - o));
}

double area2(const Vec3& a, const Vec3& b, const Vec3& c) {
  return norm(cross(b - a, c - a));
}

}  // namespace

CleanResult clean_soup(const TriangleSoup& soup, const CleanOptions& options) {
  detail::require_indices_in_range(soup);
  if (options.progress) options.progress->begin("clean");
  const SoupTopology topo = detail::analyze_soup(soup);
  const std::size_t nt = soup.triangles.size();
  CleanResult result;
  CleanReport& r = result.report;
  r.input_points = soup.points.size();
  r.input_triangles = nt;
  r.merged_points = soup.points.size() - topo.vertex_count;
  // Vertex positions by id.
  std::vector<Vec3> position(topo.vertex_count);
  for (std::uint32_t v = 0; v < topo.vertex_count; ++v)
    position[v] = soup.points[topo.merge.first_point[v]];

  // --- 2. which triangles stay ------------------------------------------------------------
  // keep[t]: 0 dropped, 1 kept. Within a set of duplicates the orientations vote; the set's
  // first triangle with the winning orientation stays.
  std::vector<std::uint8_t> keep(nt, 0);
  bool any_duplicate = false;
  for (std::size_t t = 0; t < nt; ++t) {
    if (topo.flags[t] & SoupTopology::kRepeatedCorner) {
      ++r.repeated_corner_triangles;
      continue;
    }
    keep[t] = 1;
    any_duplicate = any_duplicate || (topo.flags[t] & SoupTopology::kDuplicate);
  }
  if (any_duplicate) {
    struct Key {
      std::array<std::uint32_t, 3> sorted;
      std::uint32_t triangle;
    };
    std::vector<Key> keys;
    for (std::size_t t = 0; t < nt; ++t)
      if (keep[t]) {
        Key k{topo.corners[t], static_cast<std::uint32_t>(t)};
        std::sort(k.sorted.begin(), k.sorted.end());
        keys.push_back(k);
      }
    std::sort(keys.begin(), keys.end(), [](const Key& a, const Key& b) {
      return std::tie(a.sorted, a.triangle) < std::tie(b.sorted, b.triangle);
    });
    // Same cyclic order as the set's first triangle?
    auto same_turn = [&](std::uint32_t a, std::uint32_t b) {
      const auto &ca = topo.corners[a], &cb = topo.corners[b];
      int s = 0;
      while (cb[s] != ca[0]) ++s;
      return cb[(s + 1) % 3] == ca[1];
    };
    for (std::size_t i = 0; i < keys.size();) {
      std::size_t j = i + 1;
      while (j < keys.size() && keys[j].sorted == keys[i].sorted) ++j;
      if (j - i > 1) {
        int net = 0;
        for (std::size_t m = i; m < j; ++m)
          net += same_turn(keys[i].triangle, keys[m].triangle) ? 1 : -1;
        for (std::size_t m = i; m < j; ++m) keep[keys[m].triangle] = 0;
        if (net == 0) {
          r.cancelled_triangles += j - i;
        } else {
          for (std::size_t m = i; m < j; ++m)
            if (same_turn(keys[i].triangle, keys[m].triangle) == (net > 0)) {
              keep[keys[m].triangle] = 1;
              break;
            }
          r.duplicate_triangles += j - i - 1;
        }
      }
      i = j;
    }
  }

  // --- 3. pieces, consistently oriented -------------------------------------------------
  // For each edge with exactly two kept uses, those uses; the edge of each triangle corner.
  std::vector<std::uint32_t> corner_edge(3 * nt, kNoIndex);
  std::vector<std::array<std::uint32_t, 2>> pair_of(topo.edges.size(), {kNoIndex, kNoIndex});
  for (std::size_t e = 0; e < topo.edges.size(); ++e) {
    const detail::Edge& edge = topo.edges[e];
    std::uint32_t kept = 0;
    for (std::uint32_t u = edge.first_use; u < edge.first_use + edge.use_count; ++u) {
      const detail::EdgeUse& use = topo.edge_uses[u];
      corner_edge[3 * use.triangle + use.corner] = static_cast<std::uint32_t>(e);
      if (keep[use.triangle]) {
        if (kept < 2) pair_of[e][kept] = u;
        ++kept;
      }
    }
    if (kept != 2) pair_of[e] = {kNoIndex, kNoIndex};
  }
  std::vector<std::uint8_t> flip(nt, 0);
  std::vector<std::uint32_t> piece(nt, kNoIndex);
  std::vector<std::uint32_t> piece_first;  // first triangle of each piece
  {
    std::deque<std::uint32_t> queue;
    for (std::size_t seed = 0; seed < nt; ++seed) {
      if (!keep[seed] || piece[seed] != kNoIndex) continue;
      const auto id = static_cast<std::uint32_t>(piece_first.size());
      piece_first.push_back(static_cast<std::uint32_t>(seed));
      piece[seed] = id;
      queue.push_back(static_cast<std::uint32_t>(seed));
      while (!queue.empty()) {
        const std::uint32_t t = queue.front();
        queue.pop_front();
        for (int k = 0; k < 3; ++k) {
          const std::uint32_t e = corner_edge[3 * t + k];
          if (e == kNoIndex || pair_of[e][0] == kNoIndex) continue;
          const detail::EdgeUse& u0 = topo.edge_uses[pair_of[e][0]];
          const detail::EdgeUse& u1 = topo.edge_uses[pair_of[e][1]];
          const detail::EdgeUse& mine = u0.triangle == t ? u0 : u1;
          const detail::EdgeUse& other = u0.triangle == t ? u1 : u0;
          if (piece[other.triangle] != kNoIndex) continue;
          piece[other.triangle] = id;
          // Neighbours agree when they walk the shared edge in opposite directions.
          const bool agree = (mine.forward != other.forward);
          flip[other.triangle] = options.orient ? (flip[t] ^ (agree ? 0 : 1)) : 0;
          queue.push_back(other.triangle);
        }
      }
    }
  }
  const std::size_t np = piece_first.size();
  r.pieces = np;
  // Keep the orientation most of each piece's area already has.
  if (options.orient) {
    std::vector<double> kept_area(np, 0), flipped_area(np, 0);
    for (std::size_t t = 0; t < nt; ++t) {
      if (!keep[t]) continue;
      const auto& c = topo.corners[t];
      (flip[t] ? flipped_area : kept_area)[piece[t]] +=
          area2(position[c[0]], position[c[1]], position[c[2]]);
    }
    for (std::size_t t = 0; t < nt; ++t)
      if (keep[t] && flipped_area[piece[t]] > kept_area[piece[t]]) flip[t] ^= 1;
  }

  // --- 4. each piece's border, volume with caps, outward --------------------------------
  // Per edge and piece: the sum of oriented uses (+1 for a → b).
  struct PieceDart {
    std::uint32_t piece, edge;
    int count;  // signed: + means a → b
  };
  std::vector<PieceDart> piece_darts;
  {
    std::vector<std::pair<std::uint32_t, int>> sums;
    for (std::size_t e = 0; e < topo.edges.size(); ++e) {
      const detail::Edge& edge = topo.edges[e];
      if (pair_of[e][0] != kNoIndex && piece[topo.edge_uses[pair_of[e][0]].triangle] ==
                                           piece[topo.edge_uses[pair_of[e][1]].triangle]) {
        const detail::EdgeUse& u0 = topo.edge_uses[pair_of[e][0]];
        const detail::EdgeUse& u1 = topo.edge_uses[pair_of[e][1]];
        if ((u0.forward ^ flip[u0.triangle]) != (u1.forward ^ flip[u1.triangle])) continue;
      }
      sums.clear();
      for (std::uint32_t u = edge.first_use; u < edge.first_use + edge.use_count; ++u) {
        const detail::EdgeUse& use = topo.edge_uses[u];
        if (!keep[use.triangle]) continue;
        const int s = (use.forward ^ flip[use.triangle]) ? 1 : -1;
        auto it = std::find_if(sums.begin(), sums.end(),
                               [&](const auto& p) { return p.first == piece[use.triangle]; });
        if (it == sums.end())
          sums.push_back({piece[use.triangle], s});
        else
          it->second += s;
      }
      for (const auto& [p, s] : sums)
        if (s != 0) piece_darts.push_back({p, static_cast<std::uint32_t>(e), s});
    }
  }
  // Sorted by piece, so each piece's darts are one run.
  std::stable_sort(piece_darts.begin(), piece_darts.end(),
                   [](const PieceDart& a, const PieceDart& b) { return a.piece < b.piece; });
  auto darts_of = [&](std::size_t begin, std::size_t end, auto&& direction) {
    std::vector<Dart> darts;
    for (std::size_t i = begin; i < end; ++i) {
      const PieceDart& d = piece_darts[i];
      const int s = d.count * direction(d.piece);
      const detail::Edge& e = topo.edges[d.edge];
      for (int m = 0; m < std::abs(s); ++m)
        darts.push_back(s > 0 ? Dart{e.a, e.b} : Dart{e.b, e.a});
    }
    return darts;
  };

  // Volumes about the bounding box's centre (smaller numbers, less cancellation).
  Box3 box;
  for (std::size_t t = 0; t < nt; ++t)
    if (keep[t])
      for (std::uint32_t v : topo.corners[t]) box.extend(position[v]);
  const Vec3 o = box.empty() ? Vec3{} : 0.5 * (box.min + box.max);
  std::vector<double> volume(np, 0);
  for (std::size_t t = 0; t < nt; ++t) {
    if (!keep[t]) continue;
    const auto& c = topo.corners[t];
    const double v = signed_volume6(o, position[c[0]], position[c[1]], position[c[2]]);
    volume[piece[t]] += flip[t] ? -v : v;
  }
  {
    // Caps of each piece's own border (the piece closed on its own).
    for (std::size_t i = 0; i < piece_darts.size();) {
      const std::uint32_t p = piece_darts[i].piece;
      std::size_t j = i;
      while (j < piece_darts.size() && piece_darts[j].piece == p) ++j;
      TriangleSoup caps;
      for (const auto& loop : detail::border_loops(darts_of(i, j, [](std::uint32_t) { return 1; })))
        append_cap(position, loop, caps);
      for (const Triangle& t : caps.triangles)
        volume[p] += signed_volume6(o, caps.points[t[0]], caps.points[t[1]], caps.points[t[2]]);
      i = j;
    }
  }
  std::vector<int> direction(np, 1);  // −1: reverse the piece
  if (options.orient) {
    double total = 0;
    for (double v : volume) total += v;
    if (total < 0) std::fill(direction.begin(), direction.end(), -1);  // all inside out
    for (std::size_t p = 0; p < np; ++p) {
      if (volume[p] * direction[p] >= 0) continue;
      // Inward-facing piece: a cavity's wall if it lies inside an odd number of the others.
      const auto& c = topo.corners[piece_first[p]];
      const Vec3 sample = position[c[0]];
      int crossings = 0;
      for (std::size_t t = 0; t < nt; ++t) {
        if (!keep[t] || piece[t] == p) continue;
        const auto& d = topo.corners[t];
        if (detail::ray_crosses({position[d[0]], position[d[1]], position[d[2]]}, sample))
          ++crossings;
      }
      if (crossings % 2 == 1)
        ++r.nested_pieces;
      else
        direction[p] = -direction[p];
    }
    for (std::size_t p = 0; p < np; ++p) r.reversed_pieces += direction[p] < 0 ? 1 : 0;
  }

  // --- output ----------------------------------------------------------------------------
  // Points in the order of their first occurrence in the input (a clean indexed mesh keeps
  // its numbering), unreferenced ones left out.
  std::vector<std::uint32_t> new_id(topo.vertex_count, kNoIndex);
  for (std::size_t t = 0; t < nt; ++t)
    if (keep[t])
      for (std::uint32_t v : topo.corners[t]) new_id[v] = 0;
  for (std::uint32_t v = 0; v < topo.vertex_count; ++v)
    if (new_id[v] != kNoIndex) {
      new_id[v] = static_cast<std::uint32_t>(result.soup.points.size());
      result.soup.points.push_back(position[v]);
    }
  for (std::size_t t = 0; t < nt; ++t) {
    if (!keep[t]) continue;
    const bool reverse = (flip[t] != 0) != (direction[piece[t]] < 0);
    if (flip[t]) ++r.flipped_triangles;
    const auto& c = topo.corners[t];
    result.soup.triangles.push_back(reverse ? Triangle{new_id[c[0]], new_id[c[2]], new_id[c[1]]}
                                            : Triangle{new_id[c[0]], new_id[c[1]], new_id[c[2]]});
  }
  r.vertices = result.soup.points.size();
  // Caps of the whole border, as the pieces now face.
  const std::vector<Dart> border =
      darts_of(0, piece_darts.size(), [&](std::uint32_t p) { return direction[p]; });
  // Darts of different pieces on one edge may cancel.
  std::vector<Dart> net = detail::net_darts(border);
  r.border_edges = detail::count_edges(net);
  for (const auto& loop : detail::border_loops(std::move(net))) {
    append_cap(position, loop, result.caps);
    ++r.holes;
  }
  r.cap_triangles = result.caps.triangles.size();
  return result;
}

}  // namespace tpmsfill
