/// @file mesh_index_impl.hpp
/// @brief What MeshIndex holds: the triangles' corner coordinates in one compact array and
/// CGAL AABB trees (Epick) over them. Private to src/: classify.cpp and distance.cpp walk the
/// trees with their own traversal traits (AABB_tree::traversal / traversal_with_priority).
///
/// Memory per triangle: 72 bytes of coordinates, 28 bytes of primitive (id + a float box
/// rounded outward, so the build never touches the coordinates again) and one AABB_node
/// (64 bytes): about 165 bytes, 0.8 GB for 4.7×10⁶ triangles.
///
/// Large soups are split at the median along the longest axis into two trees built in
/// parallel (CGAL builds one tree serially); every query walks both. The answers do not
/// depend on how many trees there are or on their shape: classify decides each triangle
/// exactly, distance returns the minimum over all triangles of one fixed double formula.
#pragma once

#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_tree.h>

#include <array>
#include <cmath>
#include <cstdint>
#include <memory>
#include <vector>

#include "mesh/cgal_types.hpp"
#include "sampling/internal/cap_winding.hpp"
#include "tpmsfill/sampling/spatial.hpp"
#include "tpmsfill/types.hpp"

namespace tpmsfill::detail {

/// A triangle's three corners, in the soup's winding order.
struct TriangleCorners {
  std::array<Vec3, 3> v;
};

/// The coordinates every primitive refers to (the AABB tree's shared data).
using TriangleArray = std::vector<TriangleCorners>;

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

/// AABB primitive (model of AABBPrimitiveWithSharedData): a triangle id into the shared
/// TriangleArray plus its bounding box in floats rounded outward. The box is only used by
/// the build (compute_bbox/split below); queries read the exact coordinates.
class TrianglePrimitive {
 public:
  using Id = std::uint32_t;
  using Point = Kernel::Point_3;
  using Datum = Kernel::Triangle_3;
  using Shared_data = const TriangleArray*;

  TrianglePrimitive() = default;
  /// From an iterator over triangle ids (AABB_tree::insert(first, beyond, &triangles)).
  template <class IdIterator>
  TrianglePrimitive(IdIterator it, const TriangleArray* triangles) : id_(*it) {
    const auto& v = (*triangles)[id_].v;
    for (int a = 0; a < 3; ++a) {
      const double lo = std::fmin(std::fmin(v[0][a], v[1][a]), v[2][a]);
      const double hi = std::fmax(std::fmax(v[0][a], v[1][a]), v[2][a]);
      lo_[a] = float_down(lo);
      hi_[a] = float_up(hi);
    }
  }

  Id id() const { return id_; }
  Datum datum(Shared_data triangles) const {
    const auto& v = (*triangles)[id_].v;
    return {to_cgal(v[0]), to_cgal(v[1]), to_cgal(v[2])};
  }
  Point reference_point(Shared_data triangles) const { return to_cgal((*triangles)[id_].v[0]); }
  static Shared_data construct_shared_data(const TriangleArray* triangles) { return triangles; }

  float lo(int axis) const { return lo_[axis]; }
  float hi(int axis) const { return hi_[axis]; }
  /// Twice the box centre along `axis` (what the build sorts by).
  float centre2(int axis) const { return lo_[axis] + hi_[axis]; }

 private:
  float lo_[3] = {0, 0, 0};
  float hi_[3] = {0, 0, 0};
  Id id_ = 0;
};

using TreeTraits = CGAL::AABB_traits<Kernel, TrianglePrimitive>;
using Tree = CGAL::AABB_tree<TreeTraits>;
using TreeNode = CGAL::AABB_node<TreeTraits>;

}  // namespace tpmsfill::detail

namespace tpmsfill {

struct MeshIndex::Impl {
  detail::TriangleArray triangles;  ///< kept triangles, corners as given, caps last
  std::vector<std::unique_ptr<detail::Tree>> trees;  ///< 1 or 2 trees, disjoint triangle sets
  Box3 bounds;                                       ///< of `triangles`
  /// Largest |coordinate| (mm), for the distance stage's rounding slack.
  double magnitude = 0;
  /// The hole caps' own winding number (empty without caps); their triangles are also the
  /// last cap_count entries of `triangles` (ids ≥ triangles.size() − cap_count).
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
