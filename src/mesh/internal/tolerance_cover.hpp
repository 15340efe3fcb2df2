/// @file tolerance_cover.hpp
/// @brief A proof that every point of a triangle lies within a distance of a set of
/// triangles: the one-sided Hausdorff bound decimation holds, both ways, at every collapse.
/// Plain double arithmetic (no CGAL), so it can be read and tested on its own.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <vector>

#include "mesh/internal/point_triangle.hpp"
#include "tpmsfill/types.hpp"

namespace tpmsfill::detail {

/// A triangle by its corners.
using Corners = std::array<Vec3, 3>;

/// Proves `within(piece, set, candidates)`: every point of the triangle `piece` lies within
/// `tolerance` of one of the triangles `set[i]`, i in `candidates`.
///
/// A convex piece of the triangle is proven when one triangle of the set lies within the
/// tolerance of all its corners (the distance to a triangle is convex, so the whole piece
/// does), or when its corners' distances plus its covering radius stay within the tolerance
/// (the distance to a set is 1-Lipschitz, and every point of a convex polygon of diameter D
/// lies within D/√3 of a corner). Otherwise it is cut: by the three planes that bound the
/// prism over the triangle nearest to its centroid (each through an edge of that
/// triangle, halfway between its normal and its neighbour's across the edge when the
/// neighbour is a candidate), so that the part over that triangle and the parts beyond each
/// edge are proven separately, which takes a piece straddling a crease, a seam or a fan of
/// thin triangles apart; or, when the piece lies within that prism already, by the plane
/// halving its diameter. A piece still unproven after `max_cuts` rounds of cutting, a corner
/// farther than the tolerance from every candidate, or more than `max_pieces` pieces in one
/// call disprove it: the answer is conservative (false can mean "not proven"), never wrong
/// beyond the round-off of the distances.
class ToleranceCover {
 public:
  explicit ToleranceCover(double tolerance, int max_cuts = 10, int max_pieces = 4000)
      : tolerance_(tolerance),
        max_cuts_(max_cuts),
        max_pieces_(max_pieces),
        scratch_(max_cuts + 1) {}

  /// Whether every point of `piece` lies within the tolerance of `set[i]` for some i in
  /// `candidates` (tried in order: put the likeliest first). On true, the indices of the
  /// triangles the proof used are appended to `uses` (with repeats).
  bool within(const Corners& piece, const std::vector<Corners>& set,
              const std::vector<std::uint32_t>& candidates, std::vector<std::uint32_t>& uses) {
    Polygon p;
    p.n = 3;
    std::copy(piece.begin(), piece.end(), p.v.begin());
    pieces_ = 0;
    return prove(p, set, candidates, uses, max_cuts_);
  }

 private:
  /// A convex polygon: a piece of a triangle after a few plane cuts (each adds at most one
  /// corner: at most 3 + 3 * max_cuts corners).
  struct Polygon {
    std::array<Vec3, 40> v;
    int n = 0;
  };

  static Vec3 unit_normal(const Corners& t) {
    const Vec3 n = cross(t[1] - t[0], t[2] - t[0]);
    const double len = norm(n);
    return len > 0 ? (1.0 / len) * n : Vec3{};
  }

  static double squared(Vec3 q, const Corners& t) {
    return squared_distance_to_triangle(q, t[0], t[1], t[2]);
  }

  /// The plane through edge i of `t` (corners i, i+1) that bounds the prism over `t`: along
  /// `t`'s normal, or halfway between it and the normal of a candidate sharing that edge;
  /// its normal points out of the prism. Normal 0 for a degenerate triangle.
  std::pair<Vec3, Vec3> prism_side(const Corners& t, int i, const std::vector<Corners>& set,
                                   const std::vector<std::uint32_t>& candidates) const {
    const Vec3 e0 = t[i], e1 = t[(i + 1) % 3], opposite = t[(i + 2) % 3];
    Vec3 up = unit_normal(t);
    if (dot(up, up) == 0) return {{}, {}};
    for (std::uint32_t k : candidates) {
      const Corners& u = set[k];
      const bool has0 = std::find(u.begin(), u.end(), e0) != u.end();
      const bool has1 = std::find(u.begin(), u.end(), e1) != u.end();
      const bool has_opposite = std::find(u.begin(), u.end(), opposite) != u.end();
      if (has0 && has1 && !has_opposite) {
        const Vec3 mid = up + unit_normal(u);
        if (dot(mid, mid) > 1e-12) up = mid;
        break;
      }
    }
    Vec3 normal = cross(e1 - e0, up);
    if (dot(opposite - e0, normal) > 0) normal = -1.0 * normal;
    return {e0, normal};
  }

  /// Cuts `p` by the plane through `origin` with normal `normal` into the part on its
  /// negative side and the part on its positive side (corners on the plane, within round-off,
  /// go to both). False, with the parts unset, when the plane does not cross `p`'s interior:
  /// then one side holds all of `p`.
  static bool cut(const Polygon& p, Vec3 origin, Vec3 normal, Polygon& below, Polygon& above) {
    std::array<double, 40> d;
    double reach = 0;
    for (int i = 0; i < p.n; ++i) reach = std::max(reach, norm(p.v[i] - origin));
    const double snap = 1e-12 * norm(normal) * reach;
    bool negative = false, positive = false;
    for (int i = 0; i < p.n; ++i) {
      d[i] = dot(p.v[i] - origin, normal);
      if (std::abs(d[i]) <= snap) d[i] = 0;
      negative = negative || d[i] < 0;
      positive = positive || d[i] > 0;
    }
    if (!negative || !positive) return false;
    below.n = above.n = 0;
    auto add = [](Polygon& q, Vec3 x) {
      if (q.n == 0 || !(q.v[q.n - 1] == x)) q.v[q.n++] = x;
    };
    for (int i = 0; i < p.n; ++i) {
      const int j = (i + 1) % p.n;
      const Vec3 a = p.v[i], b = p.v[j];
      if (d[i] <= 0) add(below, a);
      if (d[i] >= 0) add(above, a);
      if ((d[i] < 0 && d[j] > 0) || (d[i] > 0 && d[j] < 0)) {
        const Vec3 x = a + (d[i] / (d[i] - d[j])) * (b - a);
        add(below, x);
        add(above, x);
      }
    }
    for (Polygon* q : {&below, &above})
      if (q->n > 1 && q->v[0] == q->v[q->n - 1]) --q->n;
    return true;
  }

  bool prove(const Polygon& p, const std::vector<Corners>& set,
             const std::vector<std::uint32_t>& candidates, std::vector<std::uint32_t>& uses,
             int cuts) {
    const double tolerance2 = tolerance_ * tolerance_;
    double diameter2 = 0;
    int far_a = 0, far_b = 1;
    for (int i = 0; i < p.n; ++i)
      for (int j = i + 1; j < p.n; ++j) {
        const double d = dot(p.v[j] - p.v[i], p.v[j] - p.v[i]);
        if (d > diameter2) diameter2 = d, far_a = i, far_b = j;
      }
    const double radius = std::sqrt(diameter2 / 3.0);
    const double reach = tolerance_ + radius;
    std::array<double, 32> nearest;
    std::array<std::uint32_t, 32> nearest_at{};
    nearest.fill(std::numeric_limits<double>::infinity());
    std::vector<std::uint32_t>& kept = scratch_[cuts];
    kept.clear();
    for (std::uint32_t i : candidates) {
      bool all = true;
      double closest = std::numeric_limits<double>::infinity();
      for (int j = 0; j < p.n; ++j) {
        const double d = squared(p.v[j], set[i]);
        all = all && d <= tolerance2;
        if (d < nearest[j]) nearest[j] = d, nearest_at[j] = i;
        closest = std::min(closest, d);
      }
      if (all) {
        uses.push_back(i);
        return true;
      }
      // Farther than tolerance + radius from every corner: out of reach of the whole piece.
      if (closest <= reach * reach) kept.push_back(i);
    }
    const double worst = *std::max_element(nearest.begin(), nearest.begin() + p.n);
    if (worst > tolerance2) return false;
    if (std::sqrt(worst) + radius <= tolerance_) {
      uses.insert(uses.end(), nearest_at.begin(), nearest_at.begin() + p.n);
      return true;
    }
    if (cuts == 0 || ++pieces_ > max_pieces_) return false;
    // The pieces below write scratch_[cuts - 1] and deeper, never this level's list: no copy.
    const std::vector<std::uint32_t>& passed = kept;
    // Peel the parts beyond each side of the prism over the triangle nearest to the piece's
    // centroid (it overlaps the piece, so every part peeled off is smaller than the piece).
    Vec3 centroid{};
    for (int j = 0; j < p.n; ++j) centroid = centroid + p.v[j];
    centroid = (1.0 / p.n) * centroid;
    std::uint32_t at = nearest_at[0];
    double best = std::numeric_limits<double>::infinity();
    for (std::uint32_t i : passed) {
      const double d = squared(centroid, set[i]);
      if (d < best) best = d, at = i;
    }
    const Corners& a = set[at];
    Polygon inside = p, below, above;
    bool peeled = false;
    for (int i = 0; i < 3; ++i) {
      const auto [origin, normal] = prism_side(a, i, set, passed);
      if (dot(normal, normal) == 0) break;
      if (!cut(inside, origin, normal, below, above)) continue;  // not across the piece
      if (!prove(above, set, passed, uses, cuts - 1)) return false;
      inside = below;
      peeled = true;
    }
    if (peeled) return prove(inside, set, passed, uses, cuts - 1);
    // The piece lies over that triangle already: halve it.
    if (!cut(p, 0.5 * (p.v[far_a] + p.v[far_b]), p.v[far_b] - p.v[far_a], below, above))
      return false;  // a point, and not near enough
    return prove(below, set, passed, uses, cuts - 1) && prove(above, set, passed, uses, cuts - 1);
  }

  double tolerance_;
  int max_cuts_;
  int max_pieces_;
  int pieces_ = 0;                                   ///< cut pieces in this call of within()
  std::vector<std::vector<std::uint32_t>> scratch_;  ///< per remaining cuts: candidates kept
};

}  // namespace tpmsfill::detail
