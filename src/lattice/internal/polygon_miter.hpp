/// @file polygon_miter.hpp
/// @brief Mitered signed distance to a simple polygon in the plane (negative inside), for seed
/// 004's "tangent-connected" rings: the offset at which the outline's straight-line offset front
/// (edges moved parallel, corners extended until they meet, reflex corners trimmed) passes
/// through the point. In the straight-skeleton face of edge e that is the distance to e's line,
/// so the faces of the interior and exterior skeletons are computed once (CGAL, in
/// src/lattice/internal/polygon_miter.cpp only) and kept as plain polygons, sorted into square
/// buckets so a query tests a few of them.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

namespace tpmsfill::detail {

/// Whether the closed outline is simple: no two edges cross or touch, except neighbours at
/// their shared corner (repeated corners and straight-through corners aside).
bool is_simple_outline(const std::vector<std::array<double, 2>>& loop);

class PolygonMiterDistance {
 public:
  using Point = std::array<double, 2>;

  /// @param loop   the polygon's corners in order, either orientation (closed implicitly),
  ///               a simple polygon with at least 3 distinct corners
  /// @param reach  offsets up to this are exact; beyond it only the sign is (|value| > reach)
  /// @param closed_form_if_convex  a convex outline's offset is its largest distance to an
  ///               edge's line: no skeleton is built (false: the skeleton anyway, for tests)
  /// @throws InputError when the outline is not simple or its skeleton cannot be built
  PolygonMiterDistance(const std::vector<Point>& loop, double reach,
                       bool closed_form_if_convex = true);

  /// The mitered offset through p, negative inside. Const and lock-free: safe from any thread.
  double operator()(Point p) const;

 private:
  // One skeleton face: its corners corners_[first, first + count), and its edge's line
  // through `a` with unit normal `n`; the value in it is sign * |n . (p - a)|.
  struct Face {
    std::uint32_t first = 0, count = 0;
    Point a{}, n{}, lo{}, hi{};
    double sign = 1;
  };

  void add_face(const std::vector<Point>& corners, Point a, Point b, double sign);
  void build_grid();
  bool contains(const Face& f, Point p) const;
  double boundary_distance(const Face& f, Point p) const;
  bool overlaps(const Face& f, Point lo, Point hi) const;
  double value(const Face& f, Point p) const;
  int cell(double x, int a) const;

  double beyond_ = 0, tolerance_ = 0, size_ = 1;
  std::vector<std::array<Point, 2>> edges_;  // convex closed form: (corner, outward unit normal)
  std::vector<Face> faces_;
  std::vector<Point> corners_;
  Point lo_{}, hi_{};
  std::array<int, 2> n_{};
  std::vector<std::uint32_t> start_, bucket_;  // bucket k's faces: bucket_[start_[k], start_[k+1])
};

}  // namespace tpmsfill::detail
