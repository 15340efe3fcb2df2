// Stage "classify": one line along x per grid row (j, k); the AABB trees hand over the
// triangles whose box holds the line, each crossing is decided exactly in the yz plane with
// a symbolic perturbation, the crossing x positions are sorted and the spans between odd and
// even crossings filled.
//
// The perturbation. The row's point p = (y, z) is moved to p' = (y + ε, z + ε²), 0 < ε ≪ 1.
// For an edge (a, b) of a projected triangle, orientation(a, b, p') is the sign of
//   (b.y − a.y)(p.z + ε² − a.z) − (b.z − a.z)(p.y + ε − a.y)
// = orientation(a, b, p) + (a.z − b.z)·ε + (b.y − a.y)·ε²,
// so where orientation(a, b, p) = 0 it is sign(a.z − b.z) when a.z ≠ b.z, else
// sign(b.y − a.y) (never 0: a ≠ b for an edge of a non-degenerate projected triangle).
// p' lies on no line through two distinct input points, so it is strictly inside or strictly
// outside every projected triangle of non-zero area: an edge shared by two triangles on
// opposite sides is counted by exactly one, a vertex by exactly one of its fan, and a
// triangle seen edge-on (zero projected area) by none. Parity of the perturbed line is then
// the exact parity of the surface along it. All predicates are CGAL Epick's (exact); only the
// crossing's x position is computed in double.
#include "tpmsfill/classify.hpp"

#include <algorithm>
#include <cmath>
#include <vector>

#include "detail/mesh_index_impl.hpp"
#include "detail/parallel.hpp"
#include "tpmsfill/error.hpp"

namespace tpmsfill {
namespace {

using detail::TreeNode;
using detail::TrianglePrimitive;
using Point2 = detail::Kernel::Point_2;

/// The line {(x, y, z) : x ∈ ℝ} of one grid row.
struct RowLine {
  double y, z;
};

/// Does the perturbed point p' = (p.y + ε, p.z + ε²) lie strictly left of a → b?
bool left_of(const Point2& a, const Point2& b, const Point2& p) {
  switch (CGAL::orientation(a, b, p)) {
    case CGAL::LEFT_TURN:
      return true;
    case CGAL::RIGHT_TURN:
      return false;
    default:
      if (a.y() != b.y()) return a.y() > b.y();  // sign(a.z − b.z), z is Point2::y()
      return b.x() > a.x();                      // sign(b.y − a.y), y is Point2::x()
  }
}

/// Traversal traits (AABB_tree::traversal): collects the x of every exact crossing of the
/// perturbed row line with a triangle.
class RowCrossings {
 public:
  RowCrossings(const detail::TriangleArray& triangles, std::vector<double>& out)
      : triangles_(triangles), out_(out) {}

  bool go_further() const { return true; }

  bool do_intersect(const RowLine& q, const TreeNode& node) const {
    const CGAL::Bbox_3& b = node.bbox();
    return b.ymin() <= q.y && q.y <= b.ymax() && b.zmin() <= q.z && q.z <= b.zmax();
  }

  void intersection(const RowLine& q, const TrianglePrimitive& primitive) {
    const auto& v = triangles_[primitive.id()].v;
    // Cheap exact rejection: the perturbed point needs y ∈ [min, max) and z ∈ [min, max).
    if (q.y < std::fmin(std::fmin(v[0].y, v[1].y), v[2].y) ||
        q.y >= std::fmax(std::fmax(v[0].y, v[1].y), v[2].y) ||
        q.z < std::fmin(std::fmin(v[0].z, v[1].z), v[2].z) ||
        q.z >= std::fmax(std::fmax(v[0].z, v[1].z), v[2].z))
      return;
    int ia = 0, ib = 1, ic = 2;
    Point2 a(v[ia].y, v[ia].z), b(v[ib].y, v[ib].z), c(v[ic].y, v[ic].z);
    const CGAL::Orientation o = CGAL::orientation(a, b, c);
    if (o == CGAL::COLLINEAR) return;  // seen edge-on: never a crossing
    if (o == CGAL::CLOCKWISE) {
      std::swap(b, c);
      std::swap(ib, ic);
    }
    const Point2 p(q.y, q.z);
    if (!left_of(a, b, p) || !left_of(b, c, p) || !left_of(c, a, p)) return;

    // x of the crossing by barycentric coordinates in double; exact when the triangle's
    // corners share one x (a face on a grid plane stays on it), clamped to the corners' range.
    auto area2 = [](double ay, double az, double by, double bz, double cy, double cz) {
      return (by - ay) * (cz - az) - (bz - az) * (cy - ay);
    };
    const Vec3 &A = v[ia], &B = v[ib], &C = v[ic];
    const double total = area2(A.y, A.z, B.y, B.z, C.y, C.z);
    const double wb = area2(A.y, A.z, q.y, q.z, C.y, C.z) / total;  // weight of B
    const double wc = area2(A.y, A.z, B.y, B.z, q.y, q.z) / total;  // weight of C
    double x = A.x + (wb * (B.x - A.x) + wc * (C.x - A.x));
    x = std::clamp(x, std::fmin(std::fmin(A.x, B.x), C.x), std::fmax(std::fmax(A.x, B.x), C.x));
    out_.push_back(x);
  }

 private:
  const detail::TriangleArray& triangles_;
  std::vector<double>& out_;
};

/// Index of the first node with coordinate > x (dims[0] if none).
int first_node_after(const Grid& grid, double x) {
  const int n = grid.dims[0];
  double guess = std::floor((x - grid.origin.x) / grid.spacing);
  int i = guess < -1.0 ? 0 : (guess > n ? n : static_cast<int>(guess));
  while (i > 0 && grid.coordinate(0, i - 1) > x) --i;
  while (i < n && !(grid.coordinate(0, i) > x)) ++i;
  return i;
}

/// What one row contributes.
struct RowResult {
  double length = 0;  ///< inside length within the grid's x range, mm
  std::uint32_t crossings = 0;
  bool odd = false;
};

}  // namespace

Occupancy classify_grid(const MeshIndex& index, const Grid& grid, const ClassifyOptions& options) {
  const MeshIndex::Impl& impl = index.impl();
  Occupancy result;
  result.inside.grid = grid;
  result.inside.values.assign(grid.node_count(), 0);
  const std::size_t nx = static_cast<std::size_t>(std::max(grid.dims[0], 0));
  const std::size_t rows = nx == 0 ? 0
                                   : static_cast<std::size_t>(std::max(grid.dims[1], 0)) *
                                         static_cast<std::size_t>(std::max(grid.dims[2], 0));
  result.rays = rows;
  if (rows == 0) return result;

  const double x_first = grid.coordinate(0, 0);
  const double x_last = grid.coordinate(0, grid.dims[0] - 1);
  std::vector<RowResult> per_row(rows);
  detail::ProgressCounter progress(options.progress, "classify", rows);

  detail::parallel_for(rows, 64, [&](std::size_t begin, std::size_t end) {
    std::vector<double> crossings;
    for (std::size_t row = begin; row < end; ++row) {
      const int j = static_cast<int>(row % static_cast<std::size_t>(grid.dims[1]));
      const int k = static_cast<int>(row / static_cast<std::size_t>(grid.dims[1]));
      const RowLine line{grid.coordinate(1, j), grid.coordinate(2, k)};
      crossings.clear();
      RowCrossings traits(impl.triangles, crossings);
      for (const auto& tree : impl.trees) tree->traversal(line, traits);
      std::sort(crossings.begin(), crossings.end());

      RowResult& r = per_row[row];
      r.crossings = static_cast<std::uint32_t>(crossings.size());
      if (crossings.size() % 2 == 1) {
        r.odd = true;
        crossings.pop_back();  // the line enters and never leaves: ignore the last crossing
      }
      std::uint8_t* out = result.inside.values.data() + grid.index(0, j, k);
      for (std::size_t s = 0; s < crossings.size(); s += 2) {
        const double enter = crossings[s], leave = crossings[s + 1];
        // Nodes strictly between the two crossings are inside; one exactly on either is not.
        const int i0 = first_node_after(grid, enter);
        for (int i = i0; i < grid.dims[0] && grid.coordinate(0, i) < leave; ++i) out[i] = 1;
        const double lo = std::max(enter, x_first), hi = std::min(leave, x_last);
        if (hi > lo) r.length += hi - lo;
      }
    }
    progress.add(end - begin);
  });
  progress.finish();

  double length = 0;  // summed in row order: the same for every thread count
  for (const RowResult& r : per_row) {
    length += r.length;
    result.crossings += r.crossings;
    result.odd_rays += r.odd ? 1 : 0;
  }
  result.volume = length * grid.spacing * grid.spacing;
  return result;
}

}  // namespace tpmsfill
