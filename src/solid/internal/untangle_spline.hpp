/// @file untangle_spline.hpp
/// @brief Internal: moves some control points of a solid's geometry spline G so that det J_G > 0
/// at every Jacobian sample, by the foldover-free energy of untangle.hpp with a position term.
/// Used by the spline fit (solid_spline.cpp): a cubic spline fitted to a fold-free piecewise-
/// linear map folds where the map's Jacobian changes faster than an element, near the cube's
/// edges and corners above all.
///
/// At sample q, J = J_G(q) R_q⁻¹, R_q a reference Jacobian (the tets' own map there), so that
/// J = I where G follows the tets. The energy is Σ_q ω_q f_ε(J_q) (ω_q the samples' weights
/// scaled to sum to 1; the fit gives each Gauss point its quadrature weight · det R_q) plus
/// fidelity · Σ_k w_k |G(x_k) − target_k|² / (its value at the start), so that the positions stay
/// near the fit's while the folds open.
#pragma once

#include <array>
#include <cstdint>
#include <functional>
#include <vector>

#include "solid/internal/untangle.hpp"
#include "tpmsfill/solid/thb_basis.hpp"

namespace tpmsfill::detail {

/// Where det J_G must be positive: a point of an element, its weight and R_q⁻¹ (det R_q > 0).
struct JacobianSample {
  std::uint32_t element = 0;
  std::array<double, 3> uvw{};
  double weight = 0;
  Matrix3 reference_inverse{};
};

/// Where G should stay: a point of an element, its weight and the position G should have.
struct PositionSample {
  std::uint32_t element = 0;
  std::array<double, 3> uvw{};
  double weight = 0;
  std::array<double, 3> target{};
};

/// Moves the functions with `movable` set (G's coefficients c, 3 per function) to make
/// det J_G > 0 at every sample; the others stay.
/// @pre both sample lists sorted by element; every element with a sample in the support of a
///      movable function has its samples listed (the rest of the spline is not looked at)
/// @param[in] fidelity  the position term's weight against the Jacobian term's, at the start
UntangleResult untangle_spline(const SplineBasis& basis, const std::vector<char>& movable,
                               const std::vector<JacobianSample>& jacobians,
                               const std::vector<PositionSample>& positions, double fidelity,
                               std::vector<double>& c,
                               const std::function<void(double)>& report = {});

}  // namespace tpmsfill::detail
