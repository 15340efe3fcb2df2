/// @file cap_winding.hpp
/// @brief What the hole caps add to the winding number, and where they can matter.
///
/// clean_soup() closes a model M's holes with caps C, so that M ∪ C bounds a volume and its
/// winding number is the signed crossing count J along a ray. The model's own winding number
/// is then w_M = J_M + R, where J_M counts M's crossings from x = −∞ to p and R depends only
/// on the holes' rims, not on the caps' shape. Take the surface S that sweeps the rims
/// (oriented as C's border) to x = −∞: C ∪ −S is closed apart from its end at x = −∞, the
/// ray along x never crosses S, and far out at x = −∞ the ray is inside S's tubes as often as
/// the rims' projection on the yz plane winds around the row (ω). So
///   R(p) = −w_S(p) − ω(p.y, p.z),
/// and each rim edge (a, b) sweeps a strip whose solid angle at p is the spherical triangle
/// (â, b̂, −x̂): R needs no caps at all, only the rim edges, and ω is one number per row.
///
/// A rim is evaluated through a hierarchy over runs of consecutive edges, in the manner of
/// Barill et al. (SIGGRAPH 2018): a run far from p (its centre farther than kFarFactor times
/// its radius, and p not behind it along the ray) counts as the strip of its chord plus the
/// dipole of the small loop that run and chord make; near runs are opened down to exact
/// strips. Each connected patch of caps (one per hole) bounds where it can matter at all: a
/// surface of area A at distance d subtends at most A / d² steradians.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "tpmsfill/types.hpp"

namespace tpmsfill::detail {

class CapWinding {
 public:
  CapWinding() = default;
  /// From the caps (CleanResult::caps): their patches bound where they matter, their border
  /// loops (in the caps' border direction, the reverse of the model's) are the rims.
  explicit CapWinding(const TriangleSoup& caps);

  bool empty() const { return rims_.empty(); }
  const Box3& bounds() const { return box_; }  ///< of the caps

  /// Upper bound on the caps' |w_C(p)|: where it is below ½, J alone decides.
  double bound(const Vec3& p) const;
  /// Upper bound on |w_C| anywhere on the grid row through (y, z).
  double row_bound(double y, double z) const;

  /// ω: how often the rims' projection on the yz plane winds counter-clockwise around
  /// (y, z) (the same for every point of a grid row).
  int shadow_winding(double y, double z) const;
  /// R(p) by the hierarchy (far runs as chord + dipole, near edges exact); `shadow` is
  /// shadow_winding(p.y, p.z). If `rim_distance` is given it receives a lower bound on the
  /// distance from p to the rims (R varies on that scale).
  double remainder(const Vec3& p, int shadow, double* rim_distance = nullptr) const;
  /// R(p), every rim edge exact (the reference for remainder()).
  double remainder_exact(const Vec3& p) const;

 private:
  struct Run {
    std::uint32_t begin = 0, end = 0;  ///< edges [begin, end) of points_ (edge i: i → i + 1)
    std::uint32_t left = 0;            ///< children left, left + 1; 0 for a leaf
    Vec3 centre;
    double radius = 0;
    Vec3 area;  ///< vector area of the loop run + chord back to its start
    Box3 box;
  };
  void build(std::uint32_t run);

  std::vector<Vec3> points_;         ///< rims one after the other, each closed by repeating
                                     ///< its first corner
  std::vector<std::uint32_t> rims_;  ///< root run of each rim
  std::vector<Run> runs_;
  struct Patch {
    Box3 box;
    double area = 0;
  };
  std::vector<Patch> patches_;  ///< connected pieces of the caps
  Box3 box_;
};

}  // namespace tpmsfill::detail
