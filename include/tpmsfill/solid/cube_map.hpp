/// @file cube_map.hpp
/// @brief Stage "cube map" of the material pipeline (Li & Fu 2021, §2.2): a genus-0 tet
/// mesh mapped onto the unit cube [0, 1]³, the volumetric parameterization that the
/// trivariate spline G(u, v, w) is fitted over.
///
///  1. Corners: eight boundary vertices, corner k going to (k & 1, k >> 1 & 1, k >> 2 & 1):
///     given, or the boundary vertex furthest towards that corner of the bounding box (each
///     axis scaled by the box's size); when the curves between those cannot be traced, the
///     same in the box along the boundary's principal axes (a tilted or long part).
///  2. Curves: the cube's twelve edges as shortest boundary-edge paths (Dijkstra) between
///     their corners, traced so that they must bound six patches as the cube's edges bound its
///     faces: one face's loop first, which cuts the boundary into two disks; the opposite
///     face's loop inside the disk that holds its corners, leaving an annulus; the four side
///     curves across the annulus, each past the curves before it. Each face in turn goes first
///     until one works; when none does (corners at the tips of limbs, tets too coarse for a
///     thin part), the stage refuses and asks for corners or smaller tets. Each curve is
///     mapped onto its cube edge by normalised arc length.
///  3. Patches: each patch onto its cube face by Floater's mean-value coordinates
///     (w_ij = (tan(α/2) + tan(β/2)) / |x_j − x_i|, α and β the angles at x_i beside edge ij;
///     Li & Fu 2021 call them dihedral angles). The face is convex, so the patch map is a
///     bijection (Floater 2003), but it squeezes a protrusion exponentially: where a
///     triangle's image holds under 10⁻⁵ of its share of the face (or rounding turned it), the
///     patch's free points move by projected Newton steps on the foldover-free energy below,
///     in the plane, which keeps every image positive and evens out the areas. The stage
///     counts flipped triangles rather than assume none.
///  4. Interior: the P1 finite-element harmonic map, K_ij = Σ_T V_T ∇λ_i · ∇λ_j over the tets
///     T at edge ij (eq. 4 of Li & Fu 2021 with its two slips mended), solved as
///     K_II f_I = −K_IB f_B for the three coordinates (one sparse Cholesky factorization).
///  5. Untangling: a 3D harmonic map is not always a bijection (bear at diagonal / 30: 41 of
///     7,211 tets inverted). The interior points within two rings of every inverted or flat
///     tet move, by Garanzha et al.'s foldover-free maps (2021), until every image is positive
///     (the rings widen when not). The stage counts the tets still inverted, and those flat.
///     A flat image cannot be mended where a tet's four corners, or a chord's two ends, lie on
///     one patch: split the chords first (with_chords_split()). Where tets stay folded,
///     smaller tets around them usually give the interior room: folded_tets() names them, and
///     with_folds_opened() gives the few a mesh keeps more values of ε, region by region.
///
/// A box whose corners are the box's corners maps to the box's affine image, to round-off:
/// mean-value coordinates and P1 harmonic maps both reproduce linear functions.
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <vector>

#include "tpmsfill/progress.hpp"
#include "tpmsfill/solid/tet_mesh.hpp"

namespace tpmsfill {

struct CubeMapOptions {
  /// Point indices of the boundary vertices placed at the cube's corners, corner k at
  /// (k & 1, k >> 1 & 1, k >> 2 & 1), so that the boundary's outward side maps to the cube's
  /// outside (a mirrored choice is refused). Unset: found as the file comment says.
  std::optional<std::array<std::uint32_t, 8>> corners = {};
  Progress* progress = nullptr;  ///< reports the stage's steps (corners, patches, interior)
};

/// The cube's 12 edges: edge e joins corners cube_edge_corners(e)[0] → [1], which differ in
/// one bit, the axis e / 4 (edges 0-3 run along u, 4-7 along v, 8-11 along w).
std::array<int, 2> cube_edge_corners(int edge);

struct CubeMap {
  /// Per point of the mesh, (u, v, w) in [0, 1]³; NaN for points in no tet.
  std::vector<std::array<double, 3>> uvw;
  std::array<std::uint32_t, 8> corners{};  ///< point ids at the cube's corners
  /// Per cube edge (cube_edge_corners), its point ids from the first corner to the second.
  std::array<std::vector<std::uint32_t>, 12> curves;
  /// Boundary faces per cube face (face 2·axis + side lies at coordinate `axis` = `side`).
  std::array<std::uint64_t, 6> patch_faces{};
  std::uint64_t boundary_faces = 0;
  std::uint64_t flipped_boundary_faces = 0;  ///< image on their cube face reversed or flat
  /// Patches whose mean-value map crowded (a triangle's image under 10⁻⁵ of its share of the
  /// face, or turned or flat), relaxed by Newton steps on a foldover-free energy.
  std::uint64_t relaxed_patches = 0;
  std::uint64_t inverted_tets = 0;  ///< image inverted (exact orientation), untangled
  /// Image with no volume: all four corners on one cube face (a tet whose four corners lie on
  /// one patch of the boundary), or otherwise coplanar.
  std::uint64_t flat_tets = 0;
  std::uint64_t tets = 0;
  std::uint64_t interior_points = 0;  ///< unknowns of the harmonic solve
  /// The harmonic interior's inverted tets, before untangling.
  std::uint64_t harmonic_inverted_tets = 0;
  std::uint64_t untangled_points = 0;  ///< interior points the untangling moved
  /// Interior points with_folds_opened() moved, summed over the regions it kept.
  std::uint64_t opened_points = 0;
};

/// Maps a tet mesh onto the unit cube (see the file comment).
/// @param[in] mesh  a solid ball: check_tet_mesh() finds no ball_problem(); tets positive (an
///                  all-negative mesh is refused: call with_positive_tets() first); its chords
///                  split (with_chords_split()) for a map with no flat tets
/// @throws InputError  the mesh is not a ball (the sentence ball_problem() gives); corners
///                     given that are not boundary vertices, repeat, or are mirrored; corners
///                     found that coincide (a flat or thin part: give them); curves that do
///                     not cut the boundary into the cube's six faces (give corners); a
///                     solver failure
/// @throws Cancelled   options.progress asked to stop
CubeMap map_to_cube(const TetMesh& mesh, const CubeMapOptions& options = {});

/// The tets whose image under the map is inverted or flat (exact orientation), by index: where
/// it folds, for a caller that meshes finer there (TetrahedralizeOptions::finer) and maps again.
std::vector<std::uint32_t> folded_tets(const TetMesh& mesh, const CubeMap& map);

/// The map with the tets it still folds untangled once more, each region alone: the interior
/// points within 2, then 4 rings of what is still folded, with up to 1,000 values of ε. The
/// untangling in map_to_cube() moves the whole interior when 2 rings do not open, and on a
/// large mesh the paper's 100 values of ε can run out first: the lower femur's stand-in kept 2
/// of 144,743 tets inverted, which the 72 points around them, alone, opened in 133 values
/// (2.6 s). A region is kept only where it leaves fewer tets folded; one that does not open
/// costs all its values of ε, so this is for the map a caller keeps (after meshing finer), not
/// for every map: done inside map_to_cube(), it changed which tets the lower femur's passes
/// meshed finer, and they ended with 20 folded rather than 2.
/// @param[in] mesh  the tets map was made from
/// @param[in] map   map_to_cube()'s result for mesh
/// @return the map with inverted_tets, flat_tets and opened_points counted again; the
///         boundary's image unchanged
/// @throws Cancelled  progress asked to stop
CubeMap with_folds_opened(const TetMesh& mesh, CubeMap map, Progress* progress = nullptr);

}  // namespace tpmsfill
