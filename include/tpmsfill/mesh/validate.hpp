/// @file validate.hpp
/// @brief Stage "validate": is an indexed triangle mesh (typically marching-cubes output) a
/// closed, consistently and outwardly oriented 2-manifold without degenerate faces or
/// self-intersections?
///
/// Unlike check_mesh() (which accepts any soup and merges bit-identical points first), this
/// judges the mesh exactly as indexed, fast enough for multi-million-triangle outputs: the
/// topology is integer sorting, geometric decisions use CGAL's exact predicates (Epick). Both
/// report through MeshValidity, with one exact pair test for self-intersections. Returns data;
/// fill() turns a failing report into a ValidationError. The report counts the mesh's
/// connected components; to list, measure or drop them see components.hpp.
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "tpmsfill/progress.hpp"
#include "tpmsfill/types.hpp"

namespace tpmsfill {

/// What a mesh's maker proves of it by construction, so that validate_mesh() need not search:
/// that it is closed, consistently oriented, manifold, without degenerate triangles, separate
/// vertices at one position or intersecting triangles. marching_cubes_proved()
/// (sampling/marching_cubes.hpp) gives one, each of its assumptions checked; keep_components()
/// (components.hpp) carries one over to the components kept. It speaks only of the mesh it was
/// made for: nothing here ties it to the points, so whoever changes the mesh drops the proof.
struct ConstructionProof {
  std::uint64_t triangles = 0, points = 0;  ///< the mesh it speaks of
};

struct ValidateOptions {
  bool self_intersections = true;  ///< search for intersecting triangle pairs (exact)
  /// When set and it speaks of the mesh (the same numbers of triangles and points), the
  /// verdict is the proof's, and only the vertices, components, area, volume and orientation
  /// are measured; otherwise the mesh is searched. MeshValidity::validated_by says which.
  const ConstructionProof* proof = nullptr;
  /// When set, every triangle should lie in one closed cell of this grid (true of
  /// marching_cubes() output on that grid): the intersection search then only pairs triangles
  /// of the same or 26-adjacent cells (each triangle belongs to the cell of its centroid).
  /// If some triangle does not lie in its cell (beyond a tolerance of 1e-7 cells), the general
  /// search runs instead, so the answer never depends on this promise. Without a grid a
  /// general box-intersection search (CGAL::box_self_intersection_d) is used.
  std::optional<Grid> cell_grid{};
  std::size_t max_examples = 10;  ///< example locations kept per defect class
  Progress* progress = nullptr;
};

/// An edge between two points (coordinates in mm) and one triangle (input index) that uses it.
struct EdgeLocation {
  std::array<Vec3, 2> ends;
  std::uint32_t triangle = 0;
  bool operator==(const EdgeLocation&) const = default;
};

/// Whether a mesh bounds a solid, and where it does not: the report validate_mesh() returns
/// and check_mesh()'s MeshCheck extends with a soup's own facts, so both stages give one
/// verdict, valid(), and one list of problems() in the same words. Counts refer to the mesh's
/// vertices as `merged_points` says; triangle indices to the input's triangles.
/// How a verdict was reached: by searching the mesh (its indices for the topology, a pair
/// search for intersections), or from a ConstructionProof.
enum class ValidatedBy : std::uint8_t { Search, Construction };

struct MeshValidity {
  ValidatedBy validated_by = ValidatedBy::Search;
  /// How corners are identified. false (validate_mesh): as indexed, and separate vertices at
  /// one position are a defect (duplicate_points). true (check_mesh): by position, points with
  /// bit-identical coordinates merged first (-0.0 == +0.0), as a soup's topology is its
  /// positions'.
  bool merged_points = false;
  std::uint64_t triangles = 0;
  std::uint64_t vertices = 0;  ///< distinct vertices (as merged_points says) referenced
  /// Points whose position an earlier point already has (bit for bit). Merged: every point
  /// counts and they are merged, not a defect. As indexed: referenced points only, each a
  /// separate vertex at another's position.
  std::uint64_t duplicate_points = 0;

  // --- faces --------------------------------------------------------------------------
  /// Triangles with a repeated corner or three exactly collinear corners (CGAL::collinear).
  /// Those with a repeated corner take no part in edges, fans or components.
  std::uint64_t degenerate_triangles = 0;
  /// Triangles without a repeated corner that have the same three corners as an earlier one
  /// (in any order or orientation); the earliest of each set is not counted. Only check_mesh()
  /// counts them: as indexed a duplicate triangle always shows as an inconsistent or
  /// non-manifold edge or as a component without volume, so validate_mesh() leaves 0.
  std::uint64_t duplicate_triangles = 0;

  // --- edges and vertices ---------------------------------------------------------------
  std::uint64_t border_edges = 0;  ///< undirected edges used by one triangle
  /// Border cycles of the mesh CGAL builds from the soup (check_mesh only, MeshCheck says
  /// how); unset when not counted.
  std::optional<std::uint64_t> holes;
  std::uint64_t non_manifold_edges = 0;  ///< used by three or more triangles
  /// Vertices whose triangles form more than one fan (pinched, e.g. a bow-tie). Triangles
  /// around a vertex are in one fan when they are joined through edges at the vertex shared
  /// by two or more triangles, so a vertex on a non-manifold edge counts only when it is
  /// also pinched (the edge is already reported).
  std::uint64_t non_manifold_vertices = 0;
  /// Edges shared by exactly two triangles that walk it in the same direction.
  std::uint64_t inconsistent_edges = 0;

  // --- whole mesh ---------------------------------------------------------------------
  std::uint64_t components = 0;  ///< connected through shared vertices
  /// Pairs of triangles that intersect, by one exact pair test (Epick) with shared corners
  /// taken by vertex: sharing an edge, only if they overlap (coplanar, opposite corners on the
  /// same side); sharing one corner, only if they also meet elsewhere; otherwise if they meet
  /// at all. Degenerate and duplicate triangles are counted above and left out of the search.
  /// Unset when not searched.
  std::optional<std::uint64_t> self_intersecting_pairs;
  /// The search paired triangles by ValidateOptions::cell_grid; false when it was not set,
  /// when some triangle did not lie in its cell (then the general search ran: for
  /// marching-cubes output on that grid this means a bug upstream), or when not searched.
  bool searched_by_cells = false;
  double area = 0;  ///< total triangle area, mm^2
  /// Signed volume, mm^3 (divergence theorem, summed in a fixed order, negative when inside
  /// out). validate_mesh() always sets it; check_mesh() only for a closed, manifold,
  /// consistently oriented mesh with a surface, where it means a solid's volume.
  std::optional<double> volume;
  /// Normals point out of the solid; set when volume is. As indexed (validate_mesh): every
  /// component has a non-zero volume and the total is positive. Merged (check_mesh): every
  /// shell is oriented so the solid is on its inner side (nested shells alternate:
  /// PMP::does_bound_a_volume and a positive volume; when self-intersections exist, were not
  /// searched for, or faces are degenerate, a positive volume alone).
  std::optional<bool> outward;

  // --- where -------------------------------------------------------------------------
  // At most max_examples of each. Edges: ends in the direction the named triangle (the edge's
  // lowest-index triangle as indexed) walks them, in order of their smaller vertex; vertices
  // likewise; triangles in input order; self-intersections as (i < j) pairs, the smallest in
  // lexicographic order.
  std::vector<EdgeLocation> border_edge_examples;
  std::vector<EdgeLocation> non_manifold_edge_examples;
  std::vector<EdgeLocation> inconsistent_edge_examples;
  std::vector<Vec3> non_manifold_vertex_examples;
  std::vector<std::uint32_t> degenerate_triangle_examples;
  std::vector<std::uint32_t> duplicate_triangle_examples;
  std::vector<std::array<std::uint32_t, 2>> self_intersection_examples;

  bool closed() const { return border_edges == 0; }
  bool manifold() const { return non_manifold_edges == 0 && non_manifold_vertices == 0; }
  bool consistently_oriented() const { return inconsistent_edges == 0; }

  /// A closed 2-manifold, consistently and outwardly oriented, without degenerate or duplicate
  /// triangles, separate vertices at one position or self-intersections (unsearched ones count
  /// as none), and with at least one triangle: `tpmsfill check`'s exit code 0, and what fill()
  /// requires of what it writes.
  bool valid() const;

  /// One sentence per failed condition of valid(), in the order checked; empty when valid.
  std::vector<std::string> problems() const;
};

/// Validates `mesh` as indexed.
/// @throws InputError  an index is out of range, or the mesh has more triangles or points
///                     than 32-bit corner numbers allow
/// @throws Cancelled   when options.progress says so
MeshValidity validate_mesh(const TriangleSoup& mesh, const ValidateOptions& options = {});

}  // namespace tpmsfill
