/// @file solid_spline.hpp
/// @brief Stage "spline fit" of the material pipeline (Li & Fu 2021, §2.3): the trivariate
/// splines G(u, v, w) (geometry, mm) and M(u, v, w) (material) on one basis (thb_basis.hpp),
/// fitted to a tet mesh through its cube map, and evaluated anywhere.
///
/// Every control value starts at I_G or I_M (cube_lookup) at its Greville point; explicit
/// Euler steps on a data term and regularisers follow, G and M each stopping when the
/// similarity ratio RS = (1 − ‖I − F‖ / ‖I − F⁰‖) · 100 % (F⁰ the first Greville start) moves
/// by less than rs_change between steps, or after max_iterations. On THB, leaves with large
/// residuals are then split and the fit goes on from the same spline, for `refinements` rounds.
/// Positions are scaled to unit size and the material to [0, 1] while fitting, so that g and λ
/// mean the same for a part in mm or in m.
/// The method: docs/method.md, section "Fitting a solid's splines".
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "tpmsfill/progress.hpp"
#include "tpmsfill/sampling/spatial.hpp"
#include "tpmsfill/solid/cube_map.hpp"
#include "tpmsfill/solid/cube_octree.hpp"
#include "tpmsfill/solid/tet_mesh.hpp"
#include "tpmsfill/solid/thb_basis.hpp"
#include "tpmsfill/types.hpp"

namespace tpmsfill {

/// Geometry and material on one basis: G = Σ geometry_i φ_i (mm), M = Σ material_i φ_i.
struct SolidSpline {
  SplineBasis basis;
  std::vector<Vec3> geometry;
  std::vector<double> material;  ///< empty: the solid has no material
};

/// How the fit moves its control values (tpmsfill material fit --method euler|newton).
/// - Euler (the default): the seed's explicit steps P ← P − ε δE, the data term normalised
///   per function (Li & Fu 2021, eq. 7), the regularisers' step capped where it would not be
///   stable. It stops when RS settles, well before the steps' fixed point.
/// - Newton: damped Newton steps on the energy, each solved by conjugate gradients (g and the
///   area term's curvature frozen at the step's start, the gradient exact, a backtracking line
///   search keeping every step downhill), with the data weighed per control point and every
///   element anchored lightly to the tets' map, so that both bases reach the minimum of one
///   energy and compare fairly. Measured on bunny00 and bear (docs/benchmarks.md §21): the
///   uniform basis fits M 1.6–1.8 times closer than by Euler steps, THB about as closely, G
///   neither closer; 2–6 times the time and 1.9–2.8 times the memory. Each trial step of the
///   line search is held fold-free before its energy is measured, so a held step still
///   lowers E (held after the search, the upper femur's uniform 40³ G fell from RS 43.7 % to
///   −572 % in 50 steps; held inside, 55.7 %, docs/benchmarks.md §21b part 16). E freezes g, so RS
///   can still fall: a field ending over a point below its best step's goes back to it
///   (FitRound::undone_steps).
enum class SolidFitMethod { Newton, Euler };

struct SolidFitOptions {
  CubeOctreeOptions octree = {};  ///< the starting octree (Li & Fu 2021: ≤ 5 tets per cell)
  /// > 0: the uniform baseline instead of THB: a tensor-product cubic B-spline with this many
  /// control points per axis (no refinement).
  int uniform = 0;
  double lambda1 = 1e-3;  ///< first-order regulariser (Li & Fu 2021)
  double lambda2 = 1e-3;  ///< second-order regulariser (Li & Fu 2021)
  double lambda3 = 1e-3;  ///< boundary-normal term, G only (Li & Fu 2021)
  double gamma = 1e-2;    ///< in the velocity weight g (Li & Fu 2021)
  SolidFitMethod method = SolidFitMethod::Euler;
  double step = 0.5;        ///< ε, the Euler step (Li & Fu 2021: 0.4 to 0.6)
  double rs_change = 0.05;  ///< stop when RS moves by less, in percentage points
  int max_iterations = 50;  ///< per field and round
  int refinements = 2;      ///< progressive rounds after the first (THB only)
  /// Keep G fold-free: det J_G > 0 at every Gauss point, at 5³ points evenly inside every
  /// element and at 4³ points of it reaching its faces (the cube's boundary among them), in
  /// the model written. Each round starts fold-free (the folds of the Greville
  /// start, or of a refined G at the finer elements' points, pushed open along ∇det J_G, and
  /// where that fails untangled by Garanzha et al. 2021's foldover-free energy), and each step
  /// slides along a fold rather than into it (it also watches the children's Gauss points, so
  /// that the next round starts fold-free). Costs 1.1–2.5 times the plain fit's time and under
  /// a point of RS (docs/benchmarks.md §21c). False: the plain fit, which folds near the
  /// cube's faces and edges (bear: 5,568 of 387,855 Gauss points).
  bool fold_free = true;
  /// The leaves a refinement round splits. In (0, 1]: the fewest that hold this share of G's
  /// squared residual, and those that hold it of M's (Dörfler's marking): closer fits at equal
  /// control points than the 2σ rule (the seed's duck RS at 0.5; docs/benchmarks.md §21b).
  /// 0: those whose RMS residual (of G or of M) exceeds the mean by 2σ, the default before
  /// issue 40's part 8.
  double refine_share = 0.5;
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
  int geometry_iterations = 0;  ///< steps (Newton or Euler)
  int material_iterations = 0;
  /// Steps (of G and M) undone because RS ended over a point below the best step's: the field
  /// kept is that step's (counted in the iterations above all the same).
  int undone_steps = 0;
  std::size_t solve_iterations = 0;  ///< conjugate-gradient iterations of both fields' steps
  double geometry_rs = 0;            ///< %, relative to the first Greville start
  double material_rs = 0;            ///< %
  double geometry_rms = 0;           ///< mm, |G − X| over the mesh's points
  double geometry_max = 0;           ///< mm
  double material_rms = 0;           ///< material units, |M − m| over the mesh's points
  double material_max = 0;
  std::size_t folded_samples = 0;  ///< quadrature points where det J_G ≤ 0
  /// fold_free: points where det J_G ≤ 0 at the round's start, of those watched (Gauss
  /// points, the children's Gauss points, and on the last round the finer sample's).
  std::size_t fitted_folded_samples = 0;
  std::size_t untangled_functions = 0;  ///< fold_free: control points the energy moved
  std::size_t held_functions = 0;       ///< fold_free: per step, control points slid or held
  /// fold_free, the last round: points between the watched ones where det J_G ≤ 0, found by
  /// its Bernstein bound (fold_certificate.hpp) and pushed open.
  std::size_t found_folds = 0;
  /// Where det J_G is least (Gauss points; on the last round with folds between them, the
  /// finer sample's too).
  std::array<double, 3> worst_fold{};
  /// The last round only: points of a finer sample (5³ evenly inside every element, 4³
  /// reaching its faces, 9³ on an element along the cube's edges) where det J_G ≤ 0, and that
  /// sample's size: folds between the Gauss points and on the elements' faces.
  std::size_t fine_folded_samples = 0;
  std::size_t fine_samples = 0;
  std::size_t samples = 0;  ///< quadrature points
  std::size_t split = 0;    ///< leaves split after the round
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
