/// @file check.hpp
/// @brief Stage "check": is a triangle soup a closed, outward-oriented 2-manifold without
/// self-intersections or degenerate faces, and if not, where?
///
/// Topology is judged after merging points with bit-identical coordinates (STL stores three
/// points per facet; no tolerance is ever used; -0.0 and +0.0 count as equal). Geometric decisions
/// (degenerate faces, self-intersections, orientation) use CGAL Polygon Mesh Processing on the
/// exact-predicate kernel (Epick). The soup itself is never modified.
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "tpmsfill/types.hpp"
#include "tpmsfill/units.hpp"

namespace tpmsfill {

struct CheckOptions {
  /// Search for self-intersecting triangle pairs (the most expensive fact).
  bool self_intersections = true;
  /// Largest number of example locations kept per defect class.
  std::size_t max_examples = 10;
  /// The unit the soup's coordinates are in: the facts are established on the soup as it is
  /// (no rounding moves a point), and lengths, areas, volumes and locations are reported in
  /// millimetres.
  ModelUnits units = {};
};

/// An edge between two points (coordinates in mm) and one triangle (input index) that uses it.
struct EdgeLocation {
  std::array<Vec3, 2> ends;
  std::uint32_t triangle = 0;
};

/// The facts check_mesh() establishes. Counts refer to the soup after merging bit-identical
/// points; triangle indices refer to the input soup's triangles.
struct MeshCheck {
  // --- input --------------------------------------------------------------------------
  std::uint64_t points = 0;               ///< points in the soup, as given
  std::uint64_t triangles = 0;            ///< triangles in the soup
  Box3 bbox;                              ///< of referenced points
  std::uint64_t vertices = 0;             ///< distinct positions referenced by triangles
  std::uint64_t duplicate_points = 0;     ///< points whose position an earlier point already has
  std::uint64_t unreferenced_points = 0;  ///< points no triangle uses

  // --- faces --------------------------------------------------------------------------
  /// Triangles with a repeated corner or three exactly collinear corners (CGAL::collinear).
  /// Those with a repeated corner take no part in edges, fans, edge components or volume.
  std::uint64_t degenerate_triangles = 0;
  /// Triangles without a repeated corner that have the same three corners as an earlier one
  /// (in any order or orientation); the earliest of each set is not counted.
  std::uint64_t duplicate_triangles = 0;

  // --- edges and vertices ---------------------------------------------------------------
  std::uint64_t edges = 0;         ///< distinct undirected edges
  std::uint64_t border_edges = 0;  ///< used by exactly one triangle
  /// Border cycles of the mesh CGAL builds from the soup: repeated-corner and duplicate
  /// triangles dropped (PMP::repair_polygon_soup), oriented (PMP::orient_polygon_soup, which
  /// splits non-manifold edges and vertices, so a non-manifold soup may have holes without
  /// border edges, or more holes than border edges).
  std::uint64_t holes = 0;
  std::uint64_t non_manifold_edges = 0;  ///< used by three or more triangles
  /// Vertices whose triangles form more than one fan (pinched, e.g. a bow-tie). Triangles
  /// around a vertex are in one fan when they are joined through edges at the vertex shared
  /// by two or more triangles, so a vertex on a non-manifold edge counts only when it is
  /// also pinched (the edge is already reported).
  std::uint64_t non_manifold_vertices = 0;
  /// Edges shared by exactly two triangles that traverse it in the same direction.
  std::uint64_t inconsistent_edges = 0;

  // --- whole mesh ---------------------------------------------------------------------
  std::uint64_t components = 0;  ///< connected through shared vertices (all triangles)
  /// Connected through edges shared by exactly two triangles, repeated-corner and duplicate
  /// triangles left out: the connected components of the mesh CGAL builds (see holes).
  std::uint64_t edge_components = 0;
  /// Self-intersecting triangle pairs, decided as validate_mesh() decides them (one exact pair
  /// test, validate.hpp) with shared corners taken by position: sharing an edge, only if they
  /// overlap; sharing one corner, only if they also meet elsewhere; otherwise if they meet at
  /// all. Degenerate and duplicate triangles are counted above and left out. Unset when not
  /// searched for.
  std::optional<std::uint64_t> self_intersecting_pairs;
  double area = 0;  ///< total triangle area, mm^2
  /// Set only when closed, manifold and consistently oriented (and some triangle has three
  /// distinct corners): signed volume (mm^3, divergence theorem, negative when inside out);
  /// whether every shell is oriented so the solid is on its inner side (nested shells
  /// alternate: PMP::does_bound_a_volume and a positive volume; when self-intersections
  /// exist, were not searched for, or faces are degenerate, a positive volume alone); and the
  /// genus (sum over shells of (2 - V + E - F) / 2: sphere 0, torus 1).
  std::optional<double> volume;
  std::optional<bool> outward;
  std::optional<std::int64_t> genus;

  // --- where -------------------------------------------------------------------------
  // At most CheckOptions::max_examples of each. Edges: ends in the direction the named
  // triangle walks them, in order of vertex ids (first occurrence of a position in the
  // soup); vertices likewise; triangles in input order; self-intersections as (i < j) pairs
  // of input triangle indices, sorted.
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

  /// The verdict behind `tpmsfill check`'s exit code 0: a closed 2-manifold, consistently and
  /// outwardly oriented, without degenerate or duplicate triangles or self-intersections
  /// (unsearched self-intersections count as none), and with at least one triangle.
  bool valid() const;

  /// One sentence per failed condition of valid(), in the order checked; empty when valid.
  std::vector<std::string> problems() const;
};

/// Establishes the facts above.
/// @param[in] soup     any triangle soup (indices must be in range, which readers guarantee)
/// @param[in] options  which expensive facts to compute, how many examples to keep
/// @throws InputError  an index is out of range, or the soup has more triangles or points
///                     than 32-bit corner and vertex numbers allow
/// @throws Error       internal: CGAL built a different number of faces than it was given
MeshCheck check_mesh(const TriangleSoup& soup, const CheckOptions& options = {});

/// What rounding a mesh's coordinates as a file holds them (rounding_for(format), io.hpp: STL's
/// floats, 3MF's micrometres) does to its triangles: far from the origin a sliver's corners can
/// round onto one point or one line. Marching cubes' meshes are kept clear of this by
/// construction (their points sit on grid edges, clear of the nodes); points that come from
/// anywhere else, such as iso-material surfaces mapped through a spline, are not.
struct RoundingCheck {
  std::uint64_t degenerate = 0;       ///< degenerate triangles of the mesh as given
  std::uint64_t held_degenerate = 0;  ///< of the mesh as the file holds it
  /// When the rounding made any: a sentence with how many, how far out, and what to do; else
  /// empty.
  std::string warning;
};

/// @throws InputError  as check_mesh()
RoundingCheck check_rounding(const TriangleSoup& soup, CoordinateRounding rounding);

/// The JSON object `tpmsfill check --json` prints (2-space indent, keys in this order;
/// doubles in shortest round-trip form; null where a fact is unset):
///
///   valid, problems (strings), points, triangles, vertices, duplicate_points,
///   unreferenced_points, bbox ({min:[x,y,z], max:[x,y,z]}, null without triangles),
///   degenerate_triangles, duplicate_triangles, edges, border_edges, holes,
///   non_manifold_edges, non_manifold_vertices, inconsistent_edges, consistently_oriented,
///   closed, manifold, components, edge_components, self_intersecting_pairs (null when not
///   searched), area, volume, outward, genus (null unless closed, manifold and oriented),
///   examples: {border_edges, non_manifold_edges, inconsistent_edges: [{a:[x,y,z], b:[x,y,z],
///   triangle:i}], non_manifold_vertices: [[x,y,z]], degenerate_triangles: [i],
///   duplicate_triangles: [i], self_intersections: [[i,j]]}.
///
/// Each field means what the MeshCheck member (or method) of the same name means.
std::string to_json(const MeshCheck& check);

}  // namespace tpmsfill
