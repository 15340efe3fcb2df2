// Self-intersection search for stage "validate" (see self_intersections.hpp): an exact pair
// test with a filtered plane side test, and two ways to choose the pairs to test: cells of a
// grid (each triangle in the cell of its centroid, pairs only in the same or 26-adjacent
// cells, across a face only between triangles that reach it), or CGAL's box intersection.
// Every parallel loop runs over fixed chunks whose results are merged in chunk order.
//
// Most pairs of a marching-cubes mesh share a corner (12.5 of 19 million tested on a femur at
// 0.05 mm) and are settled without a construction: by coordinates when a plane of the grid
// through the corner separates them (apart_beyond_corner), else by plane sides and at most two
// orientations (corner_neighbours_meet). tests/mesh/self_intersections_test.cpp checks the pair
// test against CGAL's exact triangle intersection.
#include "mesh/internal/self_intersections.hpp"

#include <CGAL/Bbox_3.h>
#include <CGAL/Box_intersection_d/Box_with_info_d.h>
#include <CGAL/box_intersection_d.h>
#include <CGAL/intersections.h>
#include <tbb/parallel_sort.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>

#include "core/parallel.hpp"
#include "mesh/cgal_types.hpp"

namespace tpmsfill::detail {
namespace {

using Pair = TrianglePair;

constexpr std::size_t kChunk = 4096;  // items per fixed chunk of every parallel loop

std::size_t chunk_count(std::size_t n, std::size_t chunk = kChunk) {
  return (n + chunk - 1) / chunk;
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
///
/// The cross product and the magnitudes are a triangle's own (PlaneCoefficients), so the cell
/// search computes them once per triangle rather than once per pair it tests.
struct PlaneCoefficients {
  double n[3];  // (b - a) x (c - a)
  double m[3];  // per axis the two products' magnitudes, for the permanent
};

PlaneCoefficients plane_coefficients(const Point3& pa, const Point3& pb, const Point3& pc) {
  const double ux = pb.x() - pa.x(), uy = pb.y() - pa.y(), uz = pb.z() - pa.z();
  const double wx = pc.x() - pa.x(), wy = pc.y() - pa.y(), wz = pc.z() - pa.z();
  return {{uy * wz - uz * wy, uz * wx - ux * wz, ux * wy - uy * wx},
          {std::fabs(uy * wz) + std::fabs(uz * wy), std::fabs(uz * wx) + std::fabs(ux * wz),
           std::fabs(ux * wy) + std::fabs(uy * wx)}};
}

struct Plane {
  const Point3 *a, *b, *c;
  PlaneCoefficients k;

  Plane(const Point3& pa, const Point3& pb, const Point3& pc)
      : Plane(pa, pb, pc, plane_coefficients(pa, pb, pc)) {}
  Plane(const Point3& pa, const Point3& pb, const Point3& pc, const PlaneCoefficients& coefficients)
      : a(&pa), b(&pb), c(&pc), k(coefficients) {}

  /// -1, 0 or +1: the exact sign of det(b - a, c - a, x - a).
  int side(const Point3& x) const {
    const double zx = x.x() - a->x(), zy = x.y() - a->y(), zz = x.z() - a->z();
    const double d = k.n[0] * zx + k.n[1] * zy + k.n[2] * zz;
    const double permanent =
        k.m[0] * std::fabs(zx) + k.m[1] * std::fabs(zy) + k.m[2] * std::fabs(zz);
    if (std::fabs(d) > 2e-15 * permanent && permanent > 1e-250) return d > 0 ? 1 : -1;
    return static_cast<int>(CGAL::orientation(*a, *b, *c, x));
  }
};

/// Does segment xy meet the triangle of `plane`? Both ends strictly on one side means no.
bool segment_meets_triangle(const Plane& plane, const Point3& x, const Point3& y) {
  const int sx = plane.side(x);
  if (sx != 0 && sx == plane.side(y)) return false;
  return CGAL::do_intersect(Kernel::Triangle_3(*plane.a, *plane.b, *plane.c),
                            Kernel::Segment_3(x, y));
}

/// All three of p, q, r strictly on one side of the plane.
bool strictly_one_side(const Plane& plane, const Point3& p, const Point3& q, const Point3& r) {
  const int s = plane.side(p);
  return s != 0 && s == plane.side(q) && s == plane.side(r);
}

/// Triangles h and g share an edge (corners h[hs[0]], h[hs[1]]): they intersect only if g's
/// opposite corner is coplanar with h and on the same side of the edge as h's.
bool edge_neighbours_overlap(const Plane& ph, const Triangle& h, const Triangle& g, const int hs[2],
                             const int gs[2], const std::vector<Point3>& p) {
  const Point3& s = p[g[3 - gs[0] - gs[1]]];
  if (ph.side(s) != 0) return false;  // not coplanar
  const Point3& a = p[h[hs[0]]];
  const Point3& b = p[h[hs[1]]];
  const Point3& r = p[h[3 - hs[0] - hs[1]]];
  return CGAL::coplanar_orientation(a, b, r, s) == CGAL::POSITIVE;
}

/// Triangles h and g share corner v = h[i] = g[j], and g's far edge xy crosses h's plane
/// strictly (`sy` = side of y, -side of x). Then g meets h's plane in the segment v-X, X on xy,
/// and the two meet beyond v exactly when X lies in h's closed angle at v. In h's plane, with
/// hx, hy h's next corners after v (counter-clockwise about h's normal n),
/// orient(v, hx, X) has the sign of det(hx - v, X - v, y - x) / (n . (y - x)) =
/// orientation(v, hx, x, y) * sy, so two exact orientations decide, with no construction.
bool crossing_in_angle(const Triangle& h, int i, const Point3& x, const Point3& y, int sy,
                       const std::vector<Point3>& p) {
  const Point3& v = p[h[i]];
  const int left = static_cast<int>(CGAL::orientation(v, p[h[(i + 1) % 3]], x, y)) * sy;
  if (left < 0) return false;
  return static_cast<int>(CGAL::orientation(v, p[h[(i + 2) % 3]], x, y)) * sy <= 0;
}

/// Triangles h and g share corner v = h[i] = g[j]. When, along some axis, h lies on one side of
/// v's coordinate c and g on the other (both closed), all they share lies in the plane x = c,
/// which each meets in the hull of its corners there; if one has no corner there but v, they
/// share v alone. Coordinates compared, nothing computed: it settles most pairs of
/// neighbouring marching-cubes cells, which lie on either side of a cell face.
bool apart_beyond_corner(const Triangle& h, const Triangle& g, int i, int j,
                         const std::vector<Point3>& p) {
  const Point3 &v = p[h[i]], &hx = p[h[(i + 1) % 3]], &hy = p[h[(i + 2) % 3]];
  const Point3 &gx = p[g[(j + 1) % 3]], &gy = p[g[(j + 2) % 3]];
  for (int a = 0; a < 3; ++a) {
    const double c = v[a], h1 = hx[a], h2 = hy[a], g1 = gx[a], g2 = gy[a];
    const bool h_below = h1 <= c && h2 <= c, h_above = h1 >= c && h2 >= c;
    const bool g_below = g1 <= c && g2 <= c, g_above = g1 >= c && g2 >= c;
    if (!((h_below && g_above) || (h_above && g_below))) continue;
    if ((h1 != c && h2 != c) || (g1 != c && g2 != c)) return true;
  }
  return false;
}

/// Triangles h and g share corner h[i] = g[j]: they intersect only if the far edge of either
/// meets the other triangle.
bool corner_neighbours_meet(const Plane& ph, const Plane& pg, const Triangle& h, const Triangle& g,
                            int i, int j, const std::vector<Point3>& p) {
  // With the far edge of either strictly on one side of the other's plane, that triangle
  // meets the other's plane only at the shared corner: no intersection (both of CGAL's
  // segment tests below would say no).
  const Point3 &hx = p[h[(i + 1) % 3]], &hy = p[h[(i + 2) % 3]];
  const Point3 &gx = p[g[(j + 1) % 3]], &gy = p[g[(j + 2) % 3]];
  const int sgx = ph.side(gx), sgy = ph.side(gy);
  if (sgx != 0 && sgx == sgy) return false;
  const int shx = pg.side(hx), shy = pg.side(hy);
  if (shx != 0 && shx == shy) return false;
  // A far edge crossing the other's plane strictly (the common case): meeting beyond the
  // shared corner is equivalent to CGAL's two segment tests (the meet is a segment from the
  // corner along the planes' common line; whichever triangle it leaves first, the other's
  // far edge crosses it there), and two orientations decide it.
  if (sgx != 0 && sgx == -sgy) return crossing_in_angle(h, i, gx, gy, sgy, p);
  if (shx != 0 && shx == -shy) return crossing_in_angle(g, j, hx, hy, shy, p);
  return segment_meets_triangle(ph, gx, gy) || segment_meets_triangle(pg, hx, hy);
}

/// Whether two non-degenerate triangles (corner indices into `p`) intersect beyond what they
/// share by index, as CGAL's do_faces_intersect() (self_intersections.h) decides it:
/// - a shared edge: only if the two opposite corners are coplanar with it and on the same
///   side (the triangles overlap); three shared corners (the same triangle twice) always;
/// - one shared corner: only if the opposite edge of either meets the other triangle;
/// - nothing shared: whether the closed triangles meet at all.
/// `kh` and `kg` are the planes' coefficients of h and g (plane_coefficients of their corners).
bool triangles_intersect(const Triangle& h, const Triangle& g, const PlaneCoefficients& kh,
                         const PlaneCoefficients& kg, const std::vector<Point3>& p) {
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
  if (shared == 1 && apart_beyond_corner(h, g, hs[0], gs[0], p)) return false;
  const Plane ph(p[h[0]], p[h[1]], p[h[2]], kh);
  if (shared == 2) return edge_neighbours_overlap(ph, h, g, hs, gs, p);
  const Plane pg(p[g[0]], p[g[1]], p[g[2]], kg);
  if (shared == 1) return corner_neighbours_meet(ph, pg, h, g, hs[0], gs[0], p);
  if (strictly_one_side(ph, p[g[0]], p[g[1]], p[g[2]]) ||
      strictly_one_side(pg, p[h[0]], p[h[1]], p[h[2]]))
    return false;
  return CGAL::do_intersect(Kernel::Triangle_3(p[h[0]], p[h[1]], p[h[2]]),
                            Kernel::Triangle_3(p[g[0]], p[g[1]], p[g[2]]));
}

struct Box {
  double lo[3], hi[3];
};

Box triangle_box(const std::vector<Point3>& p, const Triangle& t) {
  Box b;
  for (int a = 0; a < 3; ++a) {
    const double x = p[t[0]][a], y = p[t[1]][a], z = p[t[2]][a];
    b.lo[a] = std::min({x, y, z});
    b.hi[a] = std::max({x, y, z});
  }
  return b;
}

bool share_a_corner(const Triangle& h, const Triangle& g) {
  int shared = 0;  // summed, not short-circuited, as boxes_meet
  for (const std::uint32_t a : h) shared += int{a == g[0]} + int{a == g[1]} + int{a == g[2]};
  return shared != 0;
}

bool boxes_meet(const Box& a, const Box& b) {
  // Non-short-circuit: cheaper than six unpredictable branches.
  return (a.lo[0] <= b.hi[0]) & (b.lo[0] <= a.hi[0]) & (a.lo[1] <= b.hi[1]) & (b.lo[1] <= a.hi[1]) &
         (a.lo[2] <= b.hi[2]) & (b.lo[2] <= a.hi[2]);
}

// --- general path ----------------------------------------------------------------------------

// CGAL's box intersection, run sequentially, hands over the candidate pairs (boxes that
// meet), which are tested exactly in parallel a batch at a time. Its parallel version would
// copy the boxes eight times: 0.7 GB for 1.3 million triangles, for no gain over testing the
// candidates in parallel.
std::vector<Pair> intersecting_pairs_general(const TriangleSoup& mesh,
                                             const std::vector<Point3>& points,
                                             const std::vector<std::uint8_t>& skip) {
  using CgalBox = CGAL::Box_intersection_d::Box_with_info_d<double, 3, std::uint32_t>;
  std::vector<CgalBox> boxes;
  boxes.reserve(mesh.triangles.size());
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
    if (skip[t]) continue;
    const Triangle& tri = mesh.triangles[t];
    boxes.emplace_back(points[tri[0]].bbox() + points[tri[1]].bbox() + points[tri[2]].bbox(),
                       static_cast<std::uint32_t>(t));
  }
  constexpr std::size_t kBatch = std::size_t{1} << 20;
  std::vector<Pair> candidates, pairs;
  std::vector<std::uint8_t> meet;
  candidates.reserve(kBatch);
  auto test = [&] {
    meet.assign(candidates.size(), 0);
    parallel_for(candidates.size(), kChunk, [&](std::size_t b, std::size_t e) {
      for (std::size_t n = b; n < e; ++n) {
        const Triangle &h = mesh.triangles[candidates[n][0]], &g = mesh.triangles[candidates[n][1]];
        meet[n] = triangles_intersect(
            h, g, plane_coefficients(points[h[0]], points[h[1]], points[h[2]]),
            plane_coefficients(points[g[0]], points[g[1]], points[g[2]]), points);
      }
    });
    for (std::size_t n = 0; n < candidates.size(); ++n)
      if (meet[n]) pairs.push_back(candidates[n]);
    candidates.clear();
  };
  CGAL::box_self_intersection_d<CGAL::Sequential_tag>(
      boxes.begin(), boxes.end(), [&](const CgalBox& a, const CgalBox& b) {
        const std::uint32_t i = a.info(), j = b.info();
        candidates.push_back({std::min(i, j), std::max(i, j)});
        if (candidates.size() == kBatch) test();
      });
  test();
  tbb::parallel_sort(pairs.begin(), pairs.end());
  pairs.erase(std::unique(pairs.begin(), pairs.end()), pairs.end());
  return pairs;
}

// --- cell-grid path --------------------------------------------------------------------------
//
// Each triangle is put in the cell i (per axis) that holds its centroid and must lie in
// [L(i) - tol, L(i + 1) + tol], L(i) = origin + spacing * i as computed in double, with one
// tolerance tol far below a cell and far above the rounding of L. Then two triangles in
// cells more than one apart on some axis are disjoint (they are separated by about a cell
// less 2 tol), so only pairs in the same or 26-adjacent cells can meet; each unordered cell
// pair is visited once (the 13 neighbours with a larger cell key), each triangle pair at
// most once.
//
// Across a face between cells i and i + 1 (per axis), a triangle of cell i can meet one of
// cell i + 1 only where both reach the face: the first has max >= L(i + 1) - tol (the second's
// lower bound), the second min <= L(i + 1) + tol (the first's upper bound). Each triangle
// records which of its cell's six faces it reaches, and a neighbour pair only pairs
// triangles that reach the faces between them: exact, and most pairs are never looked at.

constexpr std::int64_t kLimit = std::int64_t{1} << 40;  // largest cell index per axis

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

/// The one tolerance for all cells, so that neighbouring cells agree on their common bound;
/// nullopt when the grid or the coordinates leave no room for one. It covers coordinates
/// rounded to float (fill validates what binary STL stores): a float ulp relative to the
/// largest coordinate. Any tolerance below a quarter cell keeps the search complete; a larger
/// one only adds candidate pairs.
std::optional<double> cell_tolerance(const TriangleSoup& mesh, const Grid& grid) {
  const double s = grid.spacing;
  if (!(s > 0) || !std::isfinite(s)) return std::nullopt;
  double magnitude =
      std::max({std::fabs(grid.origin.x), std::fabs(grid.origin.y), std::fabs(grid.origin.z)});
  // A maximum is the same in any order: per fixed chunk, then over the chunks.
  const std::size_t nt = mesh.triangles.size();
  std::vector<double> chunk_magnitude(chunk_count(nt), 0.0);
  parallel_for(chunk_magnitude.size(), 1, [&](std::size_t cb, std::size_t ce) {
    for (std::size_t c = cb; c < ce; ++c)
      for (std::size_t t = c * kChunk; t < std::min(nt, (c + 1) * kChunk); ++t)
        for (std::uint32_t v : mesh.triangles[t])
          chunk_magnitude[c] = std::max({chunk_magnitude[c], std::fabs(mesh.points[v].x),
                                         std::fabs(mesh.points[v].y), std::fabs(mesh.points[v].z)});
  });
  for (double m : chunk_magnitude) magnitude = std::max(magnitude, m);
  const double tol =
      1e-7 * s + static_cast<double>(std::numeric_limits<float>::epsilon()) * (magnitude + s);
  if (!(tol < 0.25 * s) || !std::isfinite(magnitude)) return std::nullopt;
  return tol;
}

/// A triangle's cell and the faces of it the triangle reaches: bit 2a the lower face on axis
/// a, bit 2a + 1 the upper face.
struct Placement {
  std::array<std::int64_t, 3> cell{};
  std::uint8_t reach = 0;
};

/// The cell holding the triangle's centroid, if the triangle lies in it (within tol).
std::optional<Placement> place(const TriangleSoup& mesh, const Triangle& tri, const Grid& grid,
                               double tol) {
  const double s = grid.spacing;
  Placement at;
  for (int a = 0; a < 3; ++a) {
    const double x = mesh.points[tri[0]][a], y = mesh.points[tri[1]][a], z = mesh.points[tri[2]][a];
    const double q = std::floor(((x + y + z) / 3.0 - grid.origin[a]) / s);
    if (!(std::fabs(q) < static_cast<double>(kLimit))) return std::nullopt;
    const auto i = static_cast<std::int64_t>(q);
    auto bound = [&](std::int64_t k) { return grid.origin[a] + s * static_cast<double>(k); };
    const double lo = std::min({x, y, z}), hi = std::max({x, y, z});
    if (!(lo >= bound(i) - tol && hi <= bound(i + 1) + tol)) return std::nullopt;
    if (lo <= bound(i) + tol) at.reach |= static_cast<std::uint8_t>(1u << (2 * a));
    if (hi >= bound(i + 1) - tol) at.reach |= static_cast<std::uint8_t>(2u << (2 * a));
    at.cell[a] = i;
  }
  return at;
}

/// Cell indices: per axis the lowest (0..2) and highest (3..5); empty when lo > hi.
using CellRange = std::array<std::int64_t, 6>;

constexpr CellRange kEmptyRange{kLimit, kLimit, kLimit, -kLimit, -kLimit, -kLimit};

void extend(CellRange& range, const std::array<std::int64_t, 3>& cell) {
  for (int a = 0; a < 3; ++a) {
    range[a] = std::min(range[a], cell[a]);
    range[3 + a] = std::max(range[3 + a], cell[a]);
  }
}

/// Every kept triangle placed (skipped ones: unset), and the range of occupied cells.
struct Placements {
  std::vector<std::array<std::int64_t, 3>> cell;  ///< per triangle
  std::vector<std::uint8_t> reach;                ///< per triangle
  CellRange range = kEmptyRange;
};

/// Places every triangle not skipped; nullopt when some triangle does not lie in its cell.
std::optional<Placements> place_all(const TriangleSoup& mesh, const std::vector<std::uint8_t>& skip,
                                    const Grid& grid, double tol) {
  const std::size_t nt = mesh.triangles.size();
  Placements p;
  p.cell.resize(nt);
  p.reach.assign(nt, 0);
  const std::size_t chunks = chunk_count(nt);
  std::vector<std::uint8_t> chunk_ok(chunks, 1);
  std::vector<CellRange> chunk_range(chunks, kEmptyRange);
  parallel_for(chunks, 1, [&](std::size_t cb, std::size_t ce) {
    for (std::size_t c = cb; c < ce; ++c)
      for (std::size_t t = c * kChunk; t < std::min(nt, (c + 1) * kChunk) && chunk_ok[c]; ++t) {
        if (skip[t]) continue;
        const std::optional<Placement> at = place(mesh, mesh.triangles[t], grid, tol);
        if (!at) {
          chunk_ok[c] = 0;
          break;
        }
        p.cell[t] = at->cell;
        p.reach[t] = at->reach;
        extend(chunk_range[c], at->cell);
      }
  });
  if (std::find(chunk_ok.begin(), chunk_ok.end(), 0) != chunk_ok.end()) return std::nullopt;
  for (const CellRange& r : chunk_range)
    for (int a = 0; a < 3; ++a) {
      p.range[a] = std::min(p.range[a], r[a]);
      p.range[3 + a] = std::max(p.range[3 + a], r[3 + a]);
    }
  return p;
}

/// Kept triangles sorted by the key of their cell, over the occupied range padded by one
/// cell on every side (so that key + delta of an occupied cell never wraps onto another
/// occupied cell).
struct CellOrder {
  std::array<std::int64_t, 3> dim{};  ///< padded range, cells per axis
  std::vector<std::uint64_t> keys;    ///< sorted
  std::vector<std::uint32_t> order;   ///< triangle of each key
};

/// nullopt when the padded range has more than 2^62 cells. `cell` (Placements::cell) is
/// freed before the sort.
std::optional<CellOrder> sort_by_cell(std::vector<std::array<std::int64_t, 3>> cell,
                                      const CellRange& range,
                                      const std::vector<std::uint8_t>& skip) {
  CellOrder o;
  long double cells = 1;
  for (int a = 0; a < 3; ++a) {
    o.dim[a] = range[3 + a] - range[a] + 3;
    cells *= static_cast<long double>(o.dim[a]);
  }
  if (cells > 0x1p62L) return std::nullopt;
  const std::size_t nt = cell.size();
  o.keys.reserve(nt);
  o.order.reserve(nt);
  for (std::size_t t = 0; t < nt; ++t) {
    if (skip[t]) continue;
    const auto& c = cell[t];
    o.keys.push_back(static_cast<std::uint64_t>(
        (c[0] - range[0] + 1) +
        o.dim[0] * ((c[1] - range[1] + 1) + o.dim[1] * (c[2] - range[2] + 1))));
    o.order.push_back(static_cast<std::uint32_t>(t));
  }
  cell = {};
  // Marching cubes emits its triangles cell by cell in key order: then there is nothing to sort.
  if (!std::is_sorted(o.keys.begin(), o.keys.end()))
    radix_sort(o.keys, o.order, static_cast<std::uint64_t>(cells));
  return o;
}

/// What the pair loop reads of a triangle. No box: most pairs the loop meets share a corner,
/// whose boxes always meet, so a box is made only for a pair that shares none.
struct Item {
  PlaneCoefficients plane;
  Triangle corners;
  std::uint32_t triangle;
  std::uint8_t reach;
};

/// Occupied cells: key and first item (items of cell i: [first[i], first[i + 1])).
struct Cells {
  std::vector<std::uint64_t> key;
  std::vector<std::uint32_t> first;
  std::unique_ptr<Item[]> items;  // left uninitialised until the parallel fill touches it
};

/// The cells of `o` (whose keys it frees early) with their items.
Cells occupied_cells(const TriangleSoup& mesh, const std::vector<Point3>& points, CellOrder o,
                     const std::vector<std::uint8_t>& reach) {
  Cells cells;
  for (std::size_t i = 0; i < o.keys.size(); ++i)
    if (i == 0 || o.keys[i] != o.keys[i - 1]) {
      cells.key.push_back(o.keys[i]);
      cells.first.push_back(static_cast<std::uint32_t>(i));
    }
  cells.first.push_back(static_cast<std::uint32_t>(o.keys.size()));
  o.keys = {};
  cells.items = std::make_unique_for_overwrite<Item[]>(o.order.size());
  parallel_for(o.order.size(), kChunk, [&](std::size_t b, std::size_t e) {
    for (std::size_t i = b; i < e; ++i) {
      const Triangle& t = mesh.triangles[o.order[i]];
      cells.items[i] = {plane_coefficients(points[t[0]], points[t[1]], points[t[2]]), t, o.order[i],
                        reach[o.order[i]]};
    }
  });
  return cells;
}

/// A forward neighbour: key offset, and the faces a triangle of the cell (near) and of the
/// neighbour (far) must reach to meet across them.
struct Neighbour {
  std::int64_t delta;
  std::uint8_t near, far;
};

/// The 13 neighbours with a larger key, by increasing offset.
std::vector<Neighbour> forward_neighbours(const std::array<std::int64_t, 3>& dim) {
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
  return neighbours;
}

/// Tests the pairs of cells [begin, end) and their forward neighbours; appends hits to `out`.
void pairs_of_cells(const Cells& cells, const std::vector<Neighbour>& neighbours,
                    const std::vector<Point3>& points, std::size_t begin, std::size_t end,
                    std::vector<Pair>& out) {
  const std::vector<std::uint64_t>& key = cells.key;
  const std::vector<std::uint32_t>& first = cells.first;
  const Item* items = cells.items.get();
  const std::size_t nc = key.size();
  auto test = [&](const Item& a, const Item& b) {
    if (!share_a_corner(a.corners, b.corners) &&
        !boxes_meet(triangle_box(points, a.corners), triangle_box(points, b.corners)))
      return;
    if (triangles_intersect(a.corners, b.corners, a.plane, b.plane, points))
      out.push_back({std::min(a.triangle, b.triangle), std::max(a.triangle, b.triangle)});
  };
  // One cursor per forward neighbour, advanced monotonically through the keys.
  std::array<std::size_t, 13> cursor{};
  for (std::size_t d = 0; d < neighbours.size(); ++d)
    cursor[d] = static_cast<std::size_t>(
        std::lower_bound(key.begin() + static_cast<std::ptrdiff_t>(begin), key.end(),
                         key[begin] + static_cast<std::uint64_t>(neighbours[d].delta)) -
        key.begin());
  std::vector<std::uint32_t> far;
  for (std::size_t ci = begin; ci < end; ++ci) {
    for (std::uint32_t a = first[ci]; a < first[ci + 1]; ++a)
      for (std::uint32_t b = a + 1; b < first[ci + 1]; ++b) test(items[a], items[b]);
    for (std::size_t d = 0; d < neighbours.size(); ++d) {
      const Neighbour& n = neighbours[d];
      const std::uint64_t want = key[ci] + static_cast<std::uint64_t>(n.delta);
      std::size_t& k = cursor[d];
      while (k < nc && key[k] < want) ++k;
      if (k == nc || key[k] != want) continue;
      far.clear();
      for (std::uint32_t b = first[k]; b < first[k + 1]; ++b)
        if ((items[b].reach & n.far) == n.far) far.push_back(b);
      if (far.empty()) continue;
      for (std::uint32_t a = first[ci]; a < first[ci + 1]; ++a)
        if ((items[a].reach & n.near) == n.near)
          for (std::uint32_t b : far) test(items[a], items[b]);
    }
  }
}

/// The pair loop over fixed chunks of occupied cells, merged in chunk order and sorted.
std::vector<Pair> pairs_in_cells(const Cells& cells, const std::vector<Neighbour>& neighbours,
                                 const std::vector<Point3>& points, ProgressCounter& progress) {
  const std::size_t nc = cells.key.size();
  constexpr std::size_t kCellChunk = 1024;
  const std::size_t cell_chunks = chunk_count(nc, kCellChunk);
  std::vector<std::vector<Pair>> chunk_pairs(cell_chunks);
  parallel_for(cell_chunks, 1, [&](std::size_t cb, std::size_t ce) {
    for (std::size_t c = cb; c < ce; ++c) {
      const std::size_t begin = c * kCellChunk, end = std::min(nc, begin + kCellChunk);
      pairs_of_cells(cells, neighbours, points, begin, end, chunk_pairs[c]);
      progress.add(cells.first[end] - cells.first[begin]);
    }
  });
  std::vector<Pair> pairs;
  for (const auto& p : chunk_pairs) pairs.insert(pairs.end(), p.begin(), p.end());
  tbb::parallel_sort(pairs.begin(), pairs.end());
  return pairs;
}

/// Intersecting pairs when every triangle lies in one closed cell of `grid`; nullopt when
/// some triangle does not (then the caller takes the general path).
std::optional<std::vector<Pair>> intersecting_pairs_in_cells(const TriangleSoup& mesh,
                                                             const std::vector<Point3>& points,
                                                             const std::vector<std::uint8_t>& skip,
                                                             const Grid& grid,
                                                             ProgressCounter& progress) {
  const std::optional<double> tol = cell_tolerance(mesh, grid);
  if (!tol) return std::nullopt;
  std::optional<Placements> placed = place_all(mesh, skip, grid, *tol);
  if (!placed) return std::nullopt;
  if (placed->range[0] > placed->range[3]) return std::vector<Pair>{};  // no kept triangles
  std::optional<CellOrder> order = sort_by_cell(std::move(placed->cell), placed->range, skip);
  if (!order) return std::nullopt;
  const std::vector<Neighbour> neighbours = forward_neighbours(order->dim);
  const Cells cells = occupied_cells(mesh, points, std::move(*order), placed->reach);
  placed.reset();
  return pairs_in_cells(cells, neighbours, points, progress);
}

}  // namespace

bool triangle_pair_intersects(const Triangle& h, const Triangle& g,
                              const std::vector<Vec3>& points) {
  std::vector<Point3> p(points.size());
  for (std::size_t i = 0; i < p.size(); ++i) p[i] = to_cgal(points[i]);
  return triangles_intersect(h, g, plane_coefficients(p[h[0]], p[h[1]], p[h[2]]),
                             plane_coefficients(p[g[0]], p[g[1]], p[g[2]]), p);
}

SelfIntersections find_self_intersections(const TriangleSoup& mesh,
                                          const std::vector<std::uint8_t>& skip,
                                          const std::optional<Grid>& cell_grid,
                                          ProgressCounter& progress) {
  std::vector<Point3> points(mesh.points.size());
  parallel_for(points.size(), kChunk, [&](std::size_t b, std::size_t e) {
    for (std::size_t i = b; i < e; ++i) points[i] = to_cgal(mesh.points[i]);
  });
  SelfIntersections found;
  std::optional<std::vector<Pair>> pairs;
  if (cell_grid) {
    pairs = intersecting_pairs_in_cells(mesh, points, skip, *cell_grid, progress);
    found.by_cells = pairs.has_value();
  }
  if (!pairs) {
    pairs = intersecting_pairs_general(mesh, points, skip);
    progress.add(mesh.triangles.size());
  }
  found.pairs = std::move(*pairs);
  return found;
}

}  // namespace tpmsfill::detail
