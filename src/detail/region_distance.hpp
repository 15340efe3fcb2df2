/// @file region_distance.hpp
/// @brief Signed distance to a blend region's boundary (negative inside), one evaluator for
/// the design's rows and the design review: planes, slabs, spheres, cylinders in closed form,
/// seed 004's polygon regions through their outline in their plane (round joins: the
/// Euclidean distance; miter joins, convex outlines: the largest distance to an edge's line).
#pragma once

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>

#include "detail/polygon_distance.hpp"
#include "tpmsfill/design.hpp"

namespace tpmsfill::detail {

class RegionDistance {
 public:
  explicit RegionDistance(const Region& r) : r_(r) {
    const double length = norm(r.axis);
    n_ = length > 0 ? (1 / length) * r.axis : Vec3{};
    if (r.shape != RegionShape::Polygon) return;
    u_ = (1 / norm(r.u)) * r.u;
    const Vec3 v = r.v - dot(r.v, u_) * u_;
    v_ = (1 / norm(v)) * v;
    const double reach = std::max(std::fabs(r.inner), std::fabs(r.outer)) + 1e-9;
    if (r.join == RingJoin::Round) polygon_.emplace(r.loop, reach);
  }

  /// Signed distance, mm, negative inside (a polygon: in its plane, exact up to the outer and
  /// inner rings; beyond them it is only known to be farther).
  double operator()(Vec3 p) const {
    const Vec3 d = p - r_.point;
    switch (r_.shape) {
      case RegionShape::HalfSpace:
        return -dot(d, n_);
      case RegionShape::Slab:
        return std::fabs(dot(d, n_)) - 0.5 * r_.size;
      case RegionShape::Sphere:
        return norm(d) - r_.size;
      case RegionShape::Cylinder:
        return norm(d - dot(d, n_) * n_) - r_.size;
      case RegionShape::Polygon: {
        const std::array<double, 2> q{dot(d, u_), dot(d, v_)};
        return polygon_ ? (*polygon_)(q) : miter(q);
      }
    }
    return 0;
  }

  /// Where the transition is at p: 0 at its outer edge, 1 at its inner edge, clamped (a
  /// polygon's rings: `outer` outside and `inner` inside its outline; the other shapes: a band
  /// of `width` centred on the boundary).
  double transition(Vec3 p, double width) const {
    const double d = (*this)(p);
    if (r_.shape == RegionShape::Polygon)
      return std::clamp((r_.outer - d) / (r_.inner + r_.outer), 0.0, 1.0);
    return std::clamp(0.5 - d / width, 0.0, 1.0);
  }

 private:
  // Mitered offsets of a convex outline: the largest signed distance to an edge's line.
  double miter(std::array<double, 2> q) const {
    double best = -std::numeric_limits<double>::infinity();
    const auto& l = r_.loop;
    const double orientation = signed_area() > 0 ? 1 : -1;  // outward normals either way
    for (std::size_t i = 0; i < l.size(); ++i) {
      const auto a = l[i], b = l[(i + 1) % l.size()];
      const double ex = b[0] - a[0], ey = b[1] - a[1], len = std::hypot(ex, ey);
      if (len == 0) continue;
      const double nx = orientation * ey / len, ny = -orientation * ex / len;
      best = std::max(best, nx * (q[0] - a[0]) + ny * (q[1] - a[1]));
    }
    return best;
  }
  double signed_area() const {
    double s = 0;
    const auto& l = r_.loop;
    for (std::size_t i = 0; i < l.size(); ++i) {
      const auto a = l[i], b = l[(i + 1) % l.size()];
      s += a[0] * b[1] - a[1] * b[0];
    }
    return 0.5 * s;
  }

  Region r_;
  Vec3 n_{}, u_{}, v_{};
  std::optional<PolygonDistance> polygon_;
};

}  // namespace tpmsfill::detail
