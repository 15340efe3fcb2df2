/// @file polygon_distance.hpp
/// @brief Signed distance to a closed polygon in the plane (negative inside), for seed 004's
/// ring regions: exact (the nearest segment), with segments sorted into square buckets so a
/// query near the outline looks at a few segments, and inside/outside far from it read from the
/// bucket's centre (whose side is precomputed) plus the crossings between centre and query.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <vector>

namespace tpmsfill::detail {

class PolygonDistance {
 public:
  using Point = std::array<double, 2>;

  /// @param loop   the polygon's corners in order (closed implicitly), at least 3
  /// @param reach  distances up to this are exact; beyond it only the sign is (|value| > reach)
  PolygonDistance(const std::vector<Point>& loop, double reach) : loop_(loop), reach_(reach) {
    lo_ = hi_ = loop.front();
    for (const Point& p : loop)
      for (int a = 0; a < 2; ++a) lo_[a] = std::min(lo_[a], p[a]), hi_[a] = std::max(hi_[a], p[a]);
    for (int a = 0; a < 2; ++a) lo_[a] -= reach, hi_[a] += reach;
    // About four segments a bucket, at least the reach wide so a query's candidates are local.
    const double area = (hi_[0] - lo_[0]) * (hi_[1] - lo_[1]);
    size_ = std::max({std::sqrt(area * 4.0 / static_cast<double>(loop.size())), reach,
                      1e-9 * std::max(hi_[0] - lo_[0], hi_[1] - lo_[1])});
    for (int a = 0; a < 2; ++a)
      n_[a] = std::clamp(static_cast<int>((hi_[a] - lo_[a]) / size_) + 1, 1, 2048);
    start_.assign(std::size_t(n_[0]) * n_[1] + 1, 0);
    // Segments into every bucket their box grown by the reach touches (two passes: count, fill).
    for (int pass = 0; pass < 2; ++pass) {
      std::vector<std::uint32_t> next(start_.begin(), start_.end() - 1);
      for (std::size_t s = 0; s < loop.size(); ++s) {
        const Point a = loop[s], b = loop[(s + 1) % loop.size()];
        const int i0 = cell(std::min(a[0], b[0]) - reach, 0),
                  i1 = cell(std::max(a[0], b[0]) + reach, 0);
        const int j0 = cell(std::min(a[1], b[1]) - reach, 1),
                  j1 = cell(std::max(a[1], b[1]) + reach, 1);
        for (int j = j0; j <= j1; ++j)
          for (int i = i0; i <= i1; ++i) {
            const std::size_t k = std::size_t(i) + std::size_t(n_[0]) * j;
            if (pass == 0)
              ++start_[k + 1];
            else
              segments_[next[k]++] = static_cast<std::uint32_t>(s);
          }
      }
      if (pass == 0) {
        for (std::size_t k = 1; k < start_.size(); ++k) start_[k] += start_[k - 1];
        segments_.resize(start_.back());
      }
    }
    centre_inside_.resize(std::size_t(n_[0]) * n_[1]);
    for (int j = 0; j < n_[1]; ++j)
      for (int i = 0; i < n_[0]; ++i)
        centre_inside_[std::size_t(i) + std::size_t(n_[0]) * j] = winding_inside(centre(i, j));
  }

  /// Signed distance of p to the outline, negative inside: exact where |value| <= reach.
  double operator()(Point p) const {
    if (p[0] < lo_[0] || p[1] < lo_[1] || p[0] > hi_[0] || p[1] > hi_[1]) return outside_box(p);
    const int i = cell(p[0], 0), j = cell(p[1], 1);
    const std::size_t k = std::size_t(i) + std::size_t(n_[0]) * j;
    double best = std::numeric_limits<double>::infinity();
    bool inside = centre_inside_[k];
    const Point c = centre(i, j);
    for (std::uint32_t n = start_[k]; n < start_[k + 1]; ++n) {
      const std::uint32_t s = segments_[n];
      const Point a = loop_[s], b = loop_[(s + 1) % loop_.size()];
      best = std::min(best, segment_distance(p, a, b));
      if (crosses(c, p, a, b)) inside = !inside;
    }
    const double d = std::min(best, reach_ + size_);  // beyond the reach: only the side counts
    return inside ? -d : d;
  }

 private:
  int cell(double x, int a) const {
    return std::clamp(static_cast<int>(std::floor((x - lo_[a]) / size_)), 0, n_[a] - 1);
  }
  Point centre(int i, int j) const {
    return {lo_[0] + (i + 0.5) * size_, lo_[1] + (j + 0.5) * size_};
  }
  static double segment_distance(Point p, Point a, Point b) {
    const double ex = b[0] - a[0], ey = b[1] - a[1];
    const double len2 = ex * ex + ey * ey;
    double t = len2 > 0 ? ((p[0] - a[0]) * ex + (p[1] - a[1]) * ey) / len2 : 0;
    t = std::clamp(t, 0.0, 1.0);
    return std::hypot(p[0] - a[0] - t * ex, p[1] - a[1] - t * ey);
  }
  static double orient(Point a, Point b, Point c) {
    return (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]);
  }
  // Whether segment pq crosses segment ab. A corner of the outline exactly on pq counts for
  // one of its two segments when pq passes through (their far ends on opposite sides) and for
  // both or neither when it only touches, so the parity stays right.
  static bool crosses(Point p, Point q, Point a, Point b) {
    const double d1 = orient(a, b, p), d2 = orient(a, b, q);
    const double d3 = orient(p, q, a), d4 = orient(p, q, b);
    return ((d1 > 0) != (d2 > 0)) && ((d3 > 0) != (d4 > 0));
  }
  // Even-odd rule by a ray towards +x (vertices on the ray counted half-open).
  bool winding_inside(Point p) const {
    bool inside = false;
    for (std::size_t s = 0; s < loop_.size(); ++s) {
      const Point a = loop_[s], b = loop_[(s + 1) % loop_.size()];
      if ((a[1] > p[1]) != (b[1] > p[1]) &&
          p[0] < a[0] + (p[1] - a[1]) * (b[0] - a[0]) / (b[1] - a[1]))
        inside = !inside;
    }
    return inside;
  }
  double outside_box(Point p) const {  // beyond the grown box: farther than the reach
    const double dx = std::max({lo_[0] - p[0], 0.0, p[0] - hi_[0]});
    const double dy = std::max({lo_[1] - p[1], 0.0, p[1] - hi_[1]});
    return reach_ + size_ + std::hypot(dx, dy);
  }

  std::vector<Point> loop_;
  double reach_ = 0, size_ = 1;
  Point lo_{}, hi_{};
  std::array<int, 2> n_{};
  std::vector<std::uint32_t> start_, segments_;
  std::vector<bool> centre_inside_;
};

}  // namespace tpmsfill::detail
