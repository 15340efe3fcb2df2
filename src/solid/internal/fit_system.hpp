/// @file fit_system.hpp
/// @brief Internal: the linear algebra of the spline fit (solid_spline.cpp) on a basis's
/// extraction rows: the transposes that gather element sums onto functions, a symmetric
/// matrix over the rows, and the conjugate-gradient solve on the functions that goes through
/// them.
///
/// On a leaf of level l every basis function is a fixed combination of the 64 level-l
/// B-splines there (thb_basis.hpp); each such B-spline is a row. An energy whose terms are
/// sums over elements of products of local B-splines has, on the rows, a matrix K that couples
/// a row only to rows of its own level within 3 spans per axis: 7³ = 343 places, at offsets
/// (di, dj, dk) + 3. On the functions it is Tᵀ K T, T the rows' weights (row_coefficients is
/// T, functions_from_rows Tᵀ), which is never formed: a product goes through the rows.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <vector>

#include "tpmsfill/solid/thb_basis.hpp"

namespace tpmsfill::detail {

/// The transposes of a basis's extraction: which (element, local B-spline) slots use a row,
/// and which rows use a function. Gathering through them in index order keeps sums the same
/// whatever the thread count.
struct Gather {
  std::vector<std::uint32_t> row_start, row_slot;
  std::vector<std::uint32_t> function_start, function_row;
  std::vector<double> function_weight;
};

Gather make_gather(const SplineBasis& basis);

/// T c: the coefficients on every row, `dim` values each.
std::vector<double> row_coefficients(const SplineBasis& basis, const std::vector<double>& c,
                                     int dim);

/// Tᵀ y: per function, Σ weight · y over its rows, `dim` values each.
std::vector<double> functions_from_rows(const SplineBasis& basis, const Gather& g,
                                        const std::vector<double>& rows, int dim);

/// Per function, Σ weight · (Σ over the row's slots of slot_values), `dim` values each.
std::vector<double> gather(const SplineBasis& basis, const Gather& g,
                           const std::vector<double>& slot_values, int dim);

inline constexpr int kStencil = 343;
inline constexpr std::uint32_t kNoRow = 0xffffffffu;

/// A symmetric matrix on a basis's rows (see the file comment).
struct RowMatrix {
  std::vector<std::uint32_t> neighbour;  ///< rows × kStencil; kNoRow where no row lies
  std::vector<double> value;             ///< rows × kStencil
};

/// The slot of local B-spline l in the stencil of local B-spline k (both a + 4 b + 16 c).
inline int stencil_slot(int k, int l) {
  const int d0 = (l & 3) - (k & 3) + 3, d1 = (l >> 2 & 3) - (k >> 2 & 3) + 3,
            d2 = (l >> 4) - (k >> 4) + 3;
  return d0 + 7 * d1 + 49 * d2;
}

/// The matrix's shape for a basis, its values zero.
RowMatrix row_matrix(const SplineBasis& basis, const Gather& g);

/// What one element adds to the matrix, for every pair (k, l) of its local B-splines:
///   Σ_s weight[s] φ_k(x_s) φ_l(x_s)        over its samples s (values: 64 per sample)
/// + Σ_a first[a] ∫ ∂_a φ_k ∂_a φ_l         over the element (3 × 3 × 3 Gauss points)
/// + plate ∫ Σ_t c_t ∂²_t φ_k ∂²_t φ_l       (c_t = 1 for uu, vv, ww and 2 for uv, vw, wu)
/// + mass ∫ φ_k φ_l
struct ElementTerms {
  const std::vector<std::uint32_t>* sample_start;  ///< per element, its samples' range
  const std::vector<double>* sample_value;         ///< 64 per sample, element after element
  const std::vector<double>* sample_weight;
  const std::vector<std::array<double, 3>>* first;  ///< per element
  const std::vector<double>* plate;                 ///< per element, or null
  const std::vector<double>* mass;                  ///< per element, or null
};

/// Sets the matrix's values to the sum of every element's terms (each row summed in slot
/// order: the same whatever the thread count).
void assemble_row_matrix(const SplineBasis& basis, const Gather& g, const ElementTerms& terms,
                         RowMatrix& matrix);

struct SolveReport {
  int iterations = 0;
  double relative_residual = 0;  ///< the largest over the components
};

/// Solves (Tᵀ K T) x = b for `dim` right-hand sides at once (function-major, as b), by
/// conjugate gradients preconditioned by the diagonal, from x = 0, until every component's
/// residual is below `tolerance` times its |b| or after `max_iterations`. `each_iteration`,
/// when given, is called before every iteration (a solve may take seconds: the caller's
/// progress and cancel).
SolveReport solve_conjugate_gradients(const SplineBasis& basis, const Gather& g,
                                      const RowMatrix& matrix, const std::vector<double>& b,
                                      int dim, double tolerance, int max_iterations,
                                      std::vector<double>& x,
                                      const std::function<void()>& each_iteration = {});

}  // namespace tpmsfill::detail
