// Exact check of a layer's contours (CGAL Epick): segments are bucketed on a grid as coarse
// as the longest segment, so only segments in neighbouring buckets can meet.
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/intersections.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

#include "tpmsfill/slice.hpp"

namespace tpmsfill {
namespace {

using K = CGAL::Exact_predicates_inexact_constructions_kernel;
using P2 = K::Point_2;

struct Segment {
  P2 a, b;
  std::uint32_t contour, index, size;  // index: position of a in its contour of `size` points
};

// Whether s and t are neighbours along one contour: t starts where s ends, or the other way.
bool consecutive(const Segment& s, const Segment& t) {
  if (s.contour != t.contour) return false;
  return (s.index + 1) % s.size == t.index || (t.index + 1) % t.size == s.index;
}

// Consecutive segments p→q, q→r share q and nothing else unless r turns back along p→q.
bool folds(const P2& p, const P2& q, const P2& r) {
  return CGAL::collinear(p, q, r) && !CGAL::collinear_are_strictly_ordered_along_line(p, q, r);
}

bool defect(const Segment& s, const Segment& t) {
  if (consecutive(s, t)) {
    if (s.size < 3) return true;
    return (s.index + 1) % s.size == t.index ? folds(s.a, s.b, t.b) : folds(t.a, t.b, s.b);
  }
  return CGAL::do_intersect(K::Segment_2(s.a, s.b), K::Segment_2(t.a, t.b));
}

}  // namespace

std::uint64_t count_contour_defects(const std::vector<Contour>& contours, double spacing,
                                    std::uint64_t* pairs_checked) {
  std::vector<Segment> segs;
  double longest = spacing > 0 && std::isfinite(spacing) ? spacing : 0;
  std::uint64_t bad = 0;
  for (std::uint32_t c = 0; c < contours.size(); ++c) {
    const std::vector<Vec2>& pts = contours[c].points;
    const auto n = static_cast<std::uint32_t>(pts.size());
    if (n < 3) ++bad;  // not a contour: it bounds nothing
    for (std::uint32_t k = 0; k < n; ++k) {
      const Vec2 a = pts[k], b = pts[(k + 1) % n];
      segs.push_back({P2(a.x, a.y), P2(b.x, b.y), c, k, n});
      longest = std::max({longest, std::fabs(b.x - a.x), std::fabs(b.y - a.y)});
    }
  }
  if (segs.empty() || !(longest > 0)) return bad;
  // Two segments whose boxes meet have midpoints within `longest` on each axis, so their
  // buckets (of that size) differ by at most one.
  struct Entry {
    std::int64_t bx, by;
    std::uint32_t seg;
    bool operator<(const Entry& o) const {
      return bx != o.bx ? bx < o.bx : (by != o.by ? by < o.by : seg < o.seg);
    }
  };
  std::vector<Entry> entries(segs.size());
  for (std::uint32_t s = 0; s < segs.size(); ++s) {
    const double mx = 0.5 * (segs[s].a.x() + segs[s].b.x()),
                 my = 0.5 * (segs[s].a.y() + segs[s].b.y());
    entries[s] = {static_cast<std::int64_t>(std::floor(mx / longest)),
                  static_cast<std::int64_t>(std::floor(my / longest)), s};
  }
  std::sort(entries.begin(), entries.end());
  auto bucket = [&](std::int64_t bx, std::int64_t by) {
    const auto lo = std::lower_bound(entries.begin(), entries.end(), Entry{bx, by, 0});
    auto hi = lo;
    while (hi != entries.end() && hi->bx == bx && hi->by == by) ++hi;
    return std::pair{lo, hi};
  };
  std::uint64_t pairs = 0;
  for (std::size_t e = 0; e < entries.size();) {
    const auto [lo, hi] = bucket(entries[e].bx, entries[e].by);
    // Pairs within the bucket, then with the four neighbours ahead of it (each pair once).
    for (auto s = lo; s != hi; ++s)
      for (auto t = s + 1; t != hi; ++t) ++pairs, bad += defect(segs[s->seg], segs[t->seg]);
    const std::int64_t ahead[4][2] = {{1, -1}, {1, 0}, {1, 1}, {0, 1}};
    for (const auto& d : ahead) {
      const auto [nlo, nhi] = bucket(lo->bx + d[0], lo->by + d[1]);
      for (auto s = lo; s != hi; ++s)
        for (auto t = nlo; t != nhi; ++t) ++pairs, bad += defect(segs[s->seg], segs[t->seg]);
    }
    e = static_cast<std::size_t>(hi - entries.begin());
  }
  if (pairs_checked) *pairs_checked = pairs;
  return bad;
}

}  // namespace tpmsfill
