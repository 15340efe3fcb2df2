/// @file soup_topology.hpp
/// @brief Plain-data topology of a triangle soup: equal points merged, degenerate and duplicate
/// triangles found, an edge table, vertex fans and connected components. No CGAL, no geometry
/// beyond comparing coordinates; shared by the "check" and "clean" stages. Components of a
/// mesh as indexed (no merging), for "validate" and "components", are at the end.
///
/// Vocabulary used below:
/// - *vertex*: a distinct position. Points are merged when their coordinates are equal (bit
///   for bit, except that -0.0 and +0.0 are the same); vertex ids follow the order of first
///   occurrence in TriangleSoup::points.
/// - *repeated-corner triangle*: two of its corners are the same vertex. Such triangles are
///   left out of the edge table, fans and edge components (they still join vertex components).
/// - *duplicate triangle*: a triangle that is not repeated-corner and has the same vertex set as
///   an earlier one (any order or orientation).
/// - *kept triangle*: neither repeated-corner nor duplicate. The kept triangles are what
///   CGAL's repair_polygon_soup() leaves of a triangle soup.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "core/disjoint_sets.hpp"
#include "core/index_limits.hpp"
#include "tpmsfill/types.hpp"

namespace tpmsfill::detail {

/// Input points grouped by equal coordinates.
struct PointMerge {
  std::vector<std::uint32_t> vertex_of_point;  ///< per input point: its vertex id
  std::vector<std::uint32_t> first_point;      ///< per vertex: first input point with its position
};

/// Merges points with equal coordinates (sort-based, deterministic; no tolerance).
PointMerge merge_equal_points(const std::vector<Vec3>& points);

/// One triangle's use of an edge: the triangle walks corner -> corner+1 (mod 3).
struct EdgeUse {
  std::uint32_t triangle = 0;  ///< input triangle index
  std::uint8_t corner = 0;     ///< 0, 1 or 2
  bool forward = false;        ///< walks the edge from Edge::a to Edge::b
};

/// A distinct undirected edge between vertices a < b and the triangles that use it.
struct Edge {
  std::uint32_t a = 0, b = 0;    ///< vertex ids, a < b
  std::uint32_t first_use = 0;   ///< into SoupTopology::edge_uses
  std::uint32_t use_count = 0;   ///< triangles (not repeated-corner) using it, duplicates included
  std::uint32_t kept_count = 0;  ///< of those, kept triangles
};

/// Everything plain-data we know about a soup's connectivity.
struct SoupTopology {
  enum TriangleFlag : std::uint8_t { kRepeatedCorner = 1, kDuplicate = 2 };

  PointMerge merge;
  std::uint32_t vertex_count = 0;                     ///< distinct positions among all points
  std::vector<std::array<std::uint32_t, 3>> corners;  ///< per triangle: vertex ids
  std::vector<std::uint8_t> flags;                    ///< per triangle: TriangleFlag bits
  std::vector<bool> vertex_referenced;                ///< per vertex: used by some triangle

  /// Distinct undirected edges of the non-repeated-corner triangles, sorted by (a, b); each
  /// edge's uses lie in edge_uses[first_use, first_use + use_count), sorted by triangle.
  std::vector<Edge> edges;
  std::vector<EdgeUse> edge_uses;

  /// Per vertex: fans of its non-repeated-corner triangles, where two triangles around the
  /// vertex are in the same fan when they share an edge through it used by two or more
  /// triangles. 0 for vertices without such triangles; more than 1 means a pinched vertex.
  std::vector<std::uint32_t> fans;

  /// Per vertex: vertex-connected component id (0, 1, ... in order of the smallest vertex id),
  /// kNoIndex for unreferenced vertices.
  std::vector<std::uint32_t> vertex_component;
  std::uint32_t vertex_components = 0;

  /// Kept triangles joined through edges with exactly two kept triangles (what CGAL's
  /// connected_components() sees once the soup is repaired and oriented).
  std::uint32_t edge_components = 0;
  /// Non-repeated-corner triangles joined through edges with exactly two such triangles
  /// (the shells whose Euler characteristics add up to the genus).
  std::uint32_t surface_components = 0;
};

/// Builds the topology. Precondition: every index < soup.points.size().
SoupTopology analyze_soup(const TriangleSoup& soup);

/// Triangles joined through shared point indices, as the "validate" and "components" stages
/// judge a mesh: exactly as indexed, equal positions not merged.
struct TriangleComponents {
  std::vector<std::uint32_t> of_triangle;  ///< per triangle, numbered in order of first triangle
  std::uint32_t count = 0;
};

/// Labels the components. Precondition: every index < mesh.points.size().
TriangleComponents triangle_components(const TriangleSoup& mesh);

}  // namespace tpmsfill::detail
