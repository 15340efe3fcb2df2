// Stage "validate": is an indexed mesh (marching-cubes output) a closed, outward 2-manifold
// without degenerate faces or self-intersections? Judged as indexed, fast:
// - topology from a vertex -> corner table (counting sort): each vertex looks at its own
//   corners, so edges (classified at their smaller vertex) and fans are per-vertex work;
// - duplicate points by sorting position hashes; components by union-find;
// - sums (area, volume) per fixed chunk, added in chunk order (detail::deterministic_sum);
// - self-intersections with exact predicates (Epick) either between triangles of the same or
//   26-adjacent grid cells (cell_grid) or through CGAL::box_self_intersection_d.
// Every parallel loop runs over fixed chunks whose results are merged in chunk order, so the
// report is the same for any thread count.
#include "tpmsfill/validate.hpp"

#include <CGAL/Bbox_3.h>
#include <CGAL/Box_intersection_d/Box_with_info_d.h>
#include <CGAL/box_intersection_d.h>
#include <CGAL/intersections.h>
#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_sort.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdio>
#include <limits>
#include <numeric>
#include <string>
#include <utility>

#include "detail/cgal_types.hpp"
#include "detail/parallel.hpp"
#include "detail/problem_text.hpp"
#include "detail/soup_indices.hpp"
#include "detail/soup_topology.hpp"
#include "tpmsfill/error.hpp"

namespace tpmsfill {
namespace {

using detail::plural;
using detail::Point3;
using detail::short_number;
using Pair = std::array<std::uint32_t, 2>;

constexpr std::size_t kChunk = 4096;  // items per fixed chunk of every parallel loop

std::size_t chunk_count(std::size_t n, std::size_t chunk = kChunk) {
  return (n + chunk - 1) / chunk;
}

void check_sizes(const TriangleSoup& mesh) {
  detail::require_indices_in_range(mesh);
  // Corner slots (3 per triangle) are 32-bit.
  if (mesh.triangles.size() > 0xffffffffu / 3 || mesh.points.size() >= 0xffffffffu)
    throw InputError("too many triangles or points to validate (at most 1431655765 triangles)");
}

bool repeated_corner(const Triangle& t) {
  return t[0] == t[1] || t[1] == t[2] || t[0] == t[2];
}

// --- exact pair test (the semantics of CGAL PMP::self_intersections) -----------------------

/// A triangle's plane for side tests: the sign of det(b - a, c - a, x - a), which is
/// CGAL::orientation(a, b, c, x). The cross product is computed once per triangle; a point's
/// side is decided in double arithmetic when the result exceeds a forward error bound, and
/// by CGAL's exact predicate otherwise, so every answer is exact.
///
/// Error bound: with every input difference rounded once, each product of two rounded
/// differences and each of the five additions rounded once, |computed - exact| <= 8 eps P
/// (1 + O(eps)), eps = 2^-53, P = sum over axes of (|u_y w_z| + |u_z w_y|) |x_x - a_x| (the
/// permanent). We demand |computed| > 2e-15 P (18 eps) and P > 1e-250 (no underflow).
struct Plane {
  const Point3 *a, *b, *c;
  double n[3];  // (b - a) x (c - a)
  double m[3];  // per axis the two products' magnitudes, for the permanent

  Plane(const Point3& pa, const Point3& pb, const Point3& pc) : a(&pa), b(&pb), c(&pc) {
    const double ux = pb.x() - pa.x(), uy = pb.y() - pa.y(), uz = pb.z() - pa.z();
    const double wx = pc.x() - pa.x(), wy = pc.y() - pa.y(), wz = pc.z() - pa.z();
    n[0] = uy * wz - uz * wy;
    n[1] = uz * wx - ux * wz;
    n[2] = ux * wy - uy * wx;
    m[0] = std::fabs(uy * wz) + std::fabs(uz * wy);
    m[1] = std::fabs(uz * wx) + std::fabs(ux * wz);
    m[2] = std::fabs(ux * wy) + std::fabs(uy * wx);
  }

  /// -1, 0 or +1: the exact sign of det(b - a, c - a, x - a).
  int side(const Point3& x) const {
    const double zx = x.x() - a->x(), zy = x.y() - a->y(), zz = x.z() - a->z();
    const double d = n[0] * zx + n[1] * zy + n[2] * zz;
    const double permanent = m[0] * std::fabs(zx) + m[1] * std::fabs(zy) + m[2] * std::fabs(zz);
    if (std::fabs(d) > 2e-15 * permanent && permanent > 1e-250) return d > 0 ? 1 : -1;
    return static_cast<int>(CGAL::orientation(*a, *b, *c, x));
  }
};

/// Does segment xy meet the triangle of `plane`? Both ends strictly on one side means no.
bool segment_meets_triangle(const Plane& plane, const Point3& x, const Point3& y) {
  const int sx = plane.side(x);
  if (sx != 0 && sx == plane.side(y)) return false;
  return CGAL::do_intersect(detail::Kernel::Triangle_3(*plane.a, *plane.b, *plane.c),
                            detail::Kernel::Segment_3(x, y));
}

/// All three of p, q, r strictly on one side of the plane.
bool strictly_one_side(const Plane& plane, const Point3& p, const Point3& q, const Point3& r) {
  const int s = plane.side(p);
  return s != 0 && s == plane.side(q) && s == plane.side(r);
}

/// Whether two non-degenerate triangles (corner indices into `p`) intersect beyond what they
/// share by index, as CGAL's do_faces_intersect() (self_intersections.h) decides it:
/// - a shared edge: only if the two opposite corners are coplanar with it and on the same
///   side (the triangles overlap); three shared corners (the same triangle twice) always;
/// - one shared corner: only if the opposite edge of either meets the other triangle;
/// - nothing shared: whether the closed triangles meet at all.
bool triangles_intersect(const Triangle& h, const Triangle& g, const std::vector<Point3>& p) {
  int hs[3], gs[3];
  int shared = 0;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      if (h[i] == g[j]) {
        hs[shared] = i;
        gs[shared] = j;
        ++shared;
      }
  if (shared == 3) return true;
  const Plane ph(p[h[0]], p[h[1]], p[h[2]]);
  if (shared == 2) {
    const Point3& s = p[g[3 - gs[0] - gs[1]]];
    if (ph.side(s) != 0) return false;  // not coplanar
    const Point3& a = p[h[hs[0]]];
    const Point3& b = p[h[hs[1]]];
    const Point3& r = p[h[3 - hs[0] - hs[1]]];
    return CGAL::coplanar_orientation(a, b, r, s) == CGAL::POSITIVE;
  }
  const Plane pg(p[g[0]], p[g[1]], p[g[2]]);
  if (shared == 1) {
    // With the far edge of either strictly on one side of the other's plane, that triangle
    // meets the other's plane only at the shared corner: no intersection (both of CGAL's
    // segment tests below would say no).
    const int i = hs[0], j = gs[0];
    const Point3 &hx = p[h[(i + 1) % 3]], &hy = p[h[(i + 2) % 3]];
    const Point3 &gx = p[g[(j + 1) % 3]], &gy = p[g[(j + 2) % 3]];
    const int sgx = ph.side(gx), shx = pg.side(hx);
    if ((sgx != 0 && sgx == ph.side(gy)) || (shx != 0 && shx == pg.side(hy))) return false;
    return segment_meets_triangle(ph, gx, gy) || segment_meets_triangle(pg, hx, hy);
  }
  if (strictly_one_side(ph, p[g[0]], p[g[1]], p[g[2]]) ||
      strictly_one_side(pg, p[h[0]], p[h[1]], p[h[2]]))
    return false;
  return CGAL::do_intersect(detail::Kernel::Triangle_3(p[h[0]], p[h[1]], p[h[2]]),
                            detail::Kernel::Triangle_3(p[g[0]], p[g[1]], p[g[2]]));
}

struct Box {
  double lo[3], hi[3];
};

Box triangle_box(const TriangleSoup& mesh, const Triangle& t) {
  Box b;
  for (int a = 0; a < 3; ++a) {
    const double x = mesh.points[t[0]][a], y = mesh.points[t[1]][a], z = mesh.points[t[2]][a];
    b.lo[a] = std::min({x, y, z});
    b.hi[a] = std::max({x, y, z});
  }
  return b;
}

bool boxes_meet(const Box& a, const Box& b) {
  // Non-short-circuit: cheaper than six unpredictable branches.
  return (a.lo[0] <= b.hi[0]) & (b.lo[0] <= a.hi[0]) & (a.lo[1] <= b.hi[1]) & (b.lo[1] <= a.hi[1]) &
         (a.lo[2] <= b.hi[2]) & (b.lo[2] <= a.hi[2]);
}

// --- self-intersections, general path -----------------------------------------------------

std::vector<Pair> intersecting_pairs_general(const TriangleSoup& mesh,
                                             const std::vector<Point3>& points,
                                             const std::vector<std::uint8_t>& degenerate) {
  using CgalBox = CGAL::Box_intersection_d::Box_with_info_d<double, 3, std::uint32_t>;
  std::vector<CgalBox> boxes;
  boxes.reserve(mesh.triangles.size());
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
    if (degenerate[t]) continue;
    const Triangle& tri = mesh.triangles[t];
    boxes.emplace_back(points[tri[0]].bbox() + points[tri[1]].bbox() + points[tri[2]].bbox(),
                       static_cast<std::uint32_t>(t));
  }
  tbb::enumerable_thread_specific<std::vector<Pair>> found;
  auto callback = [&](const CgalBox& a, const CgalBox& b) {
    const std::uint32_t i = a.info(), j = b.info();
    if (triangles_intersect(mesh.triangles[i], mesh.triangles[j], points))
      found.local().push_back({std::min(i, j), std::max(i, j)});
  };
  CGAL::box_self_intersection_d<CGAL::Parallel_if_available_tag>(boxes.begin(), boxes.end(),
                                                                 callback);
  std::vector<Pair> pairs;
  for (const auto& local : found) pairs.insert(pairs.end(), local.begin(), local.end());
  tbb::parallel_sort(pairs.begin(), pairs.end());
  pairs.erase(std::unique(pairs.begin(), pairs.end()), pairs.end());
  return pairs;
}

// --- self-intersections, cell-grid path ---------------------------------------------------

/// Stable LSD radix sort of (key, value) by key, 11 bits a pass, as many passes as the
/// largest key needs.
void radix_sort(std::vector<std::uint64_t>& keys, std::vector<std::uint32_t>& values,
                std::uint64_t max_key) {
  constexpr int kBits = 11;
  constexpr std::size_t kBuckets = std::size_t{1} << kBits;
  const std::size_t n = keys.size();
  std::vector<std::uint64_t> keys2(n);
  std::vector<std::uint32_t> values2(n);
  std::vector<std::size_t> count(kBuckets);
  for (int shift = 0; shift < 64 && (max_key >> shift) != 0; shift += kBits) {
    std::fill(count.begin(), count.end(), 0);
    for (std::size_t i = 0; i < n; ++i) ++count[(keys[i] >> shift) & (kBuckets - 1)];
    std::size_t sum = 0;
    for (std::size_t& c : count) {
      const std::size_t here = c;
      c = sum;
      sum += here;
    }
    for (std::size_t i = 0; i < n; ++i) {
      const std::size_t to = count[(keys[i] >> shift) & (kBuckets - 1)]++;
      keys2[to] = keys[i];
      values2[to] = values[i];
    }
    keys.swap(keys2);
    values.swap(values2);
  }
}

/// Intersecting pairs when every triangle lies in one closed cell of `grid`; nullopt when
/// some triangle does not (then the caller takes the general path).
///
/// Each triangle is put in the cell i (per axis) that holds its centroid and must lie in
/// [L(i) - tol, L(i + 1) + tol], L(i) = origin + spacing * i as computed in double, with one
/// tolerance tol far below a cell and far above the rounding of L. Then two triangles in
/// cells more than one apart on some axis are disjoint (they are separated by about a cell
/// less 2 tol), so only pairs in the same or 26-adjacent cells can meet; each unordered cell
/// pair is visited once (the 13 neighbours with a larger cell key), each triangle pair at
/// most once.
///
/// Across a face between cells i and i + 1 (per axis), a triangle of cell i can meet one of
/// cell i + 1 only where both reach the face: the first has max >= L(i + 1) - tol (the second's
/// lower bound), the second min <= L(i + 1) + tol (the first's upper bound). Each triangle
/// records which of its cell's six faces it reaches, and a neighbour pair only pairs
/// triangles that reach the faces between them: exact, and most pairs are never looked at.
std::optional<std::vector<Pair>> intersecting_pairs_in_cells(
    const TriangleSoup& mesh, const std::vector<Point3>& points,
    const std::vector<std::uint8_t>& degenerate, const Grid& grid,
    detail::ProgressCounter& progress) {
  const double s = grid.spacing;
  if (!(s > 0) || !std::isfinite(s)) return std::nullopt;
  const std::size_t nt = mesh.triangles.size();

  // One tolerance for all cells, so that neighbouring cells agree on their common bound. It
  // covers coordinates rounded to float (fill validates what binary STL stores): a float
  // ulp relative to the largest coordinate. Any tolerance below a quarter cell keeps the
  // search complete; a larger one only adds candidate pairs.
  double magnitude =
      std::max({std::fabs(grid.origin.x), std::fabs(grid.origin.y), std::fabs(grid.origin.z)});
  for (const Triangle& t : mesh.triangles)
    for (std::uint32_t v : t)
      magnitude = std::max({magnitude, std::fabs(mesh.points[v].x), std::fabs(mesh.points[v].y),
                            std::fabs(mesh.points[v].z)});
  const double tol =
      1e-7 * s + static_cast<double>(std::numeric_limits<float>::epsilon()) * (magnitude + s);
  if (!(tol < 0.25 * s) || !std::isfinite(magnitude)) return std::nullopt;

  // Cell of each kept triangle, the containment check, and the faces it reaches:
  // bit 2a: the lower face on axis a, bit 2a + 1: the upper face.
  std::vector<std::array<std::int64_t, 3>> cell(nt);
  std::vector<std::uint8_t> reach(nt, 0);
  const std::size_t chunks = chunk_count(nt);
  std::vector<std::uint8_t> chunk_ok(chunks, 1);
  std::vector<std::array<std::int64_t, 6>> chunk_range(chunks);
  constexpr std::int64_t kLimit = std::int64_t{1} << 40;
  detail::parallel_for(chunks, 1, [&](std::size_t cb, std::size_t ce) {
    for (std::size_t c = cb; c < ce; ++c) {
      std::array<std::int64_t, 6> range{kLimit, kLimit, kLimit, -kLimit, -kLimit, -kLimit};
      for (std::size_t t = c * kChunk; t < std::min(nt, (c + 1) * kChunk) && chunk_ok[c]; ++t) {
        if (degenerate[t]) continue;
        const Triangle& tri = mesh.triangles[t];
        std::uint8_t bits = 0;
        for (int a = 0; a < 3; ++a) {
          const double x = mesh.points[tri[0]][a], y = mesh.points[tri[1]][a],
                       z = mesh.points[tri[2]][a];
          const double q = std::floor(((x + y + z) / 3.0 - grid.origin[a]) / s);
          if (!(std::fabs(q) < static_cast<double>(kLimit))) {
            chunk_ok[c] = 0;
            break;
          }
          const auto i = static_cast<std::int64_t>(q);
          auto bound = [&](std::int64_t k) { return grid.origin[a] + s * static_cast<double>(k); };
          const double lo = std::min({x, y, z}), hi = std::max({x, y, z});
          if (!(lo >= bound(i) - tol && hi <= bound(i + 1) + tol)) {
            chunk_ok[c] = 0;
            break;
          }
          if (lo <= bound(i) + tol) bits |= static_cast<std::uint8_t>(1u << (2 * a));
          if (hi >= bound(i + 1) - tol) bits |= static_cast<std::uint8_t>(2u << (2 * a));
          cell[t][a] = i;
          range[a] = std::min(range[a], i);
          range[3 + a] = std::max(range[3 + a], i);
        }
        reach[t] = bits;
      }
      chunk_range[c] = range;
    }
  });
  if (std::find(chunk_ok.begin(), chunk_ok.end(), 0) != chunk_ok.end()) return std::nullopt;
  std::array<std::int64_t, 6> range{kLimit, kLimit, kLimit, -kLimit, -kLimit, -kLimit};
  for (const auto& r : chunk_range)
    for (int a = 0; a < 3; ++a) {
      range[a] = std::min(range[a], r[a]);
      range[3 + a] = std::max(range[3 + a], r[3 + a]);
    }
  if (range[0] > range[3]) return std::vector<Pair>{};  // no kept triangles

  // Cell keys over the occupied range padded by one cell on every side, so that key + delta
  // of an occupied cell never wraps onto another occupied cell.
  std::array<std::int64_t, 3> dim{};
  long double cells = 1;
  for (int a = 0; a < 3; ++a) {
    dim[a] = range[3 + a] - range[a] + 3;
    cells *= static_cast<long double>(dim[a]);
  }
  if (cells > 0x1p62L) return std::nullopt;
  std::vector<std::uint64_t> keys;
  std::vector<std::uint32_t> order;
  keys.reserve(nt);
  order.reserve(nt);
  for (std::size_t t = 0; t < nt; ++t) {
    if (degenerate[t]) continue;
    const auto& c = cell[t];
    keys.push_back(static_cast<std::uint64_t>(
        (c[0] - range[0] + 1) + dim[0] * ((c[1] - range[1] + 1) + dim[1] * (c[2] - range[2] + 1))));
    order.push_back(static_cast<std::uint32_t>(t));
  }
  cell = {};
  radix_sort(keys, order, static_cast<std::uint64_t>(cells));

  // Occupied cells: key and first item; items carry what the pair loop reads.
  std::vector<std::uint64_t> cell_key;
  std::vector<std::uint32_t> cell_first;
  for (std::size_t i = 0; i < keys.size(); ++i)
    if (i == 0 || keys[i] != keys[i - 1]) {
      cell_key.push_back(keys[i]);
      cell_first.push_back(static_cast<std::uint32_t>(i));
    }
  cell_first.push_back(static_cast<std::uint32_t>(keys.size()));
  keys = {};
  struct Item {
    Box box;
    Triangle corners;
    std::uint32_t triangle;
    std::uint8_t reach;
  };
  std::vector<Item> items(order.size());
  detail::parallel_for(order.size(), kChunk, [&](std::size_t b, std::size_t e) {
    for (std::size_t i = b; i < e; ++i) {
      const Triangle& t = mesh.triangles[order[i]];
      items[i] = {triangle_box(mesh, t), t, order[i], reach[order[i]]};
    }
  });
  reach = {};

  // The 13 forward neighbours: key offset, and the faces a triangle of the cell (near) and
  // of the neighbour (far) must reach to meet across them.
  struct Neighbour {
    std::int64_t delta;
    std::uint8_t near, far;
  };
  std::vector<Neighbour> neighbours;
  for (int dz = -1; dz <= 1; ++dz)
    for (int dy = -1; dy <= 1; ++dy)
      for (int dx = -1; dx <= 1; ++dx) {
        const std::int64_t delta = dx + dim[0] * (dy + dim[1] * dz);
        if (delta <= 0) continue;
        Neighbour n{delta, 0, 0};
        const int d[3] = {dx, dy, dz};
        for (int a = 0; a < 3; ++a) {
          if (d[a] > 0) {
            n.near |= static_cast<std::uint8_t>(2u << (2 * a));
            n.far |= static_cast<std::uint8_t>(1u << (2 * a));
          } else if (d[a] < 0) {
            n.near |= static_cast<std::uint8_t>(1u << (2 * a));
            n.far |= static_cast<std::uint8_t>(2u << (2 * a));
          }
        }
        neighbours.push_back(n);
      }
  std::sort(neighbours.begin(), neighbours.end(),
            [](const Neighbour& a, const Neighbour& b) { return a.delta < b.delta; });

  const std::size_t nc = cell_key.size();
  constexpr std::size_t kCellChunk = 1024;
  const std::size_t cell_chunks = chunk_count(nc, kCellChunk);
  std::vector<std::vector<Pair>> chunk_pairs(cell_chunks);
  auto test = [&](const Item& a, const Item& b, std::vector<Pair>& out) {
    if (!boxes_meet(a.box, b.box)) return;
    if (triangles_intersect(a.corners, b.corners, points))
      out.push_back({std::min(a.triangle, b.triangle), std::max(a.triangle, b.triangle)});
  };
  detail::parallel_for(cell_chunks, 1, [&](std::size_t cb, std::size_t ce) {
    std::vector<std::uint32_t> near, far;
    for (std::size_t c = cb; c < ce; ++c) {
      const std::size_t begin = c * kCellChunk, end = std::min(nc, begin + kCellChunk);
      std::vector<Pair>& out = chunk_pairs[c];
      // One cursor per forward neighbour, advanced monotonically through cell_key.
      std::array<std::size_t, 13> cursor{};
      for (std::size_t d = 0; d < neighbours.size(); ++d)
        cursor[d] = static_cast<std::size_t>(
            std::lower_bound(cell_key.begin() + static_cast<std::ptrdiff_t>(begin), cell_key.end(),
                             cell_key[begin] + static_cast<std::uint64_t>(neighbours[d].delta)) -
            cell_key.begin());
      for (std::size_t ci = begin; ci < end; ++ci) {
        const std::uint32_t first = cell_first[ci], last = cell_first[ci + 1];
        for (std::uint32_t a = first; a < last; ++a)
          for (std::uint32_t b = a + 1; b < last; ++b) test(items[a], items[b], out);
        for (std::size_t d = 0; d < neighbours.size(); ++d) {
          const Neighbour& n = neighbours[d];
          const std::uint64_t want = cell_key[ci] + static_cast<std::uint64_t>(n.delta);
          std::size_t& k = cursor[d];
          while (k < nc && cell_key[k] < want) ++k;
          if (k == nc || cell_key[k] != want) continue;
          far.clear();
          for (std::uint32_t b = cell_first[k]; b < cell_first[k + 1]; ++b)
            if ((items[b].reach & n.far) == n.far) far.push_back(b);
          if (far.empty()) continue;
          for (std::uint32_t a = first; a < last; ++a)
            if ((items[a].reach & n.near) == n.near)
              for (std::uint32_t b : far) test(items[a], items[b], out);
        }
      }
      progress.add(cell_first[end] - cell_first[begin]);
    }
  });
  std::vector<Pair> pairs;
  for (const auto& p : chunk_pairs) pairs.insert(pairs.end(), p.begin(), p.end());
  tbb::parallel_sort(pairs.begin(), pairs.end());
  return pairs;
}

// --- components ---------------------------------------------------------------------------

/// Per triangle its component (through shared points), numbered in order of first triangle.
std::uint32_t label_components(const TriangleSoup& mesh, std::vector<std::uint32_t>& label) {
  detail::DisjointSets sets(mesh.points.size());
  for (const Triangle& t : mesh.triangles) {
    sets.unite(t[0], t[1]);
    sets.unite(t[0], t[2]);
  }
  std::vector<std::uint32_t> id(mesh.points.size(), detail::kNoIndex);
  label.resize(mesh.triangles.size());
  std::uint32_t count = 0;
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
    const std::uint32_t root = sets.find(mesh.triangles[t][0]);
    if (id[root] == detail::kNoIndex) id[root] = count++;
    label[t] = id[root];
  }
  return count;
}

/// Six times the signed volume of the tetrahedron (origin, triangle), and twice the area.
double six_volume(const TriangleSoup& mesh, const Triangle& t, Vec3 origin) {
  return dot(mesh.points[t[0]] - origin,
             cross(mesh.points[t[1]] - origin, mesh.points[t[2]] - origin));
}
double double_area(const TriangleSoup& mesh, const Triangle& t) {
  const Vec3 a = mesh.points[t[0]];
  return norm(cross(mesh.points[t[1]] - a, mesh.points[t[2]] - a));
}

/// Points used by some triangle.
std::vector<std::uint8_t> used_points(const TriangleSoup& mesh) {
  std::vector<std::uint8_t> used(mesh.points.size(), 0);
  for (const Triangle& t : mesh.triangles)
    for (std::uint32_t v : t) used[v] = 1;
  return used;
}

/// Centre of the bounding box of the used points (the origin when there are none).
Vec3 box_centre(const TriangleSoup& mesh, const std::vector<std::uint8_t>& used) {
  double lo[3] = {std::numeric_limits<double>::infinity(), std::numeric_limits<double>::infinity(),
                  std::numeric_limits<double>::infinity()};
  double hi[3] = {-lo[0], -lo[0], -lo[0]};
  for (std::size_t i = 0; i < mesh.points.size(); ++i)
    if (used[i])
      for (int a = 0; a < 3; ++a) {
        lo[a] = std::min(lo[a], mesh.points[i][a]);
        hi[a] = std::max(hi[a], mesh.points[i][a]);
      }
  if (!(lo[0] <= hi[0])) return {};
  return {0.5 * (lo[0] + hi[0]), 0.5 * (lo[1] + hi[1]), 0.5 * (lo[2] + hi[2])};
}

// --- topology -----------------------------------------------------------------------------

struct EdgeFacts {
  std::uint64_t border = 0, non_manifold = 0, inconsistent = 0, pinched_vertices = 0;
  std::vector<std::array<Vec3, 2>> border_examples, non_manifold_examples, inconsistent_examples;
};

/// Edges and fans from a vertex -> corner table. The triangles around vertex v are its
/// corners; corner (t, k) has the edges v -> next and prev -> v. Grouping v's corners by the
/// other end w gives every edge at v with all its uses: edges are classified at their smaller
/// vertex, and corners that share an edge used by two or more triangles are in one fan
/// (as in detail::analyze_soup). Triangles with a repeated corner take no part.
EdgeFacts edge_facts(const TriangleSoup& mesh, std::size_t max_examples,
                     detail::ProgressCounter& progress) {
  const std::size_t np = mesh.points.size(), nt = mesh.triangles.size();
  std::vector<std::uint32_t> first(np + 1, 0);
  for (const Triangle& t : mesh.triangles)
    if (!repeated_corner(t))
      for (std::uint32_t v : t) ++first[v + 1];
  for (std::size_t v = 0; v < np; ++v) first[v + 1] += first[v];
  std::vector<std::uint32_t> corners(first[np]);
  {
    std::vector<std::uint32_t> fill(first.begin(), first.end() - 1);
    for (std::size_t t = 0; t < nt; ++t)
      if (!repeated_corner(mesh.triangles[t]))
        for (std::uint32_t k = 0; k < 3; ++k)
          corners[fill[mesh.triangles[t][k]]++] = static_cast<std::uint32_t>(3 * t + k);
  }

  const std::size_t chunks = chunk_count(np);
  std::vector<EdgeFacts> partial(chunks);
  detail::parallel_for(chunks, 1, [&](std::size_t cb, std::size_t ce) {
    struct Use {
      std::uint32_t other;  // the edge's other end
      std::uint32_t local;  // index of the corner among v's corners
      bool out;             // the triangle walks v -> other
    };
    std::vector<Use> uses;
    std::vector<std::uint32_t> parent;
    for (std::size_t c = cb; c < ce; ++c) {
      EdgeFacts& f = partial[c];
      const std::size_t vb = c * kChunk, ve = std::min(np, vb + kChunk);
      for (std::size_t v = vb; v < ve; ++v) {
        const std::uint32_t d = first[v + 1] - first[v];
        if (d == 0) continue;
        uses.clear();
        for (std::uint32_t l = 0; l < d; ++l) {
          const std::uint32_t slot = corners[first[v] + l];
          const Triangle& t = mesh.triangles[slot / 3];
          const std::uint32_t k = slot % 3;
          uses.push_back({t[(k + 1) % 3], l, true});
          uses.push_back({t[(k + 2) % 3], l, false});
        }
        std::sort(uses.begin(), uses.end(), [](const Use& a, const Use& b) {
          return a.other != b.other ? a.other < b.other : a.local < b.local;
        });
        parent.resize(d);
        std::iota(parent.begin(), parent.end(), 0u);
        auto find = [&](std::uint32_t x) {
          while (parent[x] != x) x = parent[x] = parent[parent[x]];
          return x;
        };
        for (std::size_t i = 0; i < uses.size();) {
          std::size_t j = i + 1;
          while (j < uses.size() && uses[j].other == uses[i].other) ++j;
          const std::size_t m = j - i;
          if (m >= 2)
            for (std::size_t u = i + 1; u < j; ++u) {
              const std::uint32_t a = find(uses[i].local), b = find(uses[u].local);
              parent[std::max(a, b)] = std::min(a, b);
            }
          const std::uint32_t w = uses[i].other;
          if (w > v) {
            const Vec3 pv = mesh.points[v], pw = mesh.points[w];
            const std::array<Vec3, 2> ends =
                uses[i].out ? std::array<Vec3, 2>{pv, pw} : std::array<Vec3, 2>{pw, pv};
            if (m == 1) {
              if (f.border++ < max_examples) f.border_examples.push_back(ends);
            } else if (m >= 3) {
              if (f.non_manifold++ < max_examples) f.non_manifold_examples.push_back(ends);
            } else if (uses[i].out == uses[i + 1].out) {
              if (f.inconsistent++ < max_examples) f.inconsistent_examples.push_back(ends);
            }
          }
          i = j;
        }
        std::uint32_t fans = 0;
        for (std::uint32_t l = 0; l < d; ++l) fans += find(l) == l;
        if (fans > 1) ++f.pinched_vertices;
      }
      progress.add(ve - vb);
    }
  });
  EdgeFacts all;
  auto append = [&](std::vector<std::array<Vec3, 2>>& to,
                    const std::vector<std::array<Vec3, 2>>& from) {
    for (const auto& e : from)
      if (to.size() < max_examples) to.push_back(e);
  };
  for (const EdgeFacts& f : partial) {
    all.border += f.border;
    all.non_manifold += f.non_manifold;
    all.inconsistent += f.inconsistent;
    all.pinched_vertices += f.pinched_vertices;
    append(all.border_examples, f.border_examples);
    append(all.non_manifold_examples, f.non_manifold_examples);
    append(all.inconsistent_examples, f.inconsistent_examples);
  }
  return all;
}

/// Referenced points whose position an earlier referenced point already has (bit-identical,
/// -0.0 == +0.0): sort position hashes, then compare positions within equal hashes.
std::uint64_t duplicate_points(const TriangleSoup& mesh, const std::vector<std::uint8_t>& used) {
  auto bits = [](double c) {
    return c == 0.0 ? std::uint64_t{0} : std::bit_cast<std::uint64_t>(c);
  };
  auto mix = [](std::uint64_t h) {
    h ^= h >> 33;
    h *= 0xff51afd7ed558ccdULL;
    h ^= h >> 33;
    h *= 0xc4ceb9fe1a85ec53ULL;
    return h ^ (h >> 33);
  };
  std::vector<std::pair<std::uint64_t, std::uint32_t>> keys;
  for (std::size_t i = 0; i < mesh.points.size(); ++i)
    if (used[i]) keys.push_back({0, static_cast<std::uint32_t>(i)});
  detail::parallel_for(keys.size(), kChunk, [&](std::size_t b, std::size_t e) {
    for (std::size_t i = b; i < e; ++i) {
      const Vec3 p = mesh.points[keys[i].second];
      keys[i].first = mix(mix(mix(bits(p.x)) ^ bits(p.y)) ^ bits(p.z));
    }
  });
  tbb::parallel_sort(keys.begin(), keys.end());
  std::uint64_t duplicates = 0;
  for (std::size_t i = 0; i < keys.size();) {
    std::size_t j = i + 1;
    while (j < keys.size() && keys[j].first == keys[i].first) ++j;
    for (std::size_t a = i + 1; a < j; ++a)
      for (std::size_t b = i; b < a; ++b)
        if (mesh.points[keys[a].second] == mesh.points[keys[b].second]) {
          ++duplicates;
          break;
        }
    i = j;
  }
  return duplicates;
}

}  // namespace

bool ValidationReport::valid() const {
  return triangles > 0 && closed() && manifold() && inconsistent_edges == 0 &&
         degenerate_triangles == 0 && duplicate_points == 0 &&
         self_intersecting_pairs.value_or(0) == 0 && outward;
}

std::vector<std::string> ValidationReport::problems() const {
  std::vector<std::string> p;
  if (triangles == 0) p.push_back("the mesh has no triangles");
  if (border_edges > 0)
    p.push_back(plural(border_edges, "border edge", "border edges") + ": the mesh is not closed");
  if (non_manifold_edges > 0)
    p.push_back(plural(non_manifold_edges, "non-manifold edge", "non-manifold edges") +
                " (shared by three or more triangles)");
  if (non_manifold_vertices > 0)
    p.push_back(plural(non_manifold_vertices, "non-manifold vertex", "non-manifold vertices") +
                " (where separate sheets touch at a point)");
  if (inconsistent_edges > 0)
    p.push_back(plural(inconsistent_edges, "inconsistently oriented edge",
                       "inconsistently oriented edges") +
                ": neighbouring triangles disagree on which side is outside");
  if (triangles > 0 && !outward) {
    if (volume <= 0)
      p.push_back("the mesh is inside out: its signed volume is " + short_number(volume));
    else
      p.push_back("a component encloses no volume (its signed volume is zero)");
  }
  if (degenerate_triangles > 0)
    p.push_back(plural(degenerate_triangles, "degenerate triangle", "degenerate triangles") +
                " (repeated or collinear corners)");
  if (duplicate_points > 0)
    p.push_back(plural(duplicate_points, "duplicate point", "duplicate points") +
                ": separate vertices at the same position");
  if (self_intersecting_pairs.value_or(0) > 0)
    p.push_back(plural(*self_intersecting_pairs, "self-intersecting triangle pair",
                       "self-intersecting triangle pairs"));
  return p;
}

ValidationReport validate_mesh(const TriangleSoup& mesh, const ValidateOptions& options) {
  check_sizes(mesh);
  ValidationReport r;
  const std::size_t nt = mesh.triangles.size(), np = mesh.points.size();
  const std::size_t max_examples = options.max_examples;
  r.triangles = nt;
  detail::ProgressCounter progress(options.progress, "validate",
                                   np + nt + (options.self_intersections ? nt : 0));

  const std::vector<std::uint8_t> used = used_points(mesh);
  r.vertices = static_cast<std::uint64_t>(std::count(used.begin(), used.end(), 1));

  std::vector<Point3> points(np);
  detail::parallel_for(np, kChunk, [&](std::size_t b, std::size_t e) {
    for (std::size_t i = b; i < e; ++i) points[i] = detail::to_cgal(mesh.points[i]);
  });

  // --- degenerate triangles ---------------------------------------------------------------
  std::vector<std::uint8_t> degenerate(nt, 0);
  detail::parallel_for(nt, kChunk, [&](std::size_t b, std::size_t e) {
    for (std::size_t t = b; t < e; ++t) {
      const Triangle& tri = mesh.triangles[t];
      degenerate[t] =
          repeated_corner(tri) || CGAL::collinear(points[tri[0]], points[tri[1]], points[tri[2]]);
    }
  });
  for (std::size_t t = 0; t < nt; ++t)
    if (degenerate[t] && r.degenerate_triangles++ < max_examples)
      r.degenerate_examples.push_back(static_cast<std::uint32_t>(t));
  progress.add(nt);

  // --- edges, vertices, duplicate points ----------------------------------------------------
  EdgeFacts edges = edge_facts(mesh, max_examples, progress);
  r.border_edges = edges.border;
  r.non_manifold_edges = edges.non_manifold;
  r.inconsistent_edges = edges.inconsistent;
  r.non_manifold_vertices = edges.pinched_vertices;
  for (auto* examples :
       {&edges.border_examples, &edges.non_manifold_examples, &edges.inconsistent_examples})
    r.bad_edge_examples.insert(r.bad_edge_examples.end(), examples->begin(), examples->end());
  r.duplicate_points = duplicate_points(mesh, used);

  // --- components, area, volume, orientation ---------------------------------------------
  std::vector<std::uint32_t> label;
  r.components = label_components(mesh, label);
  const Vec3 centre = box_centre(mesh, used);
  std::vector<double> six_v(nt);
  detail::parallel_for(nt, kChunk, [&](std::size_t b, std::size_t e) {
    for (std::size_t t = b; t < e; ++t) six_v[t] = six_volume(mesh, mesh.triangles[t], centre);
  });
  r.volume = detail::deterministic_sum(nt, kChunk, [&](std::size_t t) { return six_v[t]; }) / 6;
  r.area = detail::deterministic_sum(
               nt, kChunk, [&](std::size_t t) { return double_area(mesh, mesh.triangles[t]); }) /
           2;
  {
    std::vector<double> component_volume(r.components, 0.0);
    for (std::size_t t = 0; t < nt; ++t) component_volume[label[t]] += six_v[t];
    r.outward = r.components > 0 && r.volume > 0 &&
                std::none_of(component_volume.begin(), component_volume.end(),
                             [](double v) { return v == 0; });
  }

  // --- self-intersections -------------------------------------------------------------------
  if (options.self_intersections) {
    std::optional<std::vector<Pair>> pairs;
    if (options.cell_grid) {
      pairs = intersecting_pairs_in_cells(mesh, points, degenerate, *options.cell_grid, progress);
      r.searched_by_cells = pairs.has_value();
    }
    if (!pairs) {
      pairs = intersecting_pairs_general(mesh, points, degenerate);
      progress.add(nt);
    }
    r.self_intersecting_pairs = pairs->size();
    pairs->resize(std::min(pairs->size(), max_examples));
    r.self_intersection_examples = std::move(*pairs);
  }
  progress.finish();
  return r;
}

Components mesh_components(const TriangleSoup& mesh) {
  check_sizes(mesh);
  Components c;
  const std::uint32_t count = label_components(mesh, c.triangle_component);
  c.info.resize(count);
  const Vec3 centre = box_centre(mesh, used_points(mesh));
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
    Components::Info& info = c.info[c.triangle_component[t]];
    if (info.triangles++ == 0) info.first_triangle = static_cast<std::uint32_t>(t);
    info.volume += six_volume(mesh, mesh.triangles[t], centre) / 6;
    info.area += double_area(mesh, mesh.triangles[t]) / 2;
  }
  return c;
}

TriangleSoup keep_components(const TriangleSoup& mesh, const Components& components,
                             const std::vector<bool>& keep) {
  detail::require_indices_in_range(mesh);
  bool fits = components.triangle_component.size() == mesh.triangles.size() &&
              keep.size() == components.info.size();
  for (std::size_t t = 0; fits && t < mesh.triangles.size(); ++t)
    fits = components.triangle_component[t] < keep.size();
  if (!fits)
    throw InputError("keep_components: the components or the keep flags do not fit the mesh");
  std::vector<std::uint32_t> new_index(mesh.points.size(), detail::kNoIndex);
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t)
    if (keep[components.triangle_component[t]])
      for (std::uint32_t v : mesh.triangles[t]) new_index[v] = 0;
  TriangleSoup out;
  for (std::size_t i = 0; i < mesh.points.size(); ++i)
    if (new_index[i] != detail::kNoIndex) {
      new_index[i] = static_cast<std::uint32_t>(out.points.size());
      out.points.push_back(mesh.points[i]);
    }
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t)
    if (keep[components.triangle_component[t]]) {
      const Triangle& tri = mesh.triangles[t];
      out.triangles.push_back({new_index[tri[0]], new_index[tri[1]], new_index[tri[2]]});
    }
  return out;
}

}  // namespace tpmsfill
