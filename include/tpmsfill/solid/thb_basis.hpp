/// @file thb_basis.hpp
/// @brief The spline basis that a heterogeneous solid's geometry G(u, v, w) and material
/// M(u, v, w) share: cubic truncated hierarchical B-splines (THB; Giannelli, Jüttler & Speleers
/// 2012) on the cube octree, and the uniform tensor-product cubic B-spline that Li & Fu 2021
/// compare against (their "trivariate NURBS", Table 2), behind one representation.
///
/// Why THB and not the T-splines of Li & Fu 2021: on an arbitrary octree T-mesh the blending
/// functions of a cubic T-spline need not sum to one nor be linearly independent (only
/// analysis-suitable T-meshes guarantee both, and normalising them makes the spline
/// rational). THB on the same octree has both properties for every octree, refines locally in
/// the same way (splitting a cell brings in the finer functions over it), and a refined basis
/// holds the coarse spline exactly, so progressive refinement starts from the spline it
/// refines.
///
/// Level l has clamped uniform cubic knots with spans[l] spans per axis (spans[l + 1] =
/// 2 spans[l]); B-spline (l, i) is non-zero on spans i − 3 .. i of its axis. Ω_l is the union
/// of the octree's leaves of level ≥ l. Function (l, i, j, k) is in the basis when its support
/// lies in Ω_l but not in Ω_{l+1}, truncated: its components along the level-(l + 1)
/// B-splines whose supports lie in Ω_{l+1} are removed (recursively, level after level). So
/// on a leaf of level L every basis function is a fixed combination of the 64 level-L
/// B-splines non-zero there; those combinations are the basis's extraction rows, and every
/// evaluation goes through them. The basis sums to one and reproduces linear functions from
/// coefficients at the Greville points (greville_points).
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "tpmsfill/solid/cube_octree.hpp"

namespace tpmsfill {

/// One B-spline of one level: index (i, j, k) along u, v, w. A T-spline's function: its
/// anchor, the T-mesh vertex (i, j, k) / 2^level (tspline_basis.hpp).
struct SplineFunction {
  int level = 0;
  std::array<std::uint32_t, 3> index{};
};

/// Which construction a basis came from: what a model file stores to build it again.
enum class SplineKind : std::uint8_t { thb, uniform, tspline };

/// A cubic spline basis over [0, 1]³ (see the file comment). Plain data.
struct SplineBasis {
  SplineKind kind = SplineKind::thb;
  std::vector<std::uint32_t> spans;       ///< per level, knot spans per axis
  std::vector<SplineFunction> functions;  ///< the basis: one control value each
  /// The cells on which the basis is polynomial (the octree's leaves), ordered by level, then
  /// k, j, i. Cell (l, i, j, k) is span (i, j, k) of level l.
  std::vector<OctreeCell> elements;
  /// Element e's local B-spline (a, b, c) (level-l B-spline (i + a, j + b, k + c), a, b, c in
  /// 0..3) is row element_rows[64 e + a + 4 b + 16 c]. A spline's coefficient on the B-spline
  /// of row r is Σ row_weight[t] · c[row_function[t]], t in [row_start[r], row_start[r + 1]),
  /// c the spline's coefficients on the basis; so on element e, function f is the sum of
  /// weight · local B-spline over the element's rows that name f.
  std::vector<std::uint32_t> element_rows;
  std::vector<std::uint32_t> row_start;
  std::vector<std::uint32_t> row_function;
  std::vector<double> row_weight;
  /// T-splines only (tspline_basis.hpp): the T-mesh's cells, and per function its local knot
  /// vectors along u, v and w.
  std::vector<OctreeCell> tmesh;
  std::vector<std::array<std::array<double, 5>, 3>> knots;
};

/// The THB basis on the octree's leaves (balanced or not).
/// @throws InputError  an octree whose leaves do not tile the cube
SplineBasis thb_basis(const CubeOctree& octree);

/// The uniform tensor-product cubic B-spline basis with per_axis³ functions (clamped uniform
/// knots, per_axis − 3 spans per axis): the uniform baseline. One level, identity rows.
/// @throws InputError  per_axis < 4 or above 1024
SplineBasis tensor_basis(int per_axis);

/// Per function, its Greville point: the mean of the three inner knots of its local knot
/// vector, per axis (a T-spline's own knots, a B-spline's its level's). Coefficients equal to a
/// linear function's values there reproduce it.
std::vector<std::array<double, 3>> greville_points(const SplineBasis& basis);

/// The element holding (u, v, w) (clamped onto the cube; a point on a shared face goes to the
/// element above it along each axis).
std::size_t basis_element_at(const SplineBasis& basis, std::array<double, 3> uvw);

/// The 64 local B-splines of one element at one point, and their derivatives by u, v, w.
/// Index a + 4 b + 16 c as in SplineBasis::element_rows.
struct LocalBasis {
  std::array<double, 64> value{};
  std::array<std::array<double, 64>, 3> first{};   ///< ∂u, ∂v, ∂w
  std::array<std::array<double, 64>, 6> second{};  ///< ∂uu, ∂vv, ∂ww, ∂uv, ∂vw, ∂wu
};

/// The local B-splines of `element` at (u, v, w) (a point of the element, or near it: the
/// polynomial is extended). `derivatives` is 0, 1 or 2; higher ones are left zero.
LocalBasis local_basis(const SplineBasis& basis, std::size_t element, std::array<double, 3> uvw,
                       int derivatives);

/// The spline Σ_i c_i φ_i with `dimension` values per function (function-major), and its
/// gradient (gradient[a · dimension + d] = ∂_a of component d), at (u, v, w).
/// @param[out] value     dimension entries
/// @param[out] gradient  3 · dimension entries, or null
void evaluate_spline(const SplineBasis& basis, const std::vector<double>& coefficients,
                     int dimension, std::array<double, 3> uvw, double* value,
                     double* gradient = nullptr);

/// The coefficients on `fine` of the spline with `coefficients` on `coarse`: the same
/// function exactly (the fine hierarchy must hold the coarse one: every leaf of `fine` lies in
/// a leaf of `coarse`). THB and uniform bases only.
/// @throws InputError  a fine basis that does not refine the coarse one
std::vector<double> refine_coefficients(const SplineBasis& coarse, const SplineBasis& fine,
                                        const std::vector<double>& coefficients, int dimension);

}  // namespace tpmsfill
