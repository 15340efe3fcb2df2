// Stage "classify": one line along x per grid row (j, k); the AABB trees hand over the
// triangles whose box holds the line, each crossing is decided exactly in the yz plane with a
// symbolic perturbation (mesh/row_crossing.hpp), the crossings are sorted and one pass
// along the row turns them into parity or the winding number at every node.
//
// Only the crossing's x position is computed in double; which triangles are crossed, and in
// which direction, is exact. The caps' winding number (holes) is floating point: it is a
// smooth sum, compared against J − ½ only where its certified bound leaves the answer open.
#include "tpmsfill/sampling/classify.hpp"

#include <algorithm>
#include <cmath>
#include <vector>

#include "core/grid_buffer.hpp"
#include "core/parallel.hpp"
#include "core/stage_progress.hpp"
#include "mesh/row_crossing.hpp"
#include "sampling/internal/mesh_index_impl.hpp"
#include "tpmsfill/error.hpp"

namespace tpmsfill {
namespace {

using detail::RowCrossing;
using detail::TreeNode;
using detail::TrianglePrimitive;

/// The line {(x, y, z) : x ∈ ℝ} of one grid row.
struct RowLine {
  double y, z;
};

/// Traversal traits (AABB_tree::traversal): collects every exact crossing of the perturbed
/// row line with a triangle.
class RowCrossings {
 public:
  RowCrossings(const detail::MeshIndexAccess::Impl& index, std::vector<RowCrossing>& out)
      : triangles_(index.triangles), order_(index.order.data()), out_(out) {}

  bool go_further() const { return true; }

  bool do_intersect(const RowLine& q, const TreeNode& node) const {
    const CGAL::Bbox_3& b = node.bbox();
    return b.ymin() <= q.y && q.y <= b.ymax() && b.zmin() <= q.z && q.z <= b.zmax();
  }

  void intersection(const RowLine& q, const TrianglePrimitive& primitive) {
    primitive.for_each_triangle(order_, [&](std::uint32_t id) {
      const std::array<Vec3, 3> v = triangles_[id];
      // The row misses a triangle whose y or z range excludes it (as it misses such a box).
      const auto [ylo, yhi] = detail::corner_range(v, 1);
      const auto [zlo, zhi] = detail::corner_range(v, 2);
      if (q.y < ylo || q.y > yhi || q.z < zlo || q.z > zhi) return;
      RowCrossing c = detail::row_crossing(v, q.y, q.z);
      c.cap = id >= triangles_.first_cap();
      if (c.sign != 0) out_.push_back(c);
    });
  }

 private:
  const detail::TriangleArray& triangles_;
  const std::uint32_t* order_;
  std::vector<RowCrossing>& out_;
};

/// What one row contributes.
struct RowResult {
  double length = 0;  ///< inside length within the grid's x range, mm
  std::uint32_t crossings = 0;
  std::uint32_t disagreements = 0;
  std::uint32_t cap_evaluations = 0;
  bool odd = false;
  bool overlap = false;
  bool unbalanced = false;
};

// Where hole caps close the model M, w_M = J_M + R (sampling/internal/cap_winding.hpp): J_M counts
// the model's crossings and R, which depends only on the holes' rims, is continuous along the row
// and varies on the scale of the distance to the nearest rim. R is therefore sampled, not
// evaluated at every node: at both ends of the row's stretch near the caps and at midpoints,
// recursively. Near a rim R turns like the angle around a wire, |R''| ≈ 1 / (2π d²) at
// distance d, so linear interpolation over a stretch of length L errs by about
// (L / d)² / (16π): a stretch is interpolated once L is at most kStrideToRim times its
// distance to the nearest rim (error ≤ 0.02) and its midpoint agrees with the interpolation
// to kRemainderTolerance. A node whose interpolated w_M lies within kThresholdGuard of ½ is
// evaluated directly.
//
// R is continuous, but its formula has a cut where a rim's sweep to x = −∞ passes through the
// row (a rim edge on a grid row, common in CAD parts): there both the strip's solid angle
// and ω jump, and near it the strip's formula loses digits quadratically in the angle to
// the cut. R is therefore evaluated on the row moved off by kRowOffset times the caps' size
// in y and z (differently): the formula keeps about ten digits there, R moves by at most
// kRowOffset·size / (2π d) at distance d from a rim (below 0.002 a voxel from it for grids
// up to a thousand voxels across), and the crossings J_M stay exact on the row itself.
constexpr double kRemainderTolerance = 0.01;
constexpr double kStrideToRim = 1.0;
constexpr double kThresholdGuard = 0.03;
constexpr double kRowOffset = 1e-5;

/// R at the nodes [first, last] of one row, sampled as above.
class RowRemainder {
 public:
  RowRemainder(const Grid& grid, const RowLine& line, const detail::CapWinding& caps, int n,
               RowResult& r)
      : grid_(grid), caps_(caps), r_(r), values_(n, 0.0), rim_(n, 0.0), sampled_(n, false) {
    const double size = norm(caps.bounds().size());
    y_ = line.y + kRowOffset * size;
    z_ = line.z + 0.61803 * kRowOffset * size;
    shadow_ = caps.shadow_winding(y_, z_);
  }

  /// R at node i, evaluated.
  double exact(int i) {
    ++r_.cap_evaluations;
    sampled_[i] = true;
    return values_[i] = caps_.remainder({grid_.coordinate(0, i), y_, z_}, shadow_, &rim_[i]);
  }

  /// R at every node of [first, last].
  void sample(int first, int last) {
    exact(first);
    if (last != first) exact(last);
    fill(first, last);
  }

  double value(int i) const { return values_[i]; }
  bool sampled(int i) const { return sampled_[i]; }

 private:
  void fill(int first, int last) {
    if (last - first <= 1) return;
    const int mid = (first + last) / 2;
    exact(mid);
    const double length = grid_.spacing * (last - first);
    const double clearance = std::min(rim_[first], rim_[last]) - 0.5 * length;
    const double t = static_cast<double>(mid - first) / (last - first);
    const double lerp = values_[first] + t * (values_[last] - values_[first]);
    if (length <= kStrideToRim * clearance &&
        std::fabs(values_[mid] - lerp) <= kRemainderTolerance) {
      for (int i = first + 1; i < last; ++i)
        if (i != mid)
          values_[i] = values_[first] + static_cast<double>(i - first) / (last - first) *
                                            (values_[last] - values_[first]);
      return;
    }
    fill(first, mid);
    fill(mid, last);
  }

  const Grid& grid_;
  const detail::CapWinding& caps_;
  RowResult& r_;
  std::vector<double> values_, rim_;
  std::vector<bool> sampled_;
  double y_ = 0, z_ = 0;  ///< the row, moved off
  int shadow_ = 0;
};

/// One row: crossings sorted by x in, occupancy of the row's nodes out.
void classify_row(const Grid& grid, const RowLine& line, std::vector<RowCrossing>& crossings,
                  const detail::CapWinding& caps, const Box3& bounds, InsideRule rule,
                  std::uint8_t* out, RowResult& r) {
  std::sort(crossings.begin(), crossings.end(), [](const RowCrossing& a, const RowCrossing& b) {
    return a.x < b.x || (a.x == b.x && a.sign < b.sign);
  });
  r.crossings = static_cast<std::uint32_t>(crossings.size());
  // Parity pairs crossings up; a row that enters and never leaves ignores its last crossing.
  std::size_t parity_count = crossings.size();
  if (parity_count % 2 == 1) {
    r.odd = true;
    --parity_count;
  }

  // Spans between consecutive crossings: the state after crossing c holds until c + 1.
  const double x_first = grid.coordinate(0, 0), x_last = grid.coordinate(0, grid.dims[0] - 1);
  int winding = 0;
  for (std::size_t c = 0; c < crossings.size(); ++c) {
    winding += crossings[c].sign;
    const bool inside =
        rule == InsideRule::Parity ? (c < parity_count && c % 2 == 0) : winding >= 1;
    if (!inside || c + 1 == crossings.size()) continue;
    const double lo = std::max(crossings[c].x, x_first), hi = std::min(crossings[c + 1].x, x_last);
    if (hi > lo) r.length += hi - lo;
  }

  if (winding != 0) r.unbalanced = true;

  // Nodes: J below (crossings with x < node) and above (x ≤ node); a node on a crossing takes
  // the lower J, and parity counts it as outside. J_M and J_C likewise for the model and caps.
  const int n = grid.dims[0];
  const bool near_caps =
      rule == InsideRule::Winding && !caps.empty() && caps.row_bound(line.y, line.z) >= 0.5;
  std::vector<int> model_j(near_caps ? n : 0);
  if (crossings.empty() && !near_caps) return;  // the row's nodes are outside (zeroed)
  // Parity per node, kept only where the caps may still change the answer.
  std::vector<std::uint8_t> parity(near_caps ? n : 0);
  winding = 0;
  int model = 0;
  std::size_t below = 0;
  for (int i = 0; i < n; ++i) {
    const double x = grid.coordinate(0, i);
    for (; below < crossings.size() && crossings[below].x < x; ++below) {
      winding += crossings[below].sign;
      if (!crossings[below].cap) model += crossings[below].sign;
    }
    int j = winding, above = winding, model_above = model;
    std::size_t on = below;
    for (; on < crossings.size() && crossings[on].x == x; ++on) {
      above += crossings[on].sign;
      if (!crossings[on].cap) model_above += crossings[on].sign;
    }
    j = std::min(j, above);
    const bool odd = on == below && below < parity_count && below % 2 == 1;
    bool inside = odd;
    if (rule == InsideRule::Winding) {
      inside = j >= 1;
      if (j < 0 || j > 1) r.overlap = true;
      if (j < 0) r.unbalanced = true;
      if (near_caps) {
        model_j[i] = std::min(model, model_above);
        parity[i] = odd ? 1 : 0;
      } else if (inside != odd) {
        ++r.disagreements;
      }
    }
    out[i] = inside ? 1 : 0;
  }
  if (near_caps) {
    // The stretch of the row where the caps' winding number could reach ½.
    auto near = [&](int i) { return caps.bound({grid.coordinate(0, i), line.y, line.z}) >= 0.5; };
    int first = 0, last = n - 1;
    while (first < n && !near(first)) ++first;
    while (last > first && !near(last)) --last;
    // Overlapping open surfaces can lift w to ½ even outside the model's box (two copies of
    // a part with the same face missing, seen from just beyond that face); nobody calls
    // that inside, and the grid's padding must stay outside.
    const bool row_in_box = bounds.min.y <= line.y && line.y <= bounds.max.y &&
                            bounds.min.z <= line.z && line.z <= bounds.max.z;
    while (first <= last && !(row_in_box && grid.coordinate(0, first) >= bounds.min.x)) ++first;
    while (last >= first && !(row_in_box && grid.coordinate(0, last) <= bounds.max.x)) --last;
    if (first <= last) {
      RowRemainder remainder(grid, line, caps, n, r);
      remainder.sample(first, last);
      for (int i = first; i <= last; ++i) {
        double w = model_j[i] + remainder.value(i);
        if (!remainder.sampled(i) && std::fabs(w - 0.5) < kThresholdGuard)
          w = model_j[i] + remainder.exact(i);
        out[i] = w >= 0.5 ? 1 : 0;
      }
      // The spans of J no longer describe this row: its length is its inside nodes'.
      r.length = 0;
      for (int i = 0; i < n; ++i) r.length += out[i] ? grid.spacing : 0.0;
    }
  }
  if (near_caps)
    for (int i = 0; i < n; ++i) r.disagreements += out[i] != parity[i];
}

}  // namespace

Occupancy classify_grid(const MeshIndex& index, const Grid& grid, const ClassifyOptions& options) {
  const auto& impl = detail::MeshIndexAccess::impl(index);
  Occupancy result;
  result.inside.grid = grid;
  detail::resize_on_huge_pages(result.inside.values, grid.node_count());
  if (grid.dims[0] < 0 || grid.dims[1] < 0 || grid.dims[2] < 0)
    throw InputError("classify_grid: the grid has a negative dimension");
  const std::size_t rows = grid.dims[0] == 0 ? 0 : grid.row_count();
  result.rows = rows;
  if (rows == 0) return result;

  std::vector<RowResult> per_row(rows);
  detail::ProgressCounter progress(options.progress, "classify", rows);

  detail::parallel_for(rows, 64, [&](std::size_t begin, std::size_t end) {
    std::vector<RowCrossing> crossings;
    for (std::size_t row = begin; row < end; ++row) {
      const int j = static_cast<int>(row % static_cast<std::size_t>(grid.dims[1]));
      const int k = static_cast<int>(row / static_cast<std::size_t>(grid.dims[1]));
      const RowLine line{grid.coordinate(1, j), grid.coordinate(2, k)};
      crossings.clear();
      RowCrossings traits(impl, crossings);
      for (const auto& tree : impl.trees) tree->traversal(line, traits);
      classify_row(grid, line, crossings, impl.caps, impl.bounds, options.rule,
                   result.inside.values.data() + grid.index(0, j, k), per_row[row]);
    }
    progress.add(end - begin);
  });
  progress.finish();

  // Summed in row order within a plane, then plane by plane: the same for every thread count,
  // and a slab's planes give the same figures as the whole grid's.
  const std::size_t ny = static_cast<std::size_t>(grid.dims[1]);
  result.planes.resize(static_cast<std::size_t>(grid.dims[2]));
  Occupancy::PlaneCounts total;
  for (std::size_t k = 0; k < result.planes.size(); ++k) {
    Occupancy::PlaneCounts& p = result.planes[k];
    double length = 0;
    for (std::size_t row = k * ny; row < (k + 1) * ny; ++row) {
      const RowResult& r = per_row[row];
      length += r.length;
      p.rows += 1;
      p.crossings += r.crossings;
      p.odd_rows += r.odd ? 1 : 0;
      if (options.rule == InsideRule::Winding) {
        p.overlap_rows += r.overlap ? 1 : 0;
        p.unbalanced_rows += r.unbalanced ? 1 : 0;
        p.parity_disagreements += r.disagreements;
        p.cap_evaluations += r.cap_evaluations;
      }
    }
    p.volume = length * grid.spacing * grid.spacing;
    total += p;
  }
  result.volume = total.volume;
  result.crossings = total.crossings;
  result.odd_rows = total.odd_rows;
  result.overlap_rows = total.overlap_rows;
  result.unbalanced_rows = total.unbalanced_rows;
  result.parity_disagreements = total.parity_disagreements;
  result.cap_evaluations = total.cap_evaluations;
  return result;
}

Occupancy::PlaneCounts& Occupancy::PlaneCounts::operator+=(const PlaneCounts& o) {
  volume += o.volume;
  rows += o.rows;
  crossings += o.crossings;
  odd_rows += o.odd_rows;
  overlap_rows += o.overlap_rows;
  unbalanced_rows += o.unbalanced_rows;
  parity_disagreements += o.parity_disagreements;
  cap_evaluations += o.cap_evaluations;
  return *this;
}

}  // namespace tpmsfill
