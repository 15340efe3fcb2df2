/// @file mesh_index_impl.hpp
/// @brief What MeshIndex holds: the triangles' corner coordinates in one compact array and
/// CGAL AABB trees (Epick) over them. Private to src/: classify.cpp and distance.cpp walk the
/// trees with their own traversal traits (AABB_tree::traversal / traversal_with_priority).
///
/// Memory per triangle: 72 bytes of coordinates (none when they are read in place from the
/// soup, IndexOptions::borrow_points), 4 bytes of `order`, and per bucket of about 3 triangles
/// (kBucket) one primitive (32 bytes: a float box rounded outward, so the build never touches
/// the coordinates again) and one AABB_node (64 bytes): about 110 bytes, or 38 borrowed (the
/// tube of docs/benchmarks.md §32: 4.7×10⁶ triangles in 1.66×10⁶ buckets). One triangle a
/// primitive took 164.
///
/// Large soups are split in two halves of the Morton order into two trees built in parallel
/// (CGAL builds one tree serially); every query walks both. The answers do not
/// depend on how many trees there are or on their shape: classify decides each triangle
/// exactly, distance returns the minimum over all triangles of one fixed double formula.
#pragma once

#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_tree.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <memory>
#include <utility>
#include <vector>

#include "mesh/cgal_types.hpp"
#include "sampling/internal/cap_winding.hpp"
#include "tpmsfill/sampling/spatial.hpp"
#include "tpmsfill/types.hpp"

namespace tpmsfill::detail {

/// The corners of the triangles in the tree, by primitive id: three consecutive points a
/// triangle. The model's are read in place from the soup when IndexOptions::borrow_points
/// allows it (ids are then the soup's triangle indices), else copied here (ids count the kept
/// triangles); the hole caps' are always copied and come after the model's ids.
class TriangleArray {
 public:
  std::array<Vec3, 3> operator[](std::uint32_t id) const {
    const Vec3* p = id < first_cap_ ? model_ + 3 * std::size_t{id}
                                    : owned_.data() + 3 * (cap_offset_ + (id - first_cap_));
    return {p[0], p[1], p[2]};
  }
  /// The first cap's id (one past the model's ids).
  std::uint32_t first_cap() const { return first_cap_; }

  /// The model's `count` triangles are read in place at `corners` (3 points each).
  void borrow(const Vec3* corners, std::uint32_t count) {
    model_ = corners;
    first_cap_ = count;
    borrowed_ = true;
  }
  void reserve(std::size_t triangles) { owned_.reserve(3 * triangles); }
  /// Appends a triangle: the model's (unless borrowed), then after end_model() the caps'.
  void copy(const Vec3& a, const Vec3& b, const Vec3& c) { owned_.insert(owned_.end(), {a, b, c}); }
  void end_model() {
    if (borrowed_) return;
    first_cap_ = static_cast<std::uint32_t>(owned_.size() / 3);
    cap_offset_ = first_cap_;
  }
  /// After the last copy().
  void finish() {
    owned_.shrink_to_fit();
    if (!borrowed_) model_ = owned_.data();
  }

 private:
  std::vector<Vec3> owned_;      ///< the copied model triangles, if any, then the caps
  const Vec3* model_ = nullptr;  ///< the model's first corner (borrowed or owned_)
  std::uint32_t first_cap_ = 0;
  std::size_t cap_offset_ = 0;  ///< triangles in owned_ before the first cap
  bool borrowed_ = false;
};

/// The least and the greatest of a triangle's corners along `axis`: its box's side.
inline std::pair<double, double> corner_range(const std::array<Vec3, 3>& v, int axis) {
  return {std::fmin(std::fmin(v[0][axis], v[1][axis]), v[2][axis]),
          std::fmax(std::fmax(v[0][axis], v[1][axis]), v[2][axis])};
}

/// Largest float <= d (or >= d when up): boxes rounded outward stay conservative.
inline float float_down(double d) {
  float f = static_cast<float>(d);
  if (static_cast<double>(f) > d) f = std::nextafter(f, -INFINITY);
  return f;
}
inline float float_up(double d) {
  float f = static_cast<float>(d);
  if (static_cast<double>(f) < d) f = std::nextafter(f, INFINITY);
  return f;
}

/// The tree's primitives are buckets: runs of up to kBucket consecutive entries of `order`,
/// the triangles' ids sorted along a Morton curve, cut where the curve jumps (a bucket's
/// triangles share a Morton cell about their own size). The tree then holds one node (64
/// bytes) and one primitive (32 bytes) per bucket instead of per triangle
/// (docs/benchmarks.md §32).
inline constexpr std::uint32_t kBucket = 4;

/// A bucket: its first entry of `order` and its length (1 to kBucket).
struct Bucket {
  std::uint32_t first = 0, count = 0;
};

/// What the primitives refer to (the AABB tree's shared data).
struct BucketData {
  const TriangleArray* triangles = nullptr;
  const std::uint32_t* order = nullptr;
};

/// AABB primitive (model of AABBPrimitiveWithSharedData): a bucket (its first entry of
/// `order` and its length) plus the bounding box of its triangles in floats rounded outward.
/// The box is only used by the build (compute_bbox/split below); queries read the exact
/// coordinates.
class TrianglePrimitive {
 public:
  using Id = std::uint32_t;
  using Point = Kernel::Point_3;
  using Datum = Kernel::Triangle_3;
  using Shared_data = const BucketData*;

  TrianglePrimitive() = default;
  /// From an iterator over buckets (AABB_tree::insert(first, beyond, &data)).
  template <class BucketIterator>
  TrianglePrimitive(BucketIterator it, const BucketData* data)
      : first_(it->first), count_(it->count) {
    double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
    for (std::uint32_t k = 0; k < count_; ++k) {
      const std::array<Vec3, 3> v = (*data->triangles)[data->order[first_ + k]];
      for (int a = 0; a < 3; ++a) {
        const auto [l, h] = corner_range(v, a);
        lo[a] = std::fmin(lo[a], l);
        hi[a] = std::fmax(hi[a], h);
      }
    }
    for (int a = 0; a < 3; ++a) {
      lo_[a] = float_down(lo[a]);
      hi_[a] = float_up(hi[a]);
    }
  }

  /// The bucket's first entry of `order`.
  Id id() const { return first_; }
  /// Calls f(triangle id) for each triangle of the bucket.
  template <class F>
  void for_each_triangle(const std::uint32_t* order, F&& f) const {
    for (std::uint32_t k = 0; k < count_; ++k) f(order[first_ + k]);
  }
  Datum datum(Shared_data data) const {
    const std::array<Vec3, 3> v = (*data->triangles)[data->order[first_]];
    return {to_cgal(v[0]), to_cgal(v[1]), to_cgal(v[2])};
  }
  Point reference_point(Shared_data data) const {
    return to_cgal((*data->triangles)[data->order[first_]][0]);
  }
  static Shared_data construct_shared_data(const BucketData* data) { return data; }

  float lo(int axis) const { return lo_[axis]; }
  float hi(int axis) const { return hi_[axis]; }
  /// Twice the box centre along `axis` (what the build sorts by).
  float centre2(int axis) const { return lo_[axis] + hi_[axis]; }

 private:
  float lo_[3] = {0, 0, 0};
  float hi_[3] = {0, 0, 0};
  std::uint32_t first_ = 0;
  std::uint32_t count_ = 0;
};

using TreeTraits = CGAL::AABB_traits<Kernel, TrianglePrimitive>;
using Tree = CGAL::AABB_tree<TreeTraits>;
using TreeNode = CGAL::AABB_node<TreeTraits>;

}  // namespace tpmsfill::detail

namespace tpmsfill {

struct MeshIndex::Impl {
  detail::TriangleArray triangles;                   ///< the corners by triangle id, caps last
  std::vector<std::uint32_t> order;                  ///< triangle ids, bucket by bucket (kBucket)
  detail::BucketData buckets;                        ///< the trees' view of `triangles` and `order`
  std::size_t triangle_count = 0;                    ///< kept triangles, caps included
  std::vector<std::unique_ptr<detail::Tree>> trees;  ///< 1 or 2 trees, disjoint triangle sets
  Box3 bounds;                                       ///< of `triangles`
  /// Largest |coordinate| (mm), for the distance stage's rounding slack.
  double magnitude = 0;
  /// The hole caps' own winding number (empty without caps); their triangles are also the
  /// last cap_count entries of `triangles` (ids ≥ triangles.first_cap()).
  detail::CapWinding caps;
  std::size_t cap_count = 0;
};

namespace detail {

/// The one door to MeshIndex's inside: build_index makes one, classify and distance read it.
struct MeshIndexAccess {
  using Impl = MeshIndex::Impl;
  static const Impl& impl(const MeshIndex& index) { return *index.impl_; }
  static MeshIndex make(std::unique_ptr<Impl> impl) { return MeshIndex(std::move(impl)); }
};

}  // namespace detail

}  // namespace tpmsfill
