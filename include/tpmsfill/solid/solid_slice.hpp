/// @file solid_slice.hpp
/// @brief Direct slicing of a fitted solid, and its iso-material surfaces (Li & Fu 2021, §3
/// and §4.3): no tessellated solid, only G and M.
///
/// A level set of a scalar of the parameter cube, f = G_z − ẑ for a layer at height ẑ or
/// f = M − m for an iso-material surface, is found by an octree in the parameter cube:
///  1. Cells of the initial level (Li & Fu 2021: 1) whose f may change sign are kept: the 8
///     corners' signs differ, or the cell is no deeper than the basis's leaf there and ẑ lies
///     within the range of the B-spline coefficients of f over it (B-splines are non-negative
///     and sum to one, so f over a leaf lies within its 64 local coefficients: no crossing is
///     missed down to the basis's own leaves; below them only the corners decide, as in
///     Li & Fu 2021).
///  2. A kept cell whose Euclidean volume (its 8 mapped corners as 6 tets) exceeds τ is split
///     into its 8 children, which are kept by the same rule, until every kept cell is within τ
///     or at the deepest level. Kept cells with a face on the cube's faces that the level set
///     crosses there (a section's contours, which alone set its area) are then split down to
///     the deepest level any kept cell reached; the others keep their own levels.
///  3. No cracks between leaves of different levels (Li & Fu 2021 leave them open): a leaf
///     sees its faces and edges as finely as the tree splits them on either side (cubical
///     marching squares, Ho et al. 2005), so both leaves sharing a face piece or an edge
///     segment build the same points and segments on it; a leaf whose faces and edges are whole
///     takes its loops from marching cubes' table (tpmsfill's, with its asymptotic decider), any
///     other links its pieces' segments into loops. Each loop is cut into ears in the plane of
///     its mapped points, so no triangle turns over unless its loop's image does (where G
///     folds). The leaf across every crossed piece is kept too, split down to the piece, and a
///     leaf whose corners miss a crossing on its face is split.
///  4. On each crossed segment the point where f = 0 is found by iterated linear interpolation
///     (regula falsi, Illinois variant) to 10⁻⁹ of the solid's size, once per segment (every
///     leaf along it shares the point by its key), mapped through G and M.
/// A slice is the filled cross-section: triangles in the plane z = ẑ with the material at every
/// vertex, counter-clockwise seen from +z, and its contours (the section's border edges, where
/// the level set meets the cube's faces: the solid's boundary), outer counter-clockwise, holes
/// clockwise.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "tpmsfill/solid/solid_spline.hpp"
#include "tpmsfill/types.hpp"

namespace tpmsfill {

struct SolidSliceOptions {
  /// Split cells while their Euclidean volume exceeds this, mm³ (Li & Fu 2021 use 10, 1, 0.1
  /// on a femur's end); 0: default_slice_tau() of the control points' box (which holds the
  /// solid).
  double tau = 0;
  int initial_level = 1;  ///< the uniform start (as in Li & Fu 2021)
  /// Never split below this level (256 cells per axis). A layer's cells reach it only where
  /// τ asks, and along its contours where any cell of the layer does.
  int max_level = 8;
};

/// The τ used when none is given: (the box's diagonal / 64)³, cells about 1/64 of the part.
double default_slice_tau(const Box3& box);

/// A triangulated level set with the material at its vertices.
struct SolidLevelSet {
  std::vector<Vec3> points;                ///< mm (a slice's lie in its plane)
  std::vector<double> material;            ///< per point (0 when the spline has no material)
  std::vector<std::array<double, 3>> uvw;  ///< per point, its parameter point
  std::vector<std::array<std::uint32_t, 3>> triangles;
  int level = 0;                ///< the deepest level of a leaf marching cubes ran on
  std::size_t cells = 0;        ///< leaves kept (of any level)
  std::size_t evaluations = 0;  ///< evaluations of G and M
};

struct SolidSection {
  double z = 0;        ///< the plane, mm
  SolidLevelSet mesh;  ///< the filled cross-section
  /// Outer counter-clockwise, holes clockwise (seen from +z), none crossing another: the
  /// border of the triangles, or with turned-over triangles, of the region they all cover.
  std::vector<Contour> contours;
  double area = 0;          ///< mm², enclosed by the contours
  std::size_t flipped = 0;  ///< triangles clockwise from +z (where G folds)
};

/// The cross-section of the solid at height z (see the file comment). Empty when the plane
/// misses the solid.
/// @throws InputError  tau < 0, levels outside 0..16 or initial above max
SolidSection slice_solid(const SolidSpline& spline, double z,
                         const SolidSliceOptions& options = {});

/// The surface M = m inside the solid, mapped through G: open where it meets the solid's
/// boundary, a 2-manifold inside. Triangles face increasing material.
/// @throws InputError  a spline without material; options as slice_solid
SolidLevelSet iso_material_surface(const SolidSpline& spline, double m,
                                   const SolidSliceOptions& options = {});

}  // namespace tpmsfill
