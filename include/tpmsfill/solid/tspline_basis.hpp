/// @file tspline_basis.hpp
/// @brief Li & Fu 2021's trivariate cubic T-splines (§2.1) on the cube octree's T-mesh, in
/// the extraction form of thb_basis.hpp, so that the fit, the fold bound, inversion and
/// slicing run on them as on THB.
///
/// The anchors are the T-mesh's vertices: every corner of a cell, hanging ones too. From an
/// anchor a ray along each axis, each way, records the first two T-mesh faces normal to that
/// axis that it crosses (a face counts where the ray touches it, as in Sederberg et al.
/// 2003); they make the function's local knot vector [ξ−2, ξ−1, anchor, ξ+1, ξ+2] along that
/// axis, a ray leaving the cube repeating its face. An anchor on the face u = 0 also anchors
/// a function with knots [0, 0, 0, 0, ξ+1] along u (u = 1 alike), as a clamped B-spline's
/// first one: so a uniform T-mesh gives exactly the tensor-product basis. φ_i = N_i^u N_i^v
/// N_i^w, no weights (the seed's T-splines are polynomial).
///
/// The elements are the T-mesh's cells, split into their octree children while a knot of a
/// function non-zero there lies inside: so every function is one polynomial on an element,
/// a combination of the element's 64 local B-splines of its level (the rows), each weight
/// the blossom of the function's piece at that B-spline's three inner knots.
///
/// On an arbitrary T-mesh the functions need not sum to one nor be linearly independent.
/// check_tspline() measures both: the largest |Σ φ_i − 1| (exact from the rows) and the pairs
/// of functions with overlapping supports whose knot vectors overlap along no axis (none:
/// the T-mesh is dual-compatible, which makes its functions linearly independent; Beirão da
/// Veiga, Buffa, Sangalli & Vázquez 2013). Splitting the cells the check names does not make
/// both hold (docs/benchmarks.md §21d: a corner-crowded octree grew to 53,859 cells in three
/// passes, with more failures each pass), so the fit does not offer this basis.
#pragma once

#include <array>
#include <cstddef>
#include <vector>

#include "tpmsfill/solid/cube_octree.hpp"
#include "tpmsfill/solid/thb_basis.hpp"

namespace tpmsfill {

/// The T-spline basis on the T-mesh of `tmesh`'s leaves (kind SplineKind::tspline).
/// @throws InputError  leaves that do not tile the cube
SplineBasis tspline_basis(const CubeOctree& tmesh);

/// What makes a T-spline basis fit to be fitted.
struct TSplineCheck {
  /// The largest |c| of Σ φ_i − 1's coefficients on the elements' local B-splines: 0 exactly
  /// when the functions sum to one, else a bound on |Σ φ_i − 1| (the B-splines are ≥ 0 and
  /// sum to one).
  double unity_error = 0;
  /// The least and greatest Σ φ_i at the elements' corners, edges' and faces' middles and
  /// centres.
  std::array<double, 2> sum_range{1, 1};
  /// Pairs of functions with overlapping supports whose local knot vectors overlap (both are
  /// runs of one knot vector) along no axis: 0 means dual-compatible, so linearly independent.
  std::size_t incompatible_pairs = 0;
  std::size_t duplicates = 0;  ///< pairs of identical functions (the same knots on every axis)
  /// The T-mesh cells (indices into basis.tmesh) holding an element where the sum is off one
  /// or an incompatible pair meets.
  std::vector<std::size_t> cells;
  bool suitable() const {
    return unity_error <= 1e-12 && incompatible_pairs == 0 && duplicates == 0;
  }
};

/// Partition of unity and dual compatibility of a T-spline basis.
/// @pre basis.kind == SplineKind::tspline
TSplineCheck check_tspline(const SplineBasis& basis);

}  // namespace tpmsfill
