// Stage "clean": merge, drop, orient, turn outward, cap (see clean.hpp for the why).
//
// Everything works on the plain-data topology of mesh/soup_topology (sorted flat keys, no
// hashing), so the result is the same whatever the thread count. A border is measured as a
// chain: each undirected edge gets the sum of its oriented uses (+1 walked a → b, −1 b → a);
// an edge is a border where that sum is not zero. The border of any set of triangles is a
// closed chain (as many border edges leave each vertex as enter it), so walking it always
// closes loops, whatever non-manifold edges or vertices the soup has.
#include "tpmsfill/mesh/clean.hpp"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <deque>
#include <utility>
#include <vector>

#include "core/index_limits.hpp"
#include "core/stage_progress.hpp"
#include "mesh/border_loops.hpp"
#include "mesh/mesh_measures.hpp"
#include "mesh/row_crossing.hpp"
#include "mesh/soup_indices.hpp"
#include "mesh/soup_topology.hpp"

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

// --- 1. merged points ------------------------------------------------------------------------

/// Vertex positions by id (points merged by detail::analyze_soup).
std::vector<Vec3> vertex_positions(const TriangleSoup& soup, const SoupTopology& topo) {
  std::vector<Vec3> position(topo.vertex_count);
  for (std::uint32_t v = 0; v < topo.vertex_count; ++v)
    position[v] = soup.points[topo.merge.first_point[v]];
  return position;
}

// --- 2. which triangles stay ------------------------------------------------------------------

/// Within each set of duplicates the orientations vote: the set's first triangle with the
/// winning orientation stays, or none when they cancel. Updates keep and the counts.
void resolve_duplicates(const SoupTopology& topo, std::vector<std::uint8_t>& keep, CleanReport& r) {
  struct Key {
    std::array<std::uint32_t, 3> sorted;
    std::uint32_t triangle;
  };
  std::vector<Key> keys;
  for (std::size_t t = 0; t < keep.size(); ++t)
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

/// keep[t]: 0 dropped (repeated corner, outvoted or cancelled duplicate), 1 kept.
std::vector<std::uint8_t> kept_triangles(const SoupTopology& topo, CleanReport& r) {
  const std::size_t nt = topo.corners.size();
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
  if (any_duplicate) resolve_duplicates(topo, keep, r);
  return keep;
}

// --- 3. pieces, consistently oriented ----------------------------------------------------------

/// Edge-connected pieces of the kept triangles and how each triangle turns to agree.
struct Pieces {
  /// Per edge: its two kept uses (into SoupTopology::edge_uses) when it has exactly two,
  /// else kNoIndex twice.
  std::vector<std::array<std::uint32_t, 2>> pair_of;
  std::vector<std::uint32_t> piece;  ///< per triangle (kNoIndex: dropped)
  std::vector<std::uint32_t> first;  ///< per piece: its first triangle
  std::vector<std::uint8_t> flip;    ///< per triangle: reversed to agree with its piece
};

/// Pieces::pair_of, and per triangle corner (3t + k) the edge it starts.
std::vector<std::uint32_t> pair_edges(const SoupTopology& topo,
                                      const std::vector<std::uint8_t>& keep, Pieces& pieces) {
  std::vector<std::uint32_t> corner_edge(3 * keep.size(), kNoIndex);
  pieces.pair_of.assign(topo.edges.size(), {kNoIndex, kNoIndex});
  for (std::size_t e = 0; e < topo.edges.size(); ++e) {
    const detail::Edge& edge = topo.edges[e];
    std::uint32_t kept = 0;
    for (std::uint32_t u = edge.first_use; u < edge.first_use + edge.use_count; ++u) {
      const detail::EdgeUse& use = topo.edge_uses[u];
      corner_edge[3 * use.triangle + use.corner] = static_cast<std::uint32_t>(e);
      if (keep[use.triangle]) {
        if (kept < 2) pieces.pair_of[e][kept] = u;
        ++kept;
      }
    }
    if (kept != 2) pieces.pair_of[e] = {kNoIndex, kNoIndex};
  }
  return corner_edge;
}

/// Grows the pieces breadth-first through edges with two kept uses; with `orient`, each new
/// triangle is flipped so that it walks the shared edge against its neighbour.
void grow_pieces(const SoupTopology& topo, const std::vector<std::uint8_t>& keep,
                 const std::vector<std::uint32_t>& corner_edge, bool orient, Pieces& pieces) {
  const std::size_t nt = keep.size();
  pieces.flip.assign(nt, 0);
  pieces.piece.assign(nt, kNoIndex);
  std::deque<std::uint32_t> queue;
  for (std::size_t seed = 0; seed < nt; ++seed) {
    if (!keep[seed] || pieces.piece[seed] != kNoIndex) continue;
    const auto id = static_cast<std::uint32_t>(pieces.first.size());
    pieces.first.push_back(static_cast<std::uint32_t>(seed));
    pieces.piece[seed] = id;
    queue.push_back(static_cast<std::uint32_t>(seed));
    while (!queue.empty()) {
      const std::uint32_t t = queue.front();
      queue.pop_front();
      for (int k = 0; k < 3; ++k) {
        const std::uint32_t e = corner_edge[3 * t + k];
        if (e == kNoIndex || pieces.pair_of[e][0] == kNoIndex) continue;
        const detail::EdgeUse& u0 = topo.edge_uses[pieces.pair_of[e][0]];
        const detail::EdgeUse& u1 = topo.edge_uses[pieces.pair_of[e][1]];
        const detail::EdgeUse& mine = u0.triangle == t ? u0 : u1;
        const detail::EdgeUse& other = u0.triangle == t ? u1 : u0;
        if (pieces.piece[other.triangle] != kNoIndex) continue;
        pieces.piece[other.triangle] = id;
        // Neighbours agree when they walk the shared edge in opposite directions.
        const bool agree = (mine.forward != other.forward);
        pieces.flip[other.triangle] = orient ? (pieces.flip[t] ^ (agree ? 0 : 1)) : 0;
        queue.push_back(other.triangle);
      }
    }
  }
}

/// The pieces; with `orient`, each keeps the orientation most of its area already has.
Pieces orient_pieces(const SoupTopology& topo, const std::vector<std::uint8_t>& keep,
                     const std::vector<Vec3>& position, bool orient) {
  Pieces pieces;
  const std::vector<std::uint32_t> corner_edge = pair_edges(topo, keep, pieces);
  grow_pieces(topo, keep, corner_edge, orient, pieces);
  if (!orient) return pieces;
  const std::size_t nt = keep.size(), np = pieces.first.size();
  std::vector<double> kept_area(np, 0), flipped_area(np, 0);
  for (std::size_t t = 0; t < nt; ++t) {
    if (!keep[t]) continue;
    const auto& c = topo.corners[t];
    (pieces.flip[t] ? flipped_area : kept_area)[pieces.piece[t]] +=
        detail::double_area(position[c[0]], position[c[1]], position[c[2]]);
  }
  for (std::size_t t = 0; t < nt; ++t)
    if (keep[t] && flipped_area[pieces.piece[t]] > kept_area[pieces.piece[t]]) pieces.flip[t] ^= 1;
  return pieces;
}

// --- 4. each piece's border, volume with caps, outward ------------------------------------------

/// Per edge and piece: the sum of oriented uses (+1 for a → b), where not zero.
struct PieceDart {
  std::uint32_t piece, edge;
  int count;  // signed: + means a → b
};

/// The pieces' borders, sorted by piece (so each piece's darts are one run).
std::vector<PieceDart> piece_borders(const SoupTopology& topo,
                                     const std::vector<std::uint8_t>& keep, const Pieces& pieces) {
  const auto& piece = pieces.piece;
  const auto& flip = pieces.flip;
  std::vector<PieceDart> darts;
  std::vector<std::pair<std::uint32_t, int>> sums;
  for (std::size_t e = 0; e < topo.edges.size(); ++e) {
    const detail::Edge& edge = topo.edges[e];
    const auto& pair = pieces.pair_of[e];
    if (pair[0] != kNoIndex &&
        piece[topo.edge_uses[pair[0]].triangle] == piece[topo.edge_uses[pair[1]].triangle]) {
      const detail::EdgeUse& u0 = topo.edge_uses[pair[0]];
      const detail::EdgeUse& u1 = topo.edge_uses[pair[1]];
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
      if (s != 0) darts.push_back({p, static_cast<std::uint32_t>(e), s});
  }
  std::stable_sort(darts.begin(), darts.end(),
                   [](const PieceDart& a, const PieceDart& b) { return a.piece < b.piece; });
  return darts;
}

/// Darts [begin, end) of `darts` as directed edges, each piece's turned by direction(piece).
template <class Direction>
std::vector<Dart> darts_of(const SoupTopology& topo, const std::vector<PieceDart>& darts,
                           std::size_t begin, std::size_t end, const Direction& direction) {
  std::vector<Dart> out;
  for (std::size_t i = begin; i < end; ++i) {
    const PieceDart& d = darts[i];
    const int s = d.count * direction(d.piece);
    const detail::Edge& e = topo.edges[d.edge];
    for (int m = 0; m < std::abs(s); ++m) out.push_back(s > 0 ? Dart{e.a, e.b} : Dart{e.b, e.a});
  }
  return out;
}

/// Six times each piece's signed volume, closed on its own by caps of its border, about the
/// centre of the kept triangles' bounding box (smaller numbers, less cancellation).
std::vector<double> piece_volumes(const SoupTopology& topo, const std::vector<std::uint8_t>& keep,
                                  const Pieces& pieces, const std::vector<PieceDart>& darts,
                                  const std::vector<Vec3>& position) {
  const std::size_t nt = keep.size();
  Box3 box;
  for (std::size_t t = 0; t < nt; ++t)
    if (keep[t])
      for (std::uint32_t v : topo.corners[t]) box.extend(position[v]);
  const Vec3 o = box.centre();
  std::vector<double> volume(pieces.first.size(), 0);
  for (std::size_t t = 0; t < nt; ++t) {
    if (!keep[t]) continue;
    const auto& c = topo.corners[t];
    const double v = detail::six_volume(o, position[c[0]], position[c[1]], position[c[2]]);
    volume[pieces.piece[t]] += pieces.flip[t] ? -v : v;
  }
  for (std::size_t i = 0; i < darts.size();) {
    const std::uint32_t p = darts[i].piece;
    std::size_t j = i;
    while (j < darts.size() && darts[j].piece == p) ++j;
    TriangleSoup caps;
    for (const auto& loop :
         detail::border_loops(darts_of(topo, darts, i, j, [](std::uint32_t) { return 1; })))
      append_cap(position, loop, caps);
    for (const Triangle& t : caps.triangles)
      volume[p] += detail::six_volume(o, caps.points[t[0]], caps.points[t[1]], caps.points[t[2]]);
    i = j;
  }
  return volume;
}

/// Per piece +1, or −1 to reverse it: a piece bounding a negative volume (all of them when
/// the total is negative) is reversed unless it lies inside an odd number of other pieces.
std::vector<int> outward_directions(const SoupTopology& topo, const std::vector<std::uint8_t>& keep,
                                    const Pieces& pieces, const std::vector<double>& volume,
                                    const std::vector<Vec3>& position, CleanReport& r) {
  const std::size_t np = pieces.first.size();
  std::vector<int> direction(np, 1);
  double total = 0;
  for (double v : volume) total += v;
  if (total < 0) std::fill(direction.begin(), direction.end(), -1);  // all inside out
  for (std::size_t p = 0; p < np; ++p) {
    if (volume[p] * direction[p] >= 0) continue;
    // Inward-facing piece: a cavity's wall if it lies inside an odd number of the others.
    const Vec3 sample = position[topo.corners[pieces.first[p]][0]];
    int crossings = 0;
    for (std::size_t t = 0; t < keep.size(); ++t) {
      if (!keep[t] || pieces.piece[t] == p) continue;
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
  return direction;
}

// --- output, 5. caps ---------------------------------------------------------------------------

/// The kept triangles, as their pieces now face, over the referenced vertices in the order of
/// their first occurrence in the input (a clean indexed mesh keeps its numbering).
TriangleSoup oriented_soup(const SoupTopology& topo, const std::vector<std::uint8_t>& keep,
                           const Pieces& pieces, const std::vector<int>& direction,
                           const std::vector<Vec3>& position, CleanReport& r,
                           std::vector<std::uint32_t>& reversed) {
  TriangleSoup out;
  std::vector<std::uint32_t> new_id(topo.vertex_count, kNoIndex);
  for (std::size_t t = 0; t < keep.size(); ++t)
    if (keep[t])
      for (std::uint32_t v : topo.corners[t]) new_id[v] = 0;
  for (std::uint32_t v = 0; v < topo.vertex_count; ++v)
    if (new_id[v] != kNoIndex) {
      new_id[v] = static_cast<std::uint32_t>(out.points.size());
      out.points.push_back(position[v]);
    }
  for (std::size_t t = 0; t < keep.size(); ++t) {
    if (!keep[t]) continue;
    const bool reverse = (pieces.flip[t] != 0) != (direction[pieces.piece[t]] < 0);
    if (pieces.flip[t]) ++r.flipped_triangles;
    if (reverse) reversed.push_back(static_cast<std::uint32_t>(t));
    const auto& c = topo.corners[t];
    out.triangles.push_back(reverse ? Triangle{new_id[c[0]], new_id[c[2]], new_id[c[1]]}
                                    : Triangle{new_id[c[0]], new_id[c[1]], new_id[c[2]]});
  }
  return out;
}

/// Step 5: caps of the whole border, as the pieces now face (darts of different pieces on one
/// edge may cancel).
TriangleSoup cap_holes(const SoupTopology& topo, const std::vector<PieceDart>& darts,
                       const std::vector<int>& direction, const std::vector<Vec3>& position,
                       CleanReport& r) {
  const std::vector<Dart> border =
      darts_of(topo, darts, 0, darts.size(), [&](std::uint32_t p) { return direction[p]; });
  std::vector<Dart> net = detail::net_darts(border);
  r.border_edges = detail::count_edges(net);
  TriangleSoup caps;
  for (const auto& loop : detail::border_loops(std::move(net))) {
    append_cap(position, loop, caps);
    ++r.holes;
  }
  r.cap_triangles = caps.triangles.size();
  return caps;
}

}  // namespace

CleanResult clean_soup(const TriangleSoup& soup, const CleanOptions& options) {
  detail::require_indices_in_range(soup);
  detail::begin_stage(options.progress, "clean");
  const SoupTopology topo = detail::analyze_soup(soup);
  CleanResult result;
  CleanReport& r = result.report;
  r.input_points = soup.points.size();
  r.input_triangles = soup.triangles.size();
  r.merged_points = soup.points.size() - topo.vertex_count;

  // The five steps of clean.hpp.
  const std::vector<Vec3> position = vertex_positions(soup, topo);
  const std::vector<std::uint8_t> keep = kept_triangles(topo, r);
  const Pieces pieces = orient_pieces(topo, keep, position, options.orient);
  r.pieces = pieces.first.size();
  const std::vector<PieceDart> darts = piece_borders(topo, keep, pieces);
  const std::vector<int> direction =
      options.orient
          ? outward_directions(topo, keep, pieces,
                               piece_volumes(topo, keep, pieces, darts, position), position, r)
          : std::vector<int>(pieces.first.size(), 1);
  result.soup = oriented_soup(topo, keep, pieces, direction, position, r, result.reversed);
  r.vertices = result.soup.points.size();
  result.caps = cap_holes(topo, darts, direction, position, r);
  return result;
}

}  // namespace tpmsfill
