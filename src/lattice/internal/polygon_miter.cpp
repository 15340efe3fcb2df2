// Mitered offsets of a simple polygon through its straight skeletons (seed 004's ring regions):
// the only file that sees CGAL's Straight_skeleton_2. The skeletons are built once; what the
// queries read is plain data (each face's corners and its edge's line) in a bucket grid.
#include "lattice/internal/polygon_miter.hpp"

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Polygon_2_algorithms.h>
#include <CGAL/create_straight_skeleton_2.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>

#include "tpmsfill/error.hpp"

namespace tpmsfill::detail {
namespace {

using K = CGAL::Exact_predicates_inexact_constructions_kernel;
using Point = PolygonMiterDistance::Point;

K::Point_2 to_cgal(Point p) {
  return {p[0], p[1]};
}

// The outline without repeated corners or corners the outline runs straight through (their
// two edges share one line, so they change no offset), as CGAL points. Its orientation is
// left as given.
std::vector<K::Point_2> distinct_corners(const std::vector<Point>& loop) {
  std::vector<K::Point_2> out;
  for (const Point& p : loop)
    if (out.empty() || out.back() != to_cgal(p)) out.push_back(to_cgal(p));
  while (out.size() > 1 && out.front() == out.back()) out.pop_back();
  for (bool dropped = true; dropped && out.size() > 3;) {
    dropped = false;
    for (std::size_t i = 0; i < out.size() && out.size() > 3; ++i) {
      const K::Point_2 &a = out[(i + out.size() - 1) % out.size()], &b = out[i],
                       &c = out[(i + 1) % out.size()];
      if (CGAL::collinear(a, b, c) && CGAL::collinear_are_strictly_ordered_along_line(a, b, c)) {
        out.erase(out.begin() + static_cast<std::ptrdiff_t>(i));
        dropped = true;
      }
    }
  }
  return out;
}

bool simple(const std::vector<K::Point_2>& corners) {
  return corners.size() >= 3 && CGAL::is_simple_2(corners.begin(), corners.end(), K());
}

bool convex(const std::vector<K::Point_2>& corners) {
  for (std::size_t i = 0; i < corners.size(); ++i)
    if (CGAL::orientation(corners[i], corners[(i + 1) % corners.size()],
                          corners[(i + 2) % corners.size()]) != CGAL::LEFT_TURN)
      return false;
  return true;
}

// Liang-Barsky: whether segment ab meets the closed box [lo, hi].
bool segment_meets_box(Point a, Point b, Point lo, Point hi) {
  double t0 = 0, t1 = 1;
  for (int axis = 0; axis < 2; ++axis) {
    const double d = b[axis] - a[axis];
    if (d == 0) {
      if (a[axis] < lo[axis] || a[axis] > hi[axis]) return false;
      continue;
    }
    double u = (lo[axis] - a[axis]) / d, v = (hi[axis] - a[axis]) / d;
    if (u > v) std::swap(u, v);
    t0 = std::max(t0, u), t1 = std::min(t1, v);
    if (t0 > t1) return false;
  }
  return true;
}

double segment_distance(Point p, Point a, Point b) {
  const double ex = b[0] - a[0], ey = b[1] - a[1];
  const double len2 = ex * ex + ey * ey;
  double t = len2 > 0 ? ((p[0] - a[0]) * ex + (p[1] - a[1]) * ey) / len2 : 0;
  t = std::clamp(t, 0.0, 1.0);
  return std::hypot(p[0] - a[0] - t * ex, p[1] - a[1] - t * ey);
}

}  // namespace

bool is_simple_outline(const std::vector<std::array<double, 2>>& loop) {
  return simple(distinct_corners(loop));
}

PolygonMiterDistance::PolygonMiterDistance(const std::vector<Point>& loop, double reach,
                                           bool closed_form_if_convex)
    : beyond_(2 * reach) {
  if (!(reach > 0) || !std::isfinite(reach))
    throw InputError("a mitered outline's distances need a positive, finite reach");
  std::vector<K::Point_2> corners = distinct_corners(loop);
  if (!simple(corners))
    throw InputError(
        "a mitered polygon region's outline must be simple: at least 3 distinct corners, no "
        "edge crossing or touching another (round joins take any outline)");
  // CGAL wants the outline counter-clockwise; the exterior skeleton puts it, reversed, as the
  // hole of a frame whose margin lets the offset front run unhindered well past max_offset.
  // Half as much again as the reach keeps the frame's own front out of the band for sure.
  if (CGAL::orientation_2(corners.begin(), corners.end(), K()) == CGAL::CLOCKWISE)
    std::reverse(corners.begin(), corners.end());
  if (closed_form_if_convex && convex(corners)) {
    // Every corner turns left: the offset is the largest distance to an edge's line, and
    // CGAL's skeleton (slow for many corners on one circle, all meeting at its centre) is
    // not needed.
    for (std::size_t i = 0; i < corners.size(); ++i) {
      const K::Point_2 a = corners[i], b = corners[(i + 1) % corners.size()];
      const double ex = b.x() - a.x(), ey = b.y() - a.y(), length = std::hypot(ex, ey);
      edges_.push_back({Point{a.x(), a.y()}, Point{ey / length, -ex / length}});
    }
    return;
  }
  const auto inside =
      CGAL::create_interior_straight_skeleton_2(corners.begin(), corners.end(), K());
  const auto outside =
      CGAL::create_exterior_straight_skeleton_2(1.5 * reach, corners.begin(), corners.end(), K());
  if (!inside || !outside)
    throw InputError(
        "the straight skeleton of a mitered polygon region's outline could not be built (nearly "
        "touching edges or corners?): round joins take any outline");

  const CGAL::Bbox_2 box = CGAL::bbox_2(corners.begin(), corners.end());
  std::vector<Point> face;
  auto add = [&](const auto& skeleton, double sign) {
    for (auto f = skeleton.faces_begin(); f != skeleton.faces_end(); ++f) {
      // A face's halfedge is its contour edge; the exterior skeleton's frame edges start
      // outside the outline's box and their faces lie beyond the reach: left out.
      const auto edge = f->halfedge();
      const K::Point_2 a = edge->opposite()->vertex()->point(), b = edge->vertex()->point();
      if (a.x() < box.xmin() || a.x() > box.xmax() || a.y() < box.ymin() || a.y() > box.ymax())
        continue;
      face.clear();
      auto h = edge;
      do {
        face.push_back({h->vertex()->point().x(), h->vertex()->point().y()});
        h = h->next();
      } while (h != edge);
      add_face(face, {a.x(), a.y()}, {b.x(), b.y()}, sign);
    }
  };
  add(*inside, -1);
  add(*outside, 1);
  build_grid();
}

void PolygonMiterDistance::add_face(const std::vector<Point>& corners, Point a, Point b,
                                    double sign) {
  Face f;
  f.first = static_cast<std::uint32_t>(corners_.size());
  f.count = static_cast<std::uint32_t>(corners.size());
  const double ex = b[0] - a[0], ey = b[1] - a[1], length = std::hypot(ex, ey);
  f.a = a;
  f.n = {ey / length, -ex / length};
  f.sign = sign;
  f.lo = f.hi = corners.front();
  for (const Point& c : corners) {
    for (int axis = 0; axis < 2; ++axis)
      f.lo[axis] = std::min(f.lo[axis], c[axis]), f.hi[axis] = std::max(f.hi[axis], c[axis]);
    corners_.push_back(c);
  }
  faces_.push_back(f);
}

// Buckets about a quarter of a face's mean area wide each, every face in the buckets it
// overlaps (grown by a tolerance, so a query on a bucket's side finds its face either way).
void PolygonMiterDistance::build_grid() {
  lo_ = faces_.front().lo, hi_ = faces_.front().hi;
  for (const Face& f : faces_)
    for (int axis = 0; axis < 2; ++axis)
      lo_[axis] = std::min(lo_[axis], f.lo[axis]), hi_[axis] = std::max(hi_[axis], f.hi[axis]);
  const double width = hi_[0] - lo_[0], height = hi_[1] - lo_[1];
  tolerance_ = 1e-9 * std::max(width, height);
  for (int axis = 0; axis < 2; ++axis) lo_[axis] -= tolerance_, hi_[axis] += tolerance_;
  size_ = std::max(std::sqrt(width * height / (4.0 * static_cast<double>(faces_.size()))),
                   1e-6 * std::max(width, height));
  for (int axis = 0; axis < 2; ++axis)
    n_[axis] = std::clamp(static_cast<int>((hi_[axis] - lo_[axis]) / size_) + 1, 1, 1024);
  std::vector<std::pair<std::uint32_t, std::uint32_t>> pairs;  // (bucket, face)
  for (std::uint32_t k = 0; k < faces_.size(); ++k) {
    const Face& f = faces_[k];
    const int i0 = cell(f.lo[0] - tolerance_, 0), i1 = cell(f.hi[0] + tolerance_, 0);
    const int j0 = cell(f.lo[1] - tolerance_, 1), j1 = cell(f.hi[1] + tolerance_, 1);
    for (int j = j0; j <= j1; ++j)
      for (int i = i0; i <= i1; ++i) {
        const Point lo{lo_[0] + i * size_ - tolerance_, lo_[1] + j * size_ - tolerance_};
        const Point hi{lo[0] + size_ + 2 * tolerance_, lo[1] + size_ + 2 * tolerance_};
        if (overlaps(f, lo, hi)) pairs.push_back({static_cast<std::uint32_t>(i + n_[0] * j), k});
      }
  }
  std::sort(pairs.begin(), pairs.end());
  start_.assign(std::size_t(n_[0]) * n_[1] + 1, 0);
  bucket_.resize(pairs.size());
  for (std::size_t m = 0; m < pairs.size(); ++m) {
    ++start_[pairs[m].first + 1];
    bucket_[m] = pairs[m].second;
  }
  for (std::size_t k = 1; k < start_.size(); ++k) start_[k] += start_[k - 1];
}

double PolygonMiterDistance::operator()(Point p) const {
  if (!edges_.empty()) {
    double largest = -std::numeric_limits<double>::infinity();
    for (const auto& [a, n] : edges_)
      largest = std::max(largest, n[0] * (p[0] - a[0]) + n[1] * (p[1] - a[1]));
    return largest;
  }
  // Beyond the faces' box: outside the outline, farther than the reach.
  if (p[0] < lo_[0] || p[1] < lo_[1] || p[0] > hi_[0] || p[1] > hi_[1]) return beyond_;
  const std::size_t k = std::size_t(cell(p[0], 0)) + std::size_t(n_[0]) * cell(p[1], 1);
  for (std::uint32_t m = start_[k]; m < start_[k + 1]; ++m)
    if (contains(faces_[bucket_[m]], p)) return value(faces_[bucket_[m]], p);
  // In none: either in a rounding sliver between two faces (take the nearest: the value is
  // continuous across their shared side), or in the exterior frame's faces, past the reach.
  double nearest = std::numeric_limits<double>::infinity();
  const Face* face = nullptr;
  for (std::uint32_t m = start_[k]; m < start_[k + 1]; ++m) {
    const double d = boundary_distance(faces_[bucket_[m]], p);
    if (d < nearest) nearest = d, face = &faces_[bucket_[m]];
  }
  return face && nearest <= tolerance_ ? value(*face, p) : beyond_;
}

// Even-odd crossings of a ray towards +x, each side taken in one fixed direction so that the
// two faces sharing it compute the same crossing and no point between them is lost.
bool PolygonMiterDistance::contains(const Face& f, Point p) const {
  if (p[0] < f.lo[0] || p[1] < f.lo[1] || p[0] > f.hi[0] || p[1] > f.hi[1]) return false;
  bool inside = false;
  for (std::uint32_t i = 0; i < f.count; ++i) {
    Point a = corners_[f.first + i], b = corners_[f.first + (i + 1) % f.count];
    if ((a[1] > p[1]) == (b[1] > p[1])) continue;
    if (b < a) std::swap(a, b);
    if (p[0] < a[0] + (p[1] - a[1]) * (b[0] - a[0]) / (b[1] - a[1])) inside = !inside;
  }
  return inside;
}

double PolygonMiterDistance::boundary_distance(const Face& f, Point p) const {
  double d = std::numeric_limits<double>::infinity();
  for (std::uint32_t i = 0; i < f.count; ++i)
    d = std::min(d,
                 segment_distance(p, corners_[f.first + i], corners_[f.first + (i + 1) % f.count]));
  return d;
}

// Whether face f meets the box: one of its sides does, or the box lies inside it.
bool PolygonMiterDistance::overlaps(const Face& f, Point lo, Point hi) const {
  for (std::uint32_t i = 0; i < f.count; ++i)
    if (segment_meets_box(corners_[f.first + i], corners_[f.first + (i + 1) % f.count], lo, hi))
      return true;
  return contains(f, {0.5 * (lo[0] + hi[0]), 0.5 * (lo[1] + hi[1])});
}

double PolygonMiterDistance::value(const Face& f, Point p) const {
  return f.sign * std::fabs(f.n[0] * (p[0] - f.a[0]) + f.n[1] * (p[1] - f.a[1]));
}

int PolygonMiterDistance::cell(double x, int a) const {
  return std::clamp(static_cast<int>(std::floor((x - lo_[a]) / size_)), 0, n_[a] - 1);
}

}  // namespace tpmsfill::detail
