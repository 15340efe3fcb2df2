/// @file validate.hpp
/// @brief Stage "validate": is an indexed triangle mesh (typically marching-cubes output) a
/// closed, consistently and outwardly oriented 2-manifold without degenerate faces or
/// self-intersections?
///
/// Unlike check_mesh() (which accepts any soup and merges bit-identical points first), this
/// judges the mesh exactly as indexed, fast enough for multi-million-triangle outputs: the
/// topology is integer sorting, geometric decisions use CGAL's exact predicates (Epick).
/// Returns data; fill() turns a failing report into a ValidationError. The report counts the
/// mesh's connected components; to list, measure or drop them see components.hpp.
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "tpmsfill/progress.hpp"
#include "tpmsfill/types.hpp"

namespace tpmsfill {

struct ValidateOptions {
  bool self_intersections = true;  ///< search for intersecting triangle pairs (exact)
  /// When set, every triangle should lie in one closed cell of this grid (true of
  /// marching_cubes() output on that grid): the intersection search then only pairs triangles
  /// of the same or 26-adjacent cells (each triangle belongs to the cell of its centroid).
  /// If some triangle does not lie in its cell (beyond a tolerance of 1e-7 cells), the general
  /// search runs instead, so the answer never depends on this promise. Without a grid a
  /// general box-intersection search (CGAL::box_self_intersection_d) is used.
  std::optional<Grid> cell_grid;
  std::size_t max_examples = 10;  ///< example locations kept per defect class
  Progress* progress = nullptr;
};

struct ValidationReport {
  std::uint64_t vertices = 0;  ///< points referenced by triangles
  std::uint64_t triangles = 0;
  std::uint64_t border_edges = 0;           ///< undirected edges used by one triangle
  std::uint64_t non_manifold_edges = 0;     ///< used by three or more
  std::uint64_t non_manifold_vertices = 0;  ///< whose triangles form more than one fan
  std::uint64_t inconsistent_edges = 0;     ///< two triangles walking it the same way
  std::uint64_t degenerate_triangles = 0;   ///< repeated corner or collinear (exact)
  /// Referenced points whose position (bit for bit; -0.0 == +0.0) an earlier referenced point
  /// already has.
  std::uint64_t duplicate_points = 0;
  /// Pairs of non-degenerate triangles that intersect with exact predicates, as CGAL's
  /// PMP::self_intersections decides it with shared corners taken by index: sharing an edge,
  /// only if they overlap (coplanar, opposite corners on the same side); sharing one corner,
  /// only if they also meet elsewhere; otherwise if they meet at all. Degenerate triangles are
  /// counted above and left out of the search. Unset when not searched.
  std::optional<std::uint64_t> self_intersecting_pairs;
  /// The search paired triangles by options.cell_grid; false when it was not set, when some
  /// triangle did not lie in its cell (then the general search ran: for marching-cubes output
  /// on that grid this means a bug upstream), or when not searched.
  bool searched_by_cells = false;
  std::uint64_t components = 0;  ///< connected through shared vertices
  double area = 0;               ///< mm^2
  double volume = 0;             ///< signed, mm^3 (divergence theorem, summed in fixed order)
  /// Every component has a non-zero volume and the total is positive (with the mesh closed
  /// and consistently oriented, normals then point out of the solid).
  bool outward = false;

  /// Triangle pairs (i < j), the smallest in lexicographic order.
  std::vector<std::array<std::uint32_t, 2>> self_intersection_examples;
  std::vector<std::uint32_t> degenerate_examples;  ///< triangles, in index order
  /// Up to max_examples border edges, then up to max_examples non-manifold edges, then up to
  /// max_examples inconsistent edges, each in order of (smaller, larger) point index; the ends
  /// in the direction the edge's first triangle (lowest index) walks it.
  std::vector<std::array<Vec3, 2>> bad_edge_examples;

  bool closed() const { return border_edges == 0; }
  bool manifold() const { return non_manifold_edges == 0 && non_manifold_vertices == 0; }
  bool valid() const;
  /// One sentence per failed condition, in the order checked; empty when valid().
  std::vector<std::string> problems() const;
};

/// Validates `mesh` as indexed.
/// @throws InputError  an index is out of range, or the mesh has more triangles or points
///                     than 32-bit corner numbers allow
/// @throws Cancelled   when options.progress says so
ValidationReport validate_mesh(const TriangleSoup& mesh, const ValidateOptions& options = {});

}  // namespace tpmsfill
