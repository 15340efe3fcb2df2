/// @file solid_inverse.hpp
/// @brief Point inversion of a fitted solid, G⁻¹(p) (Li & Fu 2021, §2.3.3): the parameter
/// point whose image under G is p, so that the material can be asked anywhere in mm,
/// m(p) = M(G⁻¹(p)).
///
/// Newton's method in the cube, x ← x − J_G(x)⁻¹ (G(x) − p), clamped onto the cube, started
/// from the nearest of G's images of every element's centre (a bucket grid over them), then
/// from the next nearest when it does not converge. A point outside the solid ends on the
/// cube's boundary with its distance left: it is reported as not inside.
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <vector>

#include "tpmsfill/solid/solid_spline.hpp"
#include "tpmsfill/types.hpp"

namespace tpmsfill {

/// Where Newton starts: G at every element's centre, bucketed in mm. Plain data.
struct SolidLocator {
  std::vector<std::array<double, 3>> uvw;   ///< per start, its parameter point
  std::vector<Vec3> image;                  ///< per start, G there, mm
  Vec3 origin;                              ///< of the bucket grid, mm
  double bucket = 1;                        ///< bucket edge, mm
  std::array<int, 3> buckets{};             ///< per axis
  std::vector<std::uint32_t> bucket_start;  ///< buckets product + 1 offsets (x fastest)
  std::vector<std::uint32_t> bucket_items;  ///< start ids, bucket after bucket
  double size = 1;                          ///< the images' box diagonal, mm
};

SolidLocator build_solid_locator(const SolidSpline& spline);

struct InverseOptions {
  /// Converged when |G(x) − p| is below this share of the solid's size (its box diagonal).
  double tolerance = 1e-9;
  int max_iterations = 30;  ///< Newton steps per start
  int max_starts = 8;       ///< nearest starts tried
};

struct Preimage {
  std::array<double, 3> uvw{};  ///< the parameter point found
  double distance = 0;          ///< |G(uvw) − p|, mm
  bool inside = false;          ///< converged: G(uvw) = p to the tolerance
  int iterations = 0;           ///< Newton steps, over all starts
};

/// G⁻¹(p): see the file comment. Deterministic; safe to call from many threads.
/// @param start  where Newton starts first (a neighbouring point's preimage, when walking a
///               grid), before the locator's starts
Preimage invert_solid(const SolidSpline& spline, const SolidLocator& locator, Vec3 p,
                      const InverseOptions& options = {},
                      const std::optional<std::array<double, 3>>& start = {});

/// M(G⁻¹(p)) when p is inside the solid (and the spline has a material), else nothing.
std::optional<double> material_at(const SolidSpline& spline, const SolidLocator& locator, Vec3 p,
                                  const InverseOptions& options = {});

}  // namespace tpmsfill
