/// @file bspline_basis.hpp
/// @brief The B-spline basis in one place: the clamped uniform knots, and the p + 1 functions
/// of degree p that are not zero on one knot span with their derivatives, by Cox–de Boor's
/// recurrence in the form of The NURBS Book's algorithm A2.3. The scanned field's trivariate
/// B-spline (bspline.cpp) and the material solid's THB splines (thb_basis.cpp) both use it.
#pragma once

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <utility>

namespace tpmsfill::detail {

/// Knot q of the clamped uniform knot vector of degree p with `spans` spans: p + 1 zeros, then
/// s / spans for s = 1 .. spans − 1, then p + 1 ones.
inline double clamped_uniform_knot(std::ptrdiff_t q, int p, std::int64_t spans) {
  return std::clamp(static_cast<double>(q - p) / static_cast<double>(spans), 0.0, 1.0);
}

/// ders[k][r] = the k-th derivative at t of the degree-p B-spline that starts at knot
/// span − p + r (r = 0 .. p), for k = 0 .. n; rows above min(n, p) are zero. `knot(q)` returns
/// knot q of the knot vector (a function, so that a uniform one need not be stored).
/// Preconditions: p + 1 ≤ Width and n < Rows; knot(span) ≤ t ≤ knot(span + 1) and
/// knot(span) < knot(span + 1), so that every knot difference the recurrence divides by spans
/// the non-empty span and is positive.
template <class Knot, std::size_t Rows, std::size_t Width>
void basis_derivatives(const Knot& knot, std::ptrdiff_t span, int p, double t, int n,
                       double (&ders)[Rows][Width]) {
  static_assert(Rows >= 1 && Width >= 1);
  for (std::size_t k = 0; k < Rows; ++k) std::fill(ders[k], ders[k] + Width, 0.0);
  n = std::min(n, p);
  // ndu[r][j], r ≤ j: the degree-j functions; ndu[j][r], r < j: the knot differences.
  double ndu[Width][Width], left[Width], right[Width];
  ndu[0][0] = 1;
  for (int j = 1; j <= p; ++j) {
    left[j] = t - knot(span + 1 - j);
    right[j] = knot(span + j) - t;
    double saved = 0;
    for (int r = 0; r < j; ++r) {
      ndu[j][r] = right[r + 1] + left[j - r];
      const double temp = ndu[r][j - 1] / ndu[j][r];
      ndu[r][j] = saved + right[r + 1] * temp;
      saved = left[j - r] * temp;
    }
    ndu[j][j] = saved;
  }
  for (int r = 0; r <= p; ++r) ders[0][r] = ndu[r][p];
  // The derivatives: differences of the lower degrees' functions over the knot differences.
  for (int r = 0; r <= p; ++r) {
    double a[2][Width] = {};
    a[0][0] = 1;
    int s1 = 0, s2 = 1;
    for (int k = 1; k <= n; ++k) {
      double d = 0;
      const int rk = r - k, pk = p - k;
      if (r >= k) {
        a[s2][0] = a[s1][0] / ndu[pk + 1][rk];
        d = a[s2][0] * ndu[rk][pk];
      }
      const int j1 = rk >= -1 ? 1 : -rk, j2 = r - 1 <= pk ? k - 1 : p - r;
      for (int j = j1; j <= j2; ++j) {
        a[s2][j] = (a[s1][j] - a[s1][j - 1]) / ndu[pk + 1][rk + j];
        d += a[s2][j] * ndu[rk + j][pk];
      }
      if (r <= pk) {
        a[s2][k] = -a[s1][k - 1] / ndu[pk + 1][r];
        d += a[s2][k] * ndu[r][pk];
      }
      ders[k][r] = d;
      std::swap(s1, s2);
    }
  }
  for (int k = 1, factor = p; k <= n; factor *= p - k, ++k)
    for (int r = 0; r <= p; ++r) ders[k][r] *= factor;
}

}  // namespace tpmsfill::detail
