/// @file bspline.hpp
/// @brief Stage "bspline": the trivariate implicit B-spline fitted to a scanned distance field,
///
///   C(u, v, w) = Σ_ijk c_ijk B_i(u) B_j(v) B_k(w)   on the unit cube [0, 1]³,
///
/// with scalar coefficients, clamped uniform knots (cubic by default), point evaluation with
/// gradient, separable evaluation at the centres of a w × h × d grid of cells (a discrete
/// distance field's sample positions (α − ½)/w, ...), and least-squares fitting of those
/// samples: the exact separable solve (three mode products of small per-axis solves, the
/// default) or LSPIA (Deng & Lin 2014, the iterative method of Lin & Gao's patent). Values are
/// x fastest, as Grid's.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

namespace tpmsfill {

/// A tensor-product B-spline volume over [0, 1]³ with scalar coefficients.
struct BSplineVolume {
  int degree = 3;
  std::array<int, 3> counts{};               ///< coefficients per axis (> degree)
  std::array<std::vector<double>, 3> knots;  ///< per axis, counts + degree + 1, clamped
  std::vector<double> coefficients;          ///< counts product, x fastest
};

/// Clamped uniform knots on [0, 1] for `count` coefficients of `degree`:
/// degree + 1 zeros, count − degree − 1 equal interior steps, degree + 1 ones.
/// @throws InputError  count <= degree or degree < 1
std::vector<double> clamped_uniform_knots(int count, int degree);

/// A volume of the given counts, clamped uniform knots and zero coefficients.
/// @throws InputError  as clamped_uniform_knots
BSplineVolume make_bspline_volume(std::array<int, 3> counts, int degree = 3);

/// C(u, v, w); points outside the unit cube are clamped onto it.
double bspline_value(const BSplineVolume& volume, double u, double v, double w);
/// ∇C(u, v, w) (per unit of u, v, w).
std::array<double, 3> bspline_gradient(const BSplineVolume& volume, double u, double v, double w);

/// C and, when `gradient` is not null, ∇C along one line of points (u[n], v, w), n = 0 ..
/// u.size() − 1: the rows of a grid whose parameters are separable, at O(degree²) per line
/// and O(degree) per point. `value` and `gradient` hold u.size() entries.
void bspline_line(const BSplineVolume& volume, const std::vector<double>& u, double v, double w,
                  double* value, std::array<double, 3>* gradient = nullptr);

/// C at the centres of a dims[0] × dims[1] × dims[2] grid of cells of the unit cube, x
/// fastest; separable (the basis per axis once, then three contractions), parallel.
std::vector<double> evaluate_bspline_grid(const BSplineVolume& volume, std::array<int, 3> dims);

enum class FitMethod {
  Direct,  ///< exact least squares, per-axis normal equations (+ smoothing), mode products
  Lspia,   ///< the LSPIA iteration c += μ Aᵀ(x − Ac), from the values at Greville points
};

struct FitOptions {
  FitMethod method = FitMethod::Direct;
  int degree = 3;
  /// Direct: λ of the second-difference penalty λ‖D₂c‖² per axis, relative to the mean
  /// diagonal of BᵀB (0 = plain least squares; a little keeps the solve stable when counts
  /// approach the samples).
  double smoothing = 1e-6;
  int max_iterations = 2000;       ///< LSPIA
  double relative_change = 1e-10;  ///< LSPIA stops when L changes by less than this share
};

struct FitReport {
  double rms = 0, max_error = 0;  ///< of C − x over the samples
  int iterations = 0;             ///< LSPIA (0 for direct)
};

struct FitResult {
  BSplineVolume volume;
  FitReport report;
};

/// Fits C to `values` sampled at the cell centres of a dims grid (x fastest).
/// @throws InputError  values.size() != dims product, a count above its axis's samples or
///                     not above the degree, non-finite values
FitResult fit_bspline(const std::vector<double>& values, std::array<int, 3> dims,
                      std::array<int, 3> counts, const FitOptions& options = {});

}  // namespace tpmsfill
