/// @file check.hpp
/// @brief Stage "check": is a triangle soup a closed, outward-oriented 2-manifold without
/// self-intersections or degenerate faces, and if not, where?
///
/// Topology is judged after merging points with bit-identical coordinates (STL stores three
/// points per facet; no tolerance is ever used; -0.0 and +0.0 count as equal). Geometric decisions
/// use exact predicates (Epick): degenerate faces, self-intersections by validate_mesh()'s pair
/// test, and holes and orientation by CGAL Polygon Mesh Processing. The report is a
/// MeshValidity (validate.hpp: one verdict, one list of problems) with the soup's own facts.
/// The soup itself is never modified.
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "tpmsfill/mesh/validate.hpp"
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

/// The facts check_mesh() establishes: validity as MeshValidity states it (points merged by
/// position, holes counted, volume and orientation only for a closed, manifold, consistently
/// oriented mesh), and the soup's own facts below. Triangle indices refer to the input soup's
/// triangles.
struct MeshCheck : MeshValidity {
  std::uint64_t points = 0;               ///< points in the soup, as given
  Box3 bbox;                              ///< of referenced points
  std::uint64_t unreferenced_points = 0;  ///< points no triangle uses
  std::uint64_t edges = 0;                ///< distinct undirected edges
  /// Connected through edges shared by exactly two triangles, repeated-corner and duplicate
  /// triangles left out: the connected components of the mesh CGAL builds. Its border cycles
  /// are the holes: repeated-corner and duplicate triangles dropped
  /// (PMP::repair_polygon_soup), oriented (PMP::orient_polygon_soup, which splits non-manifold
  /// edges and vertices, so a non-manifold soup may have holes without border edges, or more
  /// holes than border edges).
  std::uint64_t edge_components = 0;
  /// Sum over shells of (2 - V + E - F) / 2 (sphere 0, torus 1); set when volume is.
  std::optional<std::int64_t> genus;
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
