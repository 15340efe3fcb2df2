// Stage "spatial": the triangles' coordinates in one array and CGAL AABB trees over them
// (see sampling/internal/mesh_index_impl.hpp for the layout and why there may be two trees).
#include "tpmsfill/sampling/spatial.hpp"

#include <tbb/parallel_invoke.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>
#include <utility>

#include "core/index_limits.hpp"
#include "core/parallel.hpp"
#include "mesh/soup_indices.hpp"
#include "sampling/internal/mesh_index_impl.hpp"
#include "tpmsfill/error.hpp"

namespace tpmsfill {

MeshIndex::MeshIndex(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}
MeshIndex::MeshIndex(MeshIndex&&) noexcept = default;
MeshIndex& MeshIndex::operator=(MeshIndex&&) noexcept = default;
MeshIndex::~MeshIndex() = default;

std::size_t MeshIndex::triangle_count() const {
  return impl_->triangles.size();
}
std::size_t MeshIndex::cap_count() const {
  return impl_->cap_count;
}
Box3 MeshIndex::bounds() const {
  return impl_->bounds;
}

namespace {

using detail::Tree;
using detail::TrianglePrimitive;

/// Above this many triangles the soup is split into two trees built in parallel.
constexpr std::size_t kSplitThreshold = 1u << 16;

/// Bounding box of primitives [first, beyond): the union of their float boxes, as doubles.
struct ComputeBox {
  template <class It>
  CGAL::Bbox_3 operator()(It first, It beyond) const {
    float lo[3] = {first->lo(0), first->lo(1), first->lo(2)};
    float hi[3] = {first->hi(0), first->hi(1), first->hi(2)};
    for (++first; first != beyond; ++first)
      for (int a = 0; a < 3; ++a) {
        lo[a] = std::min(lo[a], first->lo(a));
        hi[a] = std::max(hi[a], first->hi(a));
      }
    return {lo[0], lo[1], lo[2], hi[0], hi[1], hi[2]};
  }
};

int longest_axis(const CGAL::Bbox_3& b) {
  const double dx = b.xmax() - b.xmin(), dy = b.ymax() - b.ymin(), dz = b.zmax() - b.zmin();
  if (dx >= dy && dx >= dz) return 0;
  return dy >= dz ? 1 : 2;
}

/// Median split along the box's longest axis by box centre (as CGAL's Split_primitives, but
/// on the primitive's own floats instead of re-reading the triangle).
struct SplitAtMedian {
  template <class It>
  void operator()(It first, It beyond, const CGAL::Bbox_3& box) const {
    const int axis = longest_axis(box);
    std::nth_element(first, first + (beyond - first) / 2, beyond,
                     [axis](const TrianglePrimitive& p, const TrianglePrimitive& q) {
                       return p.centre2(axis) < q.centre2(axis);
                     });
  }
};

std::unique_ptr<Tree> build_tree(std::uint32_t* first, std::uint32_t* beyond,
                                 const detail::TriangleArray& triangles) {
  // Ids in memory order: the primitives' boxes are then computed reading the coordinates
  // sequentially (the median split leaves each half shuffled).
  std::sort(first, beyond);
  auto tree = std::make_unique<Tree>();
  tree->insert(first, beyond, &triangles);
  tree->custom_build(ComputeBox{}, SplitAtMedian{});
  return tree;
}

}  // namespace

MeshIndex build_index(const TriangleSoup& soup, const IndexOptions& options) {
  static const TriangleSoup kNoCaps;
  const TriangleSoup& caps = options.hole_caps ? *options.hole_caps : kNoCaps;
  detail::require_indices_in_range(soup, "cannot build the search tree: ");
  detail::require_indices_in_range(caps, "cannot build the search tree: hole caps: ");
  if (!detail::fits_32bit_ids(soup.triangles.size() + caps.triangles.size()))
    throw InputError("cannot build the search tree: more than 4294967295 triangles");

  auto impl = std::make_unique<detail::MeshIndexAccess::Impl>();
  auto& triangles = impl->triangles;
  triangles.reserve(soup.triangles.size() + caps.triangles.size());
  auto add = [&](const TriangleSoup& from) {
    for (const Triangle& t : from.triangles) {
      const Vec3 &a = from.points[t[0]], &b = from.points[t[1]], &c = from.points[t[2]];
      // A repeated corner (by index or by position, as STL soups repeat points) bounds
      // nothing.
      if (a == b || b == c || c == a) continue;
      triangles.push_back({{a, b, c}});
    }
  };
  add(soup);
  if (triangles.empty())
    throw InputError("cannot build the search tree: no triangle has three distinct corners");
  const std::size_t model_triangles = triangles.size();
  add(caps);
  impl->cap_count = triangles.size() - model_triangles;
  if (impl->cap_count > 0) impl->caps = detail::CapWinding(caps);

  triangles.shrink_to_fit();

  // Bounds per fixed chunk in parallel, combined in order (min/max: exact either way).
  constexpr std::size_t kBoxChunk = 1 << 16;
  std::vector<Box3> boxes((triangles.size() + kBoxChunk - 1) / kBoxChunk);
  detail::parallel_for(boxes.size(), 1, [&](std::size_t b, std::size_t e) {
    for (std::size_t c = b; c < e; ++c) {
      Vec3 lo = triangles[c * kBoxChunk].v[0], hi = lo;
      const std::size_t end = std::min(triangles.size(), (c + 1) * kBoxChunk);
      for (std::size_t t = c * kBoxChunk; t < end; ++t)
        for (const Vec3& p : triangles[t].v) {
          lo = {std::min(lo.x, p.x), std::min(lo.y, p.y), std::min(lo.z, p.z)};
          hi = {std::max(hi.x, p.x), std::max(hi.y, p.y), std::max(hi.z, p.z)};
        }
      boxes[c].min = lo;
      boxes[c].max = hi;
    }
  });
  Box3 box;
  for (const Box3& b : boxes) {
    box.extend(b.min);
    box.extend(b.max);
  }
  impl->bounds = box;
  impl->magnitude = std::max({std::fabs(box.min.x), std::fabs(box.min.y), std::fabs(box.min.z),
                              std::fabs(box.max.x), std::fabs(box.max.y), std::fabs(box.max.z)});

  // Triangle ids, split in two halves at the median box centre along the longest axis.
  std::vector<std::uint32_t> ids(triangles.size());
  for (std::size_t i = 0; i < ids.size(); ++i) ids[i] = static_cast<std::uint32_t>(i);
  std::uint32_t* begin = ids.data();
  std::uint32_t* end = ids.data() + ids.size();
  if (ids.size() < kSplitThreshold) {
    impl->trees.push_back(build_tree(begin, end, triangles));
  } else {
    const Vec3 size = box.size();
    const int axis = size.x >= size.y && size.x >= size.z ? 0 : (size.y >= size.z ? 1 : 2);
    auto centre = [&](std::uint32_t id) {
      const auto& v = triangles[id].v;
      return v[0][axis] + v[1][axis] + v[2][axis];
    };
    auto middle = ids.begin() + static_cast<std::ptrdiff_t>(ids.size() / 2);
    std::nth_element(ids.begin(), middle, ids.end(), [&](std::uint32_t p, std::uint32_t q) {
      const double cp = centre(p), cq = centre(q);
      return cp < cq || (cp == cq && p < q);
    });
    std::uint32_t* mid = ids.data() + ids.size() / 2;
    std::unique_ptr<Tree> low, high;
    tbb::parallel_invoke([&] { low = build_tree(begin, mid, triangles); },
                         [&] { high = build_tree(mid, end, triangles); });
    impl->trees.push_back(std::move(low));
    impl->trees.push_back(std::move(high));
  }
  return detail::MeshIndexAccess::make(std::move(impl));
}

}  // namespace tpmsfill
