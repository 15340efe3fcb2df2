/// @file spline_terms.hpp
/// @brief The one loop over a spline element's terms (thb_basis.hpp's extraction rows) that
/// every evaluation and every fit sum goes through.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>

#include "tpmsfill/solid/solid_spline.hpp"
#include "tpmsfill/solid/thb_basis.hpp"

namespace tpmsfill::detail {

/// visit(c, function, weight) for every local B-spline c (0..63) of `element` and every basis
/// function in its row: on the element, function = Σ weight · local B-spline c.
template <class Visit>
void for_each_term(const SplineBasis& basis, std::size_t element, const Visit& visit) {
  for (int c = 0; c < 64; ++c) {
    const std::uint32_t row = basis.element_rows[64 * element + c];
    for (std::uint32_t t = basis.row_start[row]; t < basis.row_start[row + 1]; ++t)
      visit(c, basis.row_function[t], basis.row_weight[t]);
  }
}

/// The four cubic B-splines of span `span` of a level with `spans` spans at t, and their first
/// `derivatives` (≤ 2) derivatives: ders[k][i] is the kth derivative of the span's ith.
void span_basis(std::uint32_t spans, std::uint32_t span, double t, int derivatives,
                double (&ders)[3][4]);

/// The element's 1D cubic B-splines per axis at (u, v, w): axis[a][k][i] is the kth
/// derivative (k ≤ `derivatives` ≤ 2) of the ith B-spline along axis a; local B-spline
/// (i, j, l) is their product (local_basis()).
void axis_basis(const SplineBasis& basis, std::size_t element, std::array<double, 3> uvw,
                int derivatives, double (&axis)[3][3][4]);

/// G and M at (u, v, w), clamped onto the cube; their derivatives too when asked (what
/// evaluate_solid returns), else left zero: the slices' samples need none.
SolidPoint solid_point(const SolidSpline& spline, std::array<double, 3> uvw, bool derivatives);

}  // namespace tpmsfill::detail
