/// @file untangle.hpp
/// @brief Internal: moves the free points of a map of a tet mesh so that no tet's image is
/// inverted or flat, by Garanzha, Kaporin, Kudryavtseva, Protais, Ray and Sokolov's
/// foldover-free maps (SIGGRAPH 2021). Used by the cube map (cube_map.cpp), whose harmonic
/// interior inverts tets where a limb squeezes into a thin slab of the cube, and whose
/// mean-value patches crowd a protrusion (in the plane, by projected Newton steps).
///
/// Each tet's Jacobian J = U R⁻¹ maps its own shape R, scaled so the tets' total volume is the
/// image's, onto its image U. The energy Σ_T w_T ((1 − θ) tr(JᵀJ) / χ^(2/3) + θ (det² + 1) / χ),
/// χ(D, ε) = (D + √(ε² + D²)) / 2, is finite for every map while ε > 0, and tends to a barrier
/// on det J ≤ 0 as ε → 0: L-BFGS minimises it for each ε, and ε shrinks by the paper's rule
/// (eq. 6) from the smallest det J and the energy's decrease, until every det J > 0 and the
/// energy no longer falls.
///
/// The density, the L-BFGS and the schedule serve any map whose Jacobians are linear in its
/// unknowns (FoldoverEnergy): the tets' images here, the spline G of a solid
/// (untangle_spline.hpp).
#pragma once

#include <array>
#include <cstdint>
#include <functional>
#include <vector>

#include "tpmsfill/solid/tet_mesh.hpp"

namespace tpmsfill::detail {

using Matrix3 = std::array<double, 9>;  ///< row-major
using Matrix2 = std::array<double, 4>;  ///< row-major

double determinant(const Matrix3& a);
double determinant(const Matrix2& a);

/// The cofactor matrix det(a) a⁻ᵀ (∂ det / ∂a; it exists where a is singular).
Matrix3 cofactor(const Matrix3& a);
Matrix2 cofactor(const Matrix2& a);

/// a⁻¹ = cofactor(a)ᵀ / det, given det = det a ≠ 0.
Matrix3 inverse(const Matrix3& a, double det);
Matrix2 inverse(const Matrix2& a, double det);

/// One element's density (1 − θ) tr(JᵀJ) / χ^(2/3) + θ (det² + 1) / χ, and ∂f/∂J.
double foldover_density(const Matrix3& j, double eps, Matrix3& derivative);

/// An energy Σ weight · foldover_density over elements whose Jacobians are linear in x (plus
/// any smooth term), with its gradient, and the smallest det J.
class FoldoverEnergy {
 public:
  struct Entry {
    std::int64_t row, column;
    double value;
  };

  virtual ~FoldoverEnergy() = default;
  virtual double operator()(const std::vector<double>& x, double eps,
                            std::vector<double>& gradient) const = 0;
  virtual double min_det(const std::vector<double>& x) const = 0;
  /// The energy's Hessian at x for this ε, each element's made positive semi-definite, as
  /// the entries of its lower half (row ≥ column; repeats add up). False where the energy
  /// has none: then only L-BFGS steps serve.
  virtual bool hessian(const std::vector<double>& /*x*/, double /*eps*/,
                       std::vector<Entry>& /*entries*/) const {
    return false;
  }
};

struct UntangleResult {
  int rounds = 0;             ///< values of ε tried
  int steps = 0;              ///< L-BFGS steps over all rounds
  double min_det_before = 0;  ///< smallest det J (of the scaled shapes) before and after
  double min_det_after = 0;
};

/// The schedule of ε and its limits. The defaults are the paper's (ε from 1, each new ε at
/// least 10 % below what the last round's decrease allows).
struct FoldoverSchedule {
  double first_eps = 1;
  double decrease_cap = 0.9;  ///< (1 − σ) at most this (eq. 6)
  int max_rounds = 100;       ///< values of ε
  int max_steps = 400;        ///< L-BFGS steps per value of ε
  /// Projected Newton steps rather than L-BFGS where the energy has a Hessian: dearer per
  /// step, but they scale to a region squeezed to 10⁻¹⁰ of its share, which L-BFGS barely moves.
  bool newton = false;
  int max_newton_steps = 50;  ///< Newton steps per value of ε
};

/// Minimises the energy from x under the schedule of ε, until min det J > 0 and the energy
/// no longer falls, or after schedule.max_rounds values of ε.
/// @param[in] report  called with the fraction of rounds done before every L-BFGS step (it
///                     may throw Cancelled to stop); may be empty
UntangleResult minimise_foldover(const FoldoverEnergy& energy, std::vector<double>& x,
                                 const FoldoverSchedule& schedule = {},
                                 const std::function<void(double)>& report = {});

/// Moves the points with `movable` set (and in a tet) to make every tet touching one of them
/// positive; the others stay. Only tets with a movable corner count.
/// @param[in] mesh     the tets; their shapes in mesh.points are the ideal the map keeps near
/// @param[in,out] uvw  per point, its image
/// @pre tets positive in mesh.points
/// @param[in] report  called with the fraction of rounds done before every L-BFGS step (it
///                     may throw Cancelled to stop); may be empty
/// @param[in] schedule  the values of ε (more rounds for a small region that must open)
UntangleResult untangle(const TetMesh& mesh, const std::vector<char>& movable,
                        std::vector<std::array<double, 3>>& uvw,
                        const std::function<void(double)>& report = {},
                        const FoldoverSchedule& schedule = {});

/// The same in the plane, by Newton steps: moves the movable points of a map of triangles into
/// the plane so that every triangle touching one of them turns counter-clockwise, near each
/// triangle's own shape. The density's volume term weighs `theta` (its shape term 1 − theta).
/// From a map with none turned or flat, the barrier (ε = 0) alone: the map stays injective.
/// @param[in] points     the triangles' corners in space: their shapes, the ideal
/// @param[in,out] uv     per point, its image
/// @param[in] report     as untangle()'s
UntangleResult untangle_triangles(const std::vector<Vec3>& points,
                                  const std::vector<Triangle>& triangles,
                                  const std::vector<char>& movable, double theta,
                                  std::vector<std::array<double, 2>>& uv,
                                  const std::function<void(double)>& report = {});

}  // namespace tpmsfill::detail
