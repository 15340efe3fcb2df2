// Stage "spatial": the triangles' coordinates in one array and CGAL AABB trees over them
// (see sampling/internal/mesh_index_impl.hpp for the layout and why there may be two trees).
#include "tpmsfill/sampling/spatial.hpp"

#include <tbb/parallel_invoke.h>
#include <tbb/parallel_sort.h>

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
  return impl_->triangle_count;
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

// Triangle t is points 3t, 3t + 1 and 3t + 2, and there are no other points.
bool laid_out_by_triangle(const TriangleSoup& soup) {
  if (soup.points.size() != 3 * soup.triangles.size()) return false;
  for (std::size_t t = 0; t < soup.triangles.size(); ++t) {
    const auto first = static_cast<std::uint32_t>(3 * t);
    if (soup.triangles[t] != Triangle{first, first + 1, first + 2}) return false;
  }
  return true;
}

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

std::unique_ptr<Tree> build_tree(const detail::Bucket* first, const detail::Bucket* beyond,
                                 const detail::BucketData& buckets) {
  auto tree = std::make_unique<Tree>();
  tree->insert(first, beyond, &buckets);
  tree->custom_build(ComputeBox{}, SplitAtMedian{});
  return tree;
}

/// v's low 21 bits spread to every third bit.
std::uint64_t spread_bits(std::uint64_t v) {
  v &= 0x1fffff;
  v = (v | v << 32) & 0x1f00000000ffffULL;
  v = (v | v << 16) & 0x1f0000ff0000ffULL;
  v = (v | v << 8) & 0x100f00f00f00f00fULL;
  v = (v | v << 4) & 0x10c30c30c30c30c3ULL;
  v = (v | v << 2) & 0x1249249249249249ULL;
  return v;
}

/// The kept triangles in Morton order, cut into buckets.
struct Buckets {
  std::vector<std::uint32_t> order;
  std::vector<detail::Bucket> buckets;
};

/// `ids` sorted along the Morton curve of their triangles' box centres in `box` (ties by id),
/// cut into runs of at most kBucket that share a Morton cell of about twice the triangles'
/// mean size: the curve's jumps between cells would otherwise make a few buckets long.
Buckets morton_buckets(const std::vector<std::uint32_t>& ids,
                       const detail::TriangleArray& triangles, const Box3& box) {
  constexpr double kCells = (1 << 21) - 1;
  const Vec3 size = box.size();
  auto cell = [&](double lo, double hi, double min, double extent) -> std::uint64_t {
    if (!(extent > 0)) return 0;
    const double t = ((lo + hi) / 2 - min) / extent * kCells;
    return static_cast<std::uint64_t>(std::clamp(t, 0.0, kCells));
  };
  std::vector<std::pair<std::uint64_t, std::uint32_t>> keyed(ids.size());
  // Sums of the triangles' largest box sides per chunk, added in order (deterministic).
  constexpr std::size_t kChunk = 1 << 14;
  std::vector<double> sides((ids.size() + kChunk - 1) / kChunk, 0.0);
  detail::parallel_for(sides.size(), 1, [&](std::size_t cb, std::size_t ce) {
    for (std::size_t c = cb; c < ce; ++c)
      for (std::size_t i = c * kChunk; i < std::min(ids.size(), (c + 1) * kChunk); ++i) {
        const std::array<Vec3, 3> v = triangles[ids[i]];
        std::uint64_t key = 0;
        double side = 0;
        for (int a = 0; a < 3; ++a) {
          const auto [lo, hi] = detail::corner_range(v, a);
          key |= spread_bits(cell(lo, hi, box.min[a], size[a])) << a;
          side = std::max(side, hi - lo);
        }
        keyed[i] = {key, ids[i]};
        sides[c] += side;
      }
  });
  double mean_side = 0;
  for (const double s : sides) mean_side += s;
  mean_side /= static_cast<double>(ids.size());
  // The Morton level whose cells are about twice the mean side (along the longest axis).
  const double longest = std::max({size.x, size.y, size.z});
  int level = 0;
  while (level < 21 && longest / kCells * std::ldexp(1.0, level + 1) <= 2 * mean_side) ++level;
  const int shift = 3 * level;

  tbb::parallel_sort(keyed.begin(), keyed.end());
  Buckets out;
  out.order.resize(keyed.size());
  out.buckets.reserve(keyed.size() / 2 + 1);
  std::uint64_t cell_of_bucket = 0;
  for (std::size_t i = 0; i < keyed.size(); ++i) {
    out.order[i] = keyed[i].second;
    const std::uint64_t c = keyed[i].first >> shift;
    if (out.buckets.empty() || out.buckets.back().count == detail::kBucket || c != cell_of_bucket) {
      out.buckets.push_back({static_cast<std::uint32_t>(i), 0});
      cell_of_bucket = c;
    }
    ++out.buckets.back().count;
  }
  return out;
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
  // The soup's corners are read in place when each triangle has its own three points in
  // order (STL's layout): no copy of 72 bytes a triangle.
  const bool borrow = options.borrow_points && laid_out_by_triangle(soup);
  if (borrow)
    triangles.borrow(soup.points.data(), static_cast<std::uint32_t>(soup.triangles.size()));
  else
    triangles.reserve(soup.triangles.size() + caps.triangles.size());
  // The ids of the kept triangles: a repeated corner (by index or by position, as STL soups
  // repeat points) bounds nothing.
  std::vector<std::uint32_t> ids;
  ids.reserve(soup.triangles.size() + caps.triangles.size());
  for (std::size_t i = 0; i < soup.triangles.size(); ++i) {
    const Triangle& t = soup.triangles[i];
    const Vec3 &a = soup.points[t[0]], &b = soup.points[t[1]], &c = soup.points[t[2]];
    if (a == b || b == c || c == a) continue;
    if (borrow) {
      ids.push_back(static_cast<std::uint32_t>(i));
    } else {
      ids.push_back(static_cast<std::uint32_t>(ids.size()));
      triangles.copy(a, b, c);
    }
  }
  if (ids.empty())
    throw InputError("cannot build the search tree: no triangle has three distinct corners");
  triangles.end_model();
  const std::size_t model_triangles = ids.size();
  for (const Triangle& t : caps.triangles) {
    const Vec3 &a = caps.points[t[0]], &b = caps.points[t[1]], &c = caps.points[t[2]];
    if (a == b || b == c || c == a) continue;
    ids.push_back(triangles.first_cap() + static_cast<std::uint32_t>(ids.size() - model_triangles));
    triangles.copy(a, b, c);
  }
  triangles.finish();
  impl->triangle_count = ids.size();
  impl->cap_count = ids.size() - model_triangles;
  if (impl->cap_count > 0) impl->caps = detail::CapWinding(caps);

  // Bounds per fixed chunk in parallel, combined in order (min/max: exact either way).
  constexpr std::size_t kBoxChunk = 1 << 16;
  std::vector<Box3> boxes((ids.size() + kBoxChunk - 1) / kBoxChunk);
  detail::parallel_for(boxes.size(), 1, [&](std::size_t b, std::size_t e) {
    for (std::size_t c = b; c < e; ++c) {
      Vec3 lo = triangles[ids[c * kBoxChunk]][0], hi = lo;
      const std::size_t end = std::min(ids.size(), (c + 1) * kBoxChunk);
      for (std::size_t t = c * kBoxChunk; t < end; ++t)
        for (const Vec3& p : triangles[ids[t]]) {
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

  // Buckets of up to kBucket triangles along the Morton curve, split in two halves (two trees
  // built in parallel) when there are many.
  Buckets buckets = morton_buckets(ids, triangles, box);
  std::vector<std::uint32_t>().swap(ids);
  impl->order = std::move(buckets.order);
  impl->buckets = {&impl->triangles, impl->order.data()};
  const detail::Bucket* begin = buckets.buckets.data();
  const detail::Bucket* end = begin + buckets.buckets.size();
  if (impl->order.size() < kSplitThreshold) {
    impl->trees.push_back(build_tree(begin, end, impl->buckets));
  } else {
    const detail::Bucket* mid = begin + (end - begin) / 2;
    std::unique_ptr<Tree> low, high;
    tbb::parallel_invoke([&] { low = build_tree(begin, mid, impl->buckets); },
                         [&] { high = build_tree(mid, end, impl->buckets); });
    impl->trees.push_back(std::move(low));
    impl->trees.push_back(std::move(high));
  }
  return detail::MeshIndexAccess::make(std::move(impl));
}

}  // namespace tpmsfill
