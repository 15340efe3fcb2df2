// The rim hierarchy: per rim, a binary tree over runs of consecutive edges, walked depth-first.
#include "sampling/internal/cap_winding.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "core/disjoint_sets.hpp"
#include "core/index_limits.hpp"
#include "mesh/border_loops.hpp"
#include "mesh/mesh_measures.hpp"

namespace tpmsfill::detail {
namespace {

constexpr double kFourPi = 4.0 * 3.14159265358979323846;
constexpr std::uint32_t kLeafEdges = 4;
// A run is far when its centre is farther than this many radii: chord + dipole then stay
// within about 1e-3 of the exact sum (checked in winding_test.cpp).
constexpr double kFarFactor = 4.0;

/// Winding number at p of the strip edge a → b sweeps to x = −∞: the spherical triangle
/// (â, b̂, −x̂), with triangle_winding's sign.
double strip_winding(const Vec3& p, const Vec3& a, const Vec3& b) {
  const Vec3 u0 = a - p, v0 = b - p;
  const double lu = norm(u0), lv = norm(v0);
  if (lu == 0 || lv == 0) return 0;
  const Vec3 u = (1.0 / lu) * u0, v = (1.0 / lv) * v0;
  // w = (−1, 0, 0): u·(v × w) = u.z v.y − u.y v.z, and v·w + w·u = −v.x − u.x.
  const double det = u.z * v.y - u.y * v.z;
  const double div = 1.0 + dot(u, v) - v.x - u.x;
  return 2.0 * std::atan2(det, div) / kFourPi;
}

double segment_distance(const Vec3& p, const Vec3& a, const Vec3& b) {
  const Vec3 ab = b - a;
  const double len2 = dot(ab, ab);
  const double t = len2 > 0 ? std::clamp(dot(p - a, ab) / len2, 0.0, 1.0) : 0.0;
  return norm(p - (a + t * ab));
}

}  // namespace

CapWinding::CapWinding(const TriangleSoup& caps) {
  // Patches: triangles joined through shared points. Triangles with a repeated corner (by
  // position) bound nothing and join nothing.
  DisjointSets sets(caps.points.size());
  std::vector<Triangle> kept;
  for (const Triangle& t : caps.triangles) {
    const Vec3 &a = caps.points[t[0]], &b = caps.points[t[1]], &c = caps.points[t[2]];
    if (a == b || b == c || c == a) continue;
    kept.push_back(t);
    sets.unite(t[0], t[1]);
    sets.unite(t[0], t[2]);
  }
  std::vector<std::uint32_t> patch_of(caps.points.size(), kNoIndex);
  for (const Triangle& t : kept) {
    std::uint32_t& id = patch_of[sets.find(t[0])];
    if (id == kNoIndex) {
      id = static_cast<std::uint32_t>(patches_.size());
      patches_.emplace_back();
    }
    Patch& patch = patches_[id];
    const Vec3 &a = caps.points[t[0]], &b = caps.points[t[1]], &c = caps.points[t[2]];
    for (const Vec3& v : {a, b, c}) {
      patch.box.extend(v);
      box_.extend(v);
    }
    patch.area += 0.5 * double_area(a, b, c);
  }
  // Rims: the caps' border loops, by point index.
  std::vector<std::vector<Vec3>> rims;
  for (const auto& loop : border_loops(triangle_border(caps.triangles))) {
    rims.emplace_back();
    for (std::uint32_t v : loop) rims.back().push_back(caps.points[v]);
  }
  for (const auto& rim : rims) {
    if (rim.size() < 2) continue;
    const auto begin = static_cast<std::uint32_t>(points_.size());
    points_.insert(points_.end(), rim.begin(), rim.end());
    points_.push_back(rim.front());
    for (const Vec3& v : rim) box_.extend(v);
    Run root;
    root.begin = begin;
    root.end = static_cast<std::uint32_t>(points_.size() - 1);
    rims_.push_back(static_cast<std::uint32_t>(runs_.size()));
    runs_.push_back(root);
  }
  const std::size_t roots = runs_.size();
  for (std::size_t r = 0; r < roots; ++r) build(static_cast<std::uint32_t>(r));
}

void CapWinding::build(std::uint32_t index) {
  Run run = runs_[index];
  Vec3 sum{};
  for (std::uint32_t i = run.begin; i <= run.end; ++i) {
    sum = sum + points_[i];
    run.box.extend(points_[i]);
  }
  run.centre = (1.0 / (run.end - run.begin + 1)) * sum;
  for (std::uint32_t i = run.begin; i <= run.end; ++i)
    run.radius = std::max(run.radius, norm(points_[i] - run.centre));
  const Vec3& c = run.centre;
  for (std::uint32_t i = run.begin; i < run.end; ++i)
    run.area = run.area + 0.5 * cross(points_[i] - c, points_[i + 1] - c);
  run.area = run.area + 0.5 * cross(points_[run.end] - c, points_[run.begin] - c);
  if (run.end - run.begin > kLeafEdges) {
    const std::uint32_t mid = run.begin + (run.end - run.begin) / 2;
    Run low, high;
    low.begin = run.begin;
    low.end = high.begin = mid;
    high.end = run.end;
    run.left = static_cast<std::uint32_t>(runs_.size());
    runs_.push_back(low);
    runs_.push_back(high);
    runs_[index] = run;
    build(run.left);
    build(run.left + 1);
  } else {
    runs_[index] = run;
  }
}

double CapWinding::bound(const Vec3& p) const {
  double b = 0;
  for (const Patch& patch : patches_) {
    double d2 = 0;
    for (int axis = 0; axis < 3; ++axis) {
      const double d =
          std::max({patch.box.min[axis] - p[axis], p[axis] - patch.box.max[axis], 0.0});
      d2 += d * d;
    }
    if (d2 == 0) return std::numeric_limits<double>::infinity();
    b += patch.area / (kFourPi * d2);
  }
  return b;
}

double CapWinding::row_bound(double y, double z) const {
  double b = 0;
  for (const Patch& patch : patches_) {
    const double dy = std::max({patch.box.min.y - y, y - patch.box.max.y, 0.0});
    const double dz = std::max({patch.box.min.z - z, z - patch.box.max.z, 0.0});
    const double d2 = dy * dy + dz * dz;
    if (d2 == 0) return std::numeric_limits<double>::infinity();
    b += patch.area / (kFourPi * d2);
  }
  return b;
}

int CapWinding::shadow_winding(double y, double z) const {
  int w = 0;
  for (std::uint32_t root : rims_)
    for (std::uint32_t i = runs_[root].begin; i < runs_[root].end; ++i) {
      const Vec3 &a = points_[i], &b = points_[i + 1];
      // Half-open in z, so a vertex on the row's level counts once.
      if ((a.z <= z) == (b.z <= z)) continue;
      const double side = (b.y - a.y) * (z - a.z) - (b.z - a.z) * (y - a.y);
      if (b.z > a.z && side > 0) ++w;   // upward edge with the point on its left
      if (b.z <= a.z && side < 0) --w;  // downward edge with the point on its right
    }
  return w;
}

double CapWinding::remainder(const Vec3& p, int shadow, double* rim_distance) const {
  double sum = 0;
  double nearest = std::numeric_limits<double>::infinity();
  std::vector<std::uint32_t> stack;
  for (std::uint32_t root : rims_) {
    stack.assign(1, root);
    while (!stack.empty()) {
      const Run& run = runs_[stack.back()];
      stack.pop_back();
      const Vec3 r = run.centre - p;
      const double d = norm(r);
      // Where the run's yz box holds the row, the run's loop (run + chord) may wind around
      // it, an integer the far-field form would miss: such runs are always opened.
      const bool shadowed = run.box.min.y <= p.y && p.y <= run.box.max.y && run.box.min.z <= p.z &&
                            p.z <= run.box.max.z;
      if (d > kFarFactor * run.radius && !shadowed) {
        sum += strip_winding(p, points_[run.begin], points_[run.end]) +
               dot(r, run.area) / (kFourPi * d * d * d);
        nearest = std::min(nearest, d - run.radius);
      } else if (run.left == 0) {
        for (std::uint32_t i = run.begin; i < run.end; ++i) {
          sum += strip_winding(p, points_[i], points_[i + 1]);
          nearest = std::min(nearest, segment_distance(p, points_[i], points_[i + 1]));
        }
      } else {
        stack.push_back(run.left + 1);
        stack.push_back(run.left);
      }
    }
  }
  if (rim_distance) *rim_distance = nearest;
  return -sum - shadow;
}

double CapWinding::remainder_exact(const Vec3& p) const {
  double sum = 0;
  for (std::uint32_t root : rims_)
    for (std::uint32_t i = runs_[root].begin; i < runs_[root].end; ++i)
      sum += strip_winding(p, points_[i], points_[i + 1]);
  return -sum - shadow_winding(p.y, p.z);
}

}  // namespace tpmsfill::detail
