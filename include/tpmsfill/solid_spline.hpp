/// @file solid_spline.hpp
/// @brief Stage "spline fit" of the material pipeline (seed 001 §2.3, issue 18): the
/// trivariate splines G(u, v, w) (geometry, mm) and M(u, v, w) (material) on one basis
/// (thb_basis.hpp), fitted to a tet mesh through its cube map, and evaluated anywhere.
///
///  1. Basis: THB on the cube octree of the tets' parametric centroids (the seed's ≤ 5 tets per
///     cell), or the seed's baseline, a uniform tensor-product cubic B-spline.
///  2. Start: every control value is I_G or I_M (cube_lookup) at its Greville point.
///  3. Fit: explicit Euler steps on the seed's energies,
///       E(G) = A_G + λ1 ∫ B_G + λ2 ∫ C_G + λ3 D_G,   E(M) = A_M + λ1 ∫ B_M + λ2 ∫ C_M,
///     c_i ← c_i + ε (2 R_i − λ1 ∫ S_i − λ2 ∫ T_i − λ3 ∫ U_i), with
///       R_i = Σ_k w_k g_k φ_i(x_k) (I(x_k) − F(x_k)) / Σ_k w_k φ_i(x_k)
///     over 3 × 3 × 3 Gauss points x_k of every element (weights w_k), the normalised,
///     weighted residual that makes ε a step size whatever the sample count (LSPIA's form);
///     g = (γ + |F_u|² + |F_v|² + |F_w|²)^(−1/2) the seed's velocity weight, capped at 1/(2ε)
///     so that a step never overshoots. The regularisers are the seed's, reconstructed (see
///     docs/method.md): B = |F_u|² + |F_v|² + |F_w|²; C_G = Σ |G_a × G_b|² (the images of
///     the parameter cells' faces), C_M the thin-plate energy of M; D_G = ∫ |n_G − n_I|² over
///     the cube's six faces, n_I the normal of the boundary triangle there. S, T and U are
///     their exact gradients, by the same quadrature (3 × 3 on faces). Positions are scaled to
///     unit size and the material to [0, 1] while fitting, so that g and λ mean the same for a
///     part in mm or in m.
///  4. Stop: the similarity ratio RS = (1 − ‖I − F‖ / ‖I − F⁰‖) · 100 % over the mesh's
///     points (F⁰ the first Greville start) changes by less than rs_change between steps, or
///     after max_iterations. G and M stop on their own.
///  5. Progressive refinement: leaves whose RMS residual (of G or M) exceeds the mean by
///     refine_sigmas standard deviations are split, the fit goes on from the same spline on the
///     finer basis (refine_coefficients), for `refinements` rounds.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "tpmsfill/cube_map.hpp"
#include "tpmsfill/cube_octree.hpp"
#include "tpmsfill/progress.hpp"
#include "tpmsfill/spatial.hpp"
#include "tpmsfill/tet_mesh.hpp"
#include "tpmsfill/thb_basis.hpp"
#include "tpmsfill/types.hpp"

namespace tpmsfill {

/// Geometry and material on one basis: G = Σ geometry_i φ_i (mm), M = Σ material_i φ_i.
struct SolidSpline {
  SplineBasis basis;
  std::vector<Vec3> geometry;
  std::vector<double> material;  ///< empty: the solid has no material
};

struct SolidFitOptions {
  CubeOctreeOptions octree = {};  ///< the starting octree (seed: ≤ 5 tets per cell)
  /// > 0: the seed's baseline instead of THB, a uniform tensor-product cubic B-spline with this
  /// many control points per axis (no refinement).
  int uniform = 0;
  double lambda1 = 1e-3;     ///< first-order regulariser (seed)
  double lambda2 = 1e-3;     ///< second-order regulariser (seed)
  double lambda3 = 1e-3;     ///< boundary-normal term, G only (seed)
  double gamma = 1e-2;       ///< in the velocity weight g (seed)
  double step = 0.5;         ///< ε, the Euler step (seed: 0.4 to 0.6)
  double rs_change = 0.05;   ///< stop when RS moves by less, in percentage points
  int max_iterations = 50;   ///< per field and round
  int refinements = 2;       ///< progressive rounds after the first (THB only)
  double refine_sigmas = 2;  ///< split leaves whose residual exceeds mean + this · σ
  /// The surface the tets were made from (tetrahedralize()), or null: the boundary samples
  /// then aim at it rather than at the point-normal triangles over the tets' boundary.
  /// Must outlive the call.
  const MeshIndex* surface = nullptr;
  Progress* progress = nullptr;
};

/// One round of the fit: one basis, G then M iterated to the stopping rule.
struct FitRound {
  std::size_t control_points = 0;
  std::size_t elements = 0;
  int geometry_iterations = 0;
  int material_iterations = 0;
  double geometry_rs = 0;   ///< %, relative to the first Greville start
  double material_rs = 0;   ///< %
  double geometry_rms = 0;  ///< mm, |G − X| over the mesh's points
  double geometry_max = 0;  ///< mm
  double material_rms = 0;  ///< material units, |M − m| over the mesh's points
  double material_max = 0;
  std::size_t folded_samples = 0;  ///< quadrature points where det J_G ≤ 0
  std::size_t samples = 0;         ///< quadrature points
  std::size_t split = 0;           ///< leaves split after the round
  double seconds = 0;
};

struct SolidFit {
  SolidSpline spline;
  std::vector<FitRound> rounds;
  double greville_geometry_rms = 0;  ///< mm, the first start's |G⁰ − X|
  double greville_material_rms = 0;
};

/// Fits G (and M when the mesh has material) to the mesh through its cube map.
/// @param[in] mesh  the tets the map was made from (material per point, or none)
/// @param[in] map   map_to_cube(mesh)
/// @throws InputError  a map of another mesh; options out of range (steps not in (0, 1],
///                     negative λ or γ, fewer than 1 iteration, a uniform count below 4 or
///                     above 100)
/// @throws Cancelled   options.progress asked to stop
SolidFit fit_solid_spline(const TetMesh& mesh, const CubeMap& map,
                          const SolidFitOptions& options = {});

/// G, M and their derivatives at one parameter point.
struct SolidPoint {
  Vec3 position;                 ///< G, mm
  std::array<Vec3, 3> jacobian;  ///< G_u, G_v, G_w
  double material = 0;           ///< M (0 without material)
  Vec3 material_gradient;        ///< (M_u, M_v, M_w)
};

/// G and M at (u, v, w) (clamped onto the cube).
SolidPoint evaluate_solid(const SolidSpline& spline, std::array<double, 3> uvw);

/// The solid's box, mm: G on the cube's faces (the solid's boundary), sampled at the corners
/// and centres of the basis elements' faces there; within the elements' bulge of the true box.
Box3 solid_box(const SolidSpline& spline);

}  // namespace tpmsfill
