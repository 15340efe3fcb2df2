/// @file region_distance.hpp
/// @brief Signed distance to a blend region's boundary (negative inside), one evaluator for
/// the design's rows and the design review: planes, slabs, spheres, cylinders in closed form,
/// seed 004's polygon regions through their outline in their plane (round joins: the
/// Euclidean distance; miter joins: the mitered offset through the point, read from the
/// outline's straight skeletons, any simple outline).
#pragma once

#include <algorithm>
#include <cmath>
#include <optional>

#include "lattice/internal/polygon_distance.hpp"
#include "lattice/internal/polygon_miter.hpp"
#include "tpmsfill/lattice/design.hpp"

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
    if (r.join == RingJoin::Round)
      polygon_.emplace(r.loop, reach);
    else
      miter_.emplace(r.loop, reach);
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
        return polygon_ ? (*polygon_)(q) : (*miter_)(q);
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
  Region r_;
  Vec3 n_{}, u_{}, v_{};
  std::optional<PolygonDistance> polygon_;     // round joins
  std::optional<PolygonMiterDistance> miter_;  // miter joins
};

}  // namespace tpmsfill::detail
