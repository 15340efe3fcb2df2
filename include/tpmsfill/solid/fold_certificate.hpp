/// @file fold_certificate.hpp
/// @brief A proof, element by element, that a fitted solid's geometry map G does not fold:
/// det J_G > 0 everywhere in the element, not only at the points a fit watches.
///
/// On one element G is a tensor-product cubic, so det J_G is a polynomial of degree 8 along
/// each axis (∂_u G is quadratic in u and cubic in v and w, and a determinant multiplies one
/// derivative along each axis). Its 9³ values on the element's grid of eighths fix it, and
/// their Bernstein coefficients follow by one 9 × 9 solve per axis. The polynomial lies within
/// the range of its Bernstein coefficients, so all of them positive proves det J_G > 0 on the
/// whole element (the bound Johnen, Remacle & Geuzaine 2013 use to prove curved finite
/// elements valid, with the same subdivision). Where some are not, the element is halved along
/// every axis (de Casteljau), up to `depth` times: a sub-box's corner coefficient is det J_G at
/// that corner, so a corner ≤ 0 is a fold found, and a box whose coefficients are all positive is
/// proven. What is left after `depth` halvings is undecided.
///
/// Floating point: a coefficient counts as positive when it exceeds 10⁻⁹ of the largest in
/// its element, well above the conversion's round-off (the 9 × 9 solve's condition number is
/// under 10³).
#pragma once

#include <array>
#include <cstddef>

#include "tpmsfill/solid/solid_spline.hpp"

namespace tpmsfill {

/// Per element of the spline's basis, what was shown about det J_G there.
struct FoldCertificate {
  std::size_t elements = 0;
  std::size_t proven = 0;     ///< det J_G > 0 on the whole element
  std::size_t folded = 0;     ///< a point with det J_G ≤ 0 found
  std::size_t undecided = 0;  ///< neither after the halvings
  std::size_t boxes = 0;      ///< sub-boxes examined, over all elements
  /// When folded > 0: the found point where det J_G is least, in the cube, and its value.
  std::array<double, 3> fold{};
  double fold_det = 0;
};

struct FoldCertificateOptions {
  int depth = 6;  ///< halvings of an element, at most
};

/// Proves det J_G > 0 element by element (see the file comment). Parallel; the counts are
/// the same whatever the thread count.
/// @throws InputError  a spline without control points for its basis
FoldCertificate certify_fold_free(const SolidSpline& spline,
                                  const FoldCertificateOptions& options = {});

}  // namespace tpmsfill
