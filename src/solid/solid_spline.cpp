// The spline fit of seed 001 (solid_spline.hpp): Greville start, Euler steps on the seed's
// energies, RS stopping, progressive refinement.
#include "tpmsfill/solid/solid_spline.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <functional>
#include <iterator>
#include <limits>
#include <span>
#include <stdexcept>
#include <string>
#include <tuple>
#include <utility>

#include "core/parallel.hpp"
#include "core/stage_progress.hpp"
#include "solid/cube_lookup.hpp"
#include "solid/internal/det_grid.hpp"
#include "solid/internal/fit_system.hpp"
#include "solid/internal/spline_terms.hpp"
#include "solid/internal/untangle_spline.hpp"
#include "surface/surface_normals.hpp"
#include "tpmsfill/error.hpp"
#include "tpmsfill/sampling/distance.hpp"
#include "tpmsfill/solid/tet_mesh.hpp"

namespace tpmsfill {
namespace {

using detail::Gather;
using detail::gather;
using detail::row_coefficients;

// Gauss–Legendre, 3 points on [0, 1].
constexpr double kNode[3] = {0.11270166537925831, 0.5, 0.88729833462074169};
constexpr double kWeight[3] = {5.0 / 18, 8.0 / 18, 5.0 / 18};
constexpr int kCellSamples = 27;
// The finer check of det J_G: 5³ points inside an element and 4³ reaching its faces (on an
// element along one of the cube's edges 9³ more: finer_samples()).
constexpr int kFineSamples = 125 + 64;
// A Newton step's solve: its residual relative to the right-hand side, and its iteration cap.
constexpr double kSolveTolerance = 1e-2;
constexpr int kSolveIterations = 2000;
// The anchor's share of the data's weight (newton_step()).
constexpr double kAnchor = 0.05;
// The data term's weight per control point against the regularisers (newton_step()).
constexpr double kDataWeight = 100;

// Positions to unit size about the points' box centre, material to [0, 1]: what the fit works in.
struct Units {
  Vec3 centre;
  double size = 1;
  double m0 = 0, m_range = 1;
};

Units units_of(const TetMesh& mesh, const CubeMap& map) {
  Vec3 lo{1e300, 1e300, 1e300}, hi{-1e300, -1e300, -1e300};
  double m_lo = 1e300, m_hi = -1e300;
  for (std::size_t p = 0; p < mesh.points.size(); ++p) {
    if (std::isnan(map.uvw[p][0])) continue;
    const Vec3 x = mesh.points[p];
    lo = {std::min(lo.x, x.x), std::min(lo.y, x.y), std::min(lo.z, x.z)};
    hi = {std::max(hi.x, x.x), std::max(hi.y, x.y), std::max(hi.z, x.z)};
    if (!mesh.material.empty())
      m_lo = std::min(m_lo, mesh.material[p]), m_hi = std::max(m_hi, mesh.material[p]);
  }
  Units u;
  u.centre = 0.5 * (lo + hi);
  u.size = std::max({hi.x - lo.x, hi.y - lo.y, hi.z - lo.z});
  if (!(u.size > 0)) u.size = 1;
  if (!mesh.material.empty()) {
    u.m0 = m_lo;
    u.m_range = m_hi > m_lo ? m_hi - m_lo : 1;
  }
  return u;
}

// I_G and I_M at (u, v, w), in the fit's units: x, y, z, m.
std::array<double, 4> target_at(const CubeLookup& lookup, const Units& u,
                                std::array<double, 3> uvw) {
  const CubeSample s = cube_lookup(lookup, uvw);
  return {(s.position.x - u.centre.x) / u.size, (s.position.y - u.centre.y) / u.size,
          (s.position.z - u.centre.z) / u.size, (s.material - u.m0) / u.m_range};
}

// The data: a 4-point rule (degree 2) in every tet, at its image in the cube, where I_G and
// I_M are the tet's own linear interpolation, weighted by the tet's volume (in the fit's
// units), so that the fit and RS measure the error over the solid as it is. (Weighted by the
// images' volumes instead, tets squeezed by the map, near the cube's edges and corners,
// counted for little: RS rose to 95 % while bunny00's sections lost 39 % of their area; and
// the flat images of tets lying on one patch, which hold the boundary, counted for nothing.)
// Then the boundary triangles (below). It does not depend on the basis, so RS compares rounds
// and bases fairly.
struct TetSamples {
  std::vector<std::array<double, 3>> uvw;
  std::vector<double> weight;
  std::vector<std::array<double, 4>> target;  // x, y, z, m in the fit's units
};

// Per boundary triangle, its corners' normals: the angle-weighted mean of the normals of the
// faces about the corner that lie within kCreaseDegrees of the triangle's own (so that a
// crease keeps one normal a side, as Mesh_3's protected features do).
constexpr double kCreaseDegrees = 60;

std::vector<std::array<Vec3, 3>> corner_normals(const std::vector<Vec3>& points,
                                                const std::vector<Triangle>& triangles) {
  std::vector<Vec3> normal(triangles.size());
  std::vector<std::array<double, 3>> angle(triangles.size());
  std::vector<std::uint32_t> start(points.size() + 1, 0);
  for (std::size_t f = 0; f < triangles.size(); ++f) {
    const Triangle& t = triangles[f];
    normal[f] =
        detail::unit_or_zero(cross(points[t[1]] - points[t[0]], points[t[2]] - points[t[0]]));
    for (int k = 0; k < 3; ++k) {
      const Vec3 a = points[t[(k + 1) % 3]] - points[t[k]],
                 b = points[t[(k + 2) % 3]] - points[t[k]];
      angle[f][k] = std::atan2(norm(cross(a, b)), dot(a, b));
      ++start[t[k] + 1];
    }
  }
  for (std::size_t v = 0; v < points.size(); ++v) start[v + 1] += start[v];
  std::vector<std::pair<std::uint32_t, int>> around(start.back());  // (face, corner) per point
  std::vector<std::uint32_t> fill(start.begin(), start.end() - 1);
  for (std::uint32_t f = 0; f < triangles.size(); ++f)
    for (int k = 0; k < 3; ++k) around[fill[triangles[f][k]]++] = {f, k};
  const double same_side = std::cos(kCreaseDegrees * std::acos(-1.0) / 180);
  std::vector<std::array<Vec3, 3>> out(triangles.size());
  for (std::size_t f = 0; f < triangles.size(); ++f)
    for (int k = 0; k < 3; ++k) {
      const std::uint32_t v = triangles[f][k];
      Vec3 sum;
      for (std::uint32_t i = start[v]; i < start[v + 1]; ++i) {
        const auto [g, corner] = around[i];
        if (dot(normal[g], normal[f]) >= same_side) sum = sum + angle[g][corner] * normal[g];
      }
      out[f][k] = norm(sum) > 0 ? detail::unit_or_zero(sum) : normal[f];
    }
  return out;
}

// The point at barycentric l of the cubic point-normal triangle (Vlachos et al. 2001) through
// corners p with normals n: a smooth surface through the corners, tangent to their normals,
// which bulges where the polyhedron cuts a chord.
Vec3 point_normal_triangle(const std::array<Vec3, 3>& p, const std::array<Vec3, 3>& n,
                           std::array<double, 3> l) {
  // b[i][j]: the edge control point next to corner i towards corner j.
  Vec3 b[3][3], edges;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) {
      if (i == j) continue;
      b[i][j] = (1.0 / 3) * (2.0 * p[i] + p[j] - dot(p[j] - p[i], n[i]) * n[i]);
      edges = edges + b[i][j];
    }
  const Vec3 mean = (1.0 / 3) * (p[0] + p[1] + p[2]);
  const Vec3 centre = (1.0 / 6) * edges + 0.5 * ((1.0 / 6) * edges - mean);
  Vec3 x = 6 * l[0] * l[1] * l[2] * centre;
  for (int i = 0; i < 3; ++i) {
    x = x + l[i] * l[i] * l[i] * p[i];
    for (int j = 0; j < 3; ++j)
      if (j != i) x = x + 3 * l[i] * l[i] * l[j] * b[i][j];
  }
  return x;
}

// Where the tets were made from a surface (tetrahedralize()), the boundary samples from
// `first` on aim at that surface itself: each at the surface's nearest point to its
// point-normal target. The point-normal triangles only guess the surface between the tets'
// corners; where Mesh_3's triangles cut chords of a curved surface (facet_distance, the
// bounding box's diagonal / 300 by default) that guess fell short of it: bear's tets hold
// 1.8 % less than its surface, and a section near the top of a limb lost the limb's tip.
void aim_at_surface(const MeshIndex& surface, const Units& u, std::size_t first,
                    TetSamples& samples) {
  std::vector<Vec3> guess(samples.target.size() - first);
  for (std::size_t k = 0; k < guess.size(); ++k) {
    const auto& t = samples.target[first + k];
    guess[k] = u.centre + u.size * Vec3{t[0], t[1], t[2]};
  }
  const std::vector<Vec3> on_surface = closest_points(surface, guess);
  for (std::size_t k = 0; k < guess.size(); ++k) {
    const Vec3 x = (1 / u.size) * (on_surface[k] - u.centre);
    auto& t = samples.target[first + k];
    t[0] = x.x, t[1] = x.y, t[2] = x.z;
  }
}

TetSamples tet_samples(const TetMesh& mesh, const CubeMap& map, const Units& u,
                       const MeshIndex* surface) {
  TetSamples out;
  // The sample at Σ_k w_k corner_k of a tet or a triangle (its first n corners), in the cube
  // and in the fit's units.
  auto add = [&](const std::uint32_t* corners, int n, auto&& weight_of, double weight) {
    std::array<double, 3> uvw{};
    std::array<double, 4> target{};
    for (int k = 0; k < n; ++k) {
      const double w = weight_of(k);
      const Vec3 x = mesh.points[corners[k]];
      for (int c = 0; c < 3; ++c) uvw[c] += w * map.uvw[corners[k]][c];
      target[0] += w * (x.x - u.centre.x) / u.size;
      target[1] += w * (x.y - u.centre.y) / u.size;
      target[2] += w * (x.z - u.centre.z) / u.size;
      if (!mesh.material.empty()) target[3] += w * (mesh.material[corners[k]] - u.m0) / u.m_range;
    }
    // The harmonic map can fold interior points past the cube's faces (bear with tets refined
    // in its ears: v = −0.02); the spline has no value there, and the element's cubic pieces,
    // extrapolated, took values down to −1.8: the data step lost its partition-of-unity bound
    // and grew tenfold a step. Such a sample belongs to the face it left.
    for (double& x : uvw) x = std::clamp(x, 0.0, 1.0);
    out.uvw.push_back(uvw);
    out.weight.push_back(weight);
    out.target.push_back(target);
  };
  constexpr double a = 0.58541019662496845, b = 0.13819660112501051;
  for (const Tet& t : mesh.tets) {
    const Vec3 p0 = mesh.points[t[0]];
    const double volume = std::abs(dot(mesh.points[t[1]] - p0,
                                       cross(mesh.points[t[2]] - p0, mesh.points[t[3]] - p0))) /
                          (6 * u.size * u.size * u.size);
    if (!(volume > 0)) continue;
    for (int s = 0; s < 4; ++s)
      add(
          t.data(), 4, [&](int k) { return k == s ? a : b; }, volume / 4);
  }
  // The boundary, where sections and surfaces are cut: every boundary triangle (on a cube
  // face) is cut into kBoundarySplit² and each piece gets a 3-point rule (degree 2), the
  // whole weighted as a layer of kBoundaryLayer regular tets standing on it. The volume
  // samples alone let the spline cut in where the map squeezes the boundary (bear's sections
  // 0.7-5 % short of the tets, fandisk's edge 11 %; with these 0.2-2.2 % and 0.3-0.7 %,
  // docs/benchmarks.md §21). Four tets: one lost the area, sixteen the largest interior error
  // (bear: max 0.088 / 0.114 / 0.142 mm for 1 / 4 / 16). Split in 4: with 3 points alone the
  // spline dipped between them where the map squeezes the boundary (bear's ears: teeth in its
  // sections, vertex max 0.116 mm, 0.066 split in 4, no better in 9). Each point aims at the
  // smooth point-normal triangle over the triangle, not at the triangle, which cuts a chord
  // of the surface the tets were made from (a coarse ball's sections 2.0-2.9 % short, now
  // within 0.2 %: SolidSpline.BallSectionsFollowTheSphereNotItsChords).
  constexpr double kBoundaryLayer = 4;
  constexpr int kBoundarySplit = 2;
  constexpr double kRegularTet = 0.4387;  // a regular tet's volume / its face's area^1.5
  const std::size_t first_boundary_sample = out.uvw.size();
  const std::vector<Triangle> boundary = tet_boundary(mesh).triangles;
  const std::vector<std::array<Vec3, 3>> normals = corner_normals(mesh.points, boundary);
  for (std::size_t f = 0; f < boundary.size(); ++f) {
    const Triangle& t = boundary[f];
    const std::array<Vec3, 3> p = {mesh.points[t[0]], mesh.points[t[1]], mesh.points[t[2]]};
    const double area = 0.5 * norm(cross(p[1] - p[0], p[2] - p[0])) / (u.size * u.size);
    if (!(area > 0)) continue;
    constexpr int n = kBoundarySplit;  // pieces along a side
    const double weight = kBoundaryLayer * kRegularTet * std::pow(area, 1.5) / (3 * n * n);
    // The pieces of the barycentric grid (λ1, λ2 in steps of 1/n): upright (i, j), (i + 1, j),
    // (i, j + 1), and below the diagonal also the inverted (i + 1, j + 1), (i, j + 1), (i + 1, j).
    auto sample_piece = [&](const std::array<std::array<double, 2>, 3>& grid) {
      for (int s = 0; s < 3; ++s) {
        std::array<double, 3> bary{};  // at corners 0, 1, 2 of the triangle
        for (int k = 0; k < 3; ++k) {
          const double w = k == s ? 2.0 / 3 : 1.0 / 6;
          bary[1] += w * grid[k][0] / n;
          bary[2] += w * grid[k][1] / n;
        }
        bary[0] = 1 - bary[1] - bary[2];
        add(
            t.data(), 3, [&](int k) { return bary[k]; }, weight);
        const Vec3 x = point_normal_triangle(p, normals[f], bary);
        out.target.back()[0] = (x.x - u.centre.x) / u.size;
        out.target.back()[1] = (x.y - u.centre.y) / u.size;
        out.target.back()[2] = (x.z - u.centre.z) / u.size;
      }
    };
    for (int i = 0; i < n; ++i)
      for (int j = 0; i + j < n; ++j) {
        const double x = i, y = j;
        sample_piece({{{x, y}, {x + 1, y}, {x, y + 1}}});
        if (i + j + 1 < n) sample_piece({{{x + 1, y + 1}, {x, y + 1}, {x + 1, y}}});
      }
  }
  if (surface) aim_at_surface(*surface, u, first_boundary_sample, out);
  return out;
}

// The quadrature of one basis: the data samples sorted by element; 3 × 3 × 3 Gauss points of
// every element (element after element) for the regularisers; and 3 × 3 on the elements'
// faces that lie on the cube's faces, with the boundary normal there.
struct Quadrature {
  std::vector<std::uint32_t> data_start;  // samples of element e: data[data_start[e] ..]
  std::vector<std::uint32_t> data;        // TetSamples indices
  std::vector<std::uint32_t> data_element;
  std::vector<std::array<double, 3>> uvw;
  std::vector<double> weight;
  std::vector<std::array<double, 4>> target;  // I_G, I_M there (Newton steps' anchor only)
  // Face points of element e: [face_start[e], face_start[e + 1]).
  std::vector<std::uint32_t> face_start;
  std::vector<std::array<double, 3>> face_uvw;
  std::vector<double> face_weight;
  std::vector<Vec3> face_normal;   // n_I, outward
  std::vector<std::uint8_t> face;  // 2 · axis + side
};

// The outward normal of the boundary triangle of `tet` on cube face (axis, side), or zero.
Vec3 boundary_normal(const CubeLookup& lookup, std::uint32_t tet, int axis, int side) {
  const Tet& t = lookup.tets[tet];
  for (int skip = 0; skip < 4; ++skip) {
    std::array<std::uint32_t, 3> f{};
    for (int k = 0, n = 0; k < 4; ++k)
      if (k != skip) f[n++] = t[k];
    bool on = true;
    for (std::uint32_t v : f) on = on && lookup.uvw[v][axis] == side;
    if (!on) continue;
    Vec3 n =
        cross(lookup.points[f[1]] - lookup.points[f[0]], lookup.points[f[2]] - lookup.points[f[0]]);
    if (dot(n, lookup.points[t[skip]] - lookup.points[f[0]]) > 0) n = -1.0 * n;
    const double length = norm(n);
    return length > 0 ? (1 / length) * n : Vec3{};
  }
  return {};
}

Quadrature make_quadrature(const SplineBasis& basis, const CubeLookup& lookup,
                           const TetSamples& samples, const Units* anchor) {
  const std::size_t elements = basis.elements.size();
  Quadrature q;
  q.data_element.resize(samples.uvw.size());
  detail::parallel_for(samples.uvw.size(), 256, [&](std::size_t begin, std::size_t end) {
    for (std::size_t k = begin; k < end; ++k)
      q.data_element[k] = static_cast<std::uint32_t>(basis_element_at(basis, samples.uvw[k]));
  });
  q.data_start.assign(elements + 1, 0);
  for (std::uint32_t e : q.data_element) ++q.data_start[e + 1];
  for (std::size_t e = 0; e < elements; ++e) q.data_start[e + 1] += q.data_start[e];
  q.data.resize(samples.uvw.size());
  std::vector<std::uint32_t> fill(q.data_start.begin(), q.data_start.end() - 1);
  for (std::uint32_t k = 0; k < samples.uvw.size(); ++k) q.data[fill[q.data_element[k]]++] = k;
  q.uvw.resize(elements * kCellSamples);
  q.weight.resize(q.uvw.size());
  for (std::size_t e = 0; e < elements; ++e) {
    const OctreeCell& cell = basis.elements[e];
    const double h = 1.0 / basis.spans[cell.level];
    for (int k = 0; k < kCellSamples; ++k) {
      const std::size_t at = e * kCellSamples + k;
      const int g[3] = {k % 3, k / 3 % 3, k / 9};
      for (int a = 0; a < 3; ++a) q.uvw[at][a] = (cell.index[a] + kNode[g[a]]) * h;
      q.weight[at] = kWeight[g[0]] * kWeight[g[1]] * kWeight[g[2]] * h * h * h;
    }
  }
  if (anchor) {
    q.target.resize(q.uvw.size());
    detail::parallel_for(q.uvw.size(), 256, [&](std::size_t begin, std::size_t end) {
      for (std::size_t k = begin; k < end; ++k) q.target[k] = target_at(lookup, *anchor, q.uvw[k]);
    });
  }
  q.face_start.push_back(0);
  for (std::size_t e = 0; e < elements; ++e) {
    const OctreeCell& cell = basis.elements[e];
    const std::uint32_t last = basis.spans[cell.level] - 1;
    const double h = 1.0 / basis.spans[cell.level];
    for (int axis = 0; axis < 3; ++axis)
      for (int side = 0; side < 2; ++side) {
        if (cell.index[axis] != (side ? last : 0)) continue;
        const int b = (axis + 1) % 3, c = (axis + 2) % 3;
        for (int k = 0; k < 9; ++k) {
          std::array<double, 3> p{};
          p[axis] = side;
          p[b] = (cell.index[b] + kNode[k % 3]) * h;
          p[c] = (cell.index[c] + kNode[k / 3]) * h;
          const Vec3 n = boundary_normal(lookup, cube_lookup(lookup, p).tet, axis, side);
          if (n == Vec3{}) continue;  // the point's tet only touches the face: no normal
          q.face_uvw.push_back(p);
          q.face_weight.push_back(kWeight[k % 3] * kWeight[k / 3] * h * h);
          q.face_normal.push_back(n);
          q.face.push_back(static_cast<std::uint8_t>(2 * axis + side));
        }
      }
    q.face_start.push_back(static_cast<std::uint32_t>(q.face_uvw.size()));
  }
  return q;
}

// F and its derivatives at one point from an element's local coefficients (`local`, 64 × Dim).
template <int Dim>
struct LocalValue {
  std::array<double, Dim> f{};
  std::array<std::array<double, Dim>, 3> first{};
  std::array<double, 6> second{};  // Dim 1 only

  LocalValue(const LocalBasis& b, const double* local, int derivatives) {
    for (int k = 0; k < 64; ++k)
      for (int d = 0; d < Dim; ++d) {
        const double c = local[k * Dim + d];
        f[d] += b.value[k] * c;
        if (derivatives < 1) continue;
        for (int a = 0; a < 3; ++a) first[a][d] += b.first[a][k] * c;
        if (Dim == 1 && derivatives > 1)
          for (int t = 0; t < 6; ++t) second[t] += b.second[t][k] * c;
      }
  }
};

// The fractions of an element where det J_G is watched: its Gauss points, the finer check's
// 5³ inside it, the Gauss points of its eight children (where a refined round's start must
// not fold), and the finer check's 4³ reaching its faces (where the cube's boundary is: with
// the first three alone, bear's G still folded at 1,151 points of the cube's faces, and its
// slices turned 2,388 triangles over; with them, 0 and 469), and the eighths on elements along
// the cube's edges (finer_check()). A grid is n of them, the same along each axis (point
// i + n j + n² k).
constexpr double kWatchedFractions[27] = {
    // the Gauss points
    kNode[0], kNode[1], kNode[2],
    // the finer check's
    0.1, 0.3, 0.5, 0.7, 0.9,
    // the children's Gauss points
    kNode[0] / 2, kNode[1] / 2, kNode[2] / 2, (1 + kNode[0]) / 2, (1 + kNode[1]) / 2,
    (1 + kNode[2]) / 2,
    // on the faces
    0.0, 1.0 / 3, 2.0 / 3, 1.0,
    // the eighths
    0.0, 1.0 / 8, 2.0 / 8, 3.0 / 8, 4.0 / 8, 5.0 / 8, 6.0 / 8, 7.0 / 8, 1.0};
using Grid = detail::ElementGrid;
constexpr Grid kGaussGrid{kWatchedFractions, 0, 3}, kFineGrid{kWatchedFractions, 3, 5},
    kChildGrid{kWatchedFractions, 8, 6}, kFaceGrid{kWatchedFractions, 14, 4},
    kEdgeGrid{kWatchedFractions, 18, 9};
constexpr Grid kFinerCheck[3] = {kFineGrid, kFaceGrid, kEdgeGrid};

// The finer check's grids on element e. Along the cube's edges the eighths are watched too: a
// smooth surface's map must flatten there (the cube's two faces meet at 90°, their images at
// about 180°), so det J_G runs near 0 and dips below it between coarser grids' points (bear
// at Dörfler's share 0.5: 7 of the 10 elements the bound found folded touched an edge, each
// folded at one of its eighths; with them watched, 0).
std::span<const Grid> finer_check(const SplineBasis& basis, std::size_t e) {
  const OctreeCell& cell = basis.elements[e];
  const std::uint32_t last = basis.spans[cell.level] - 1;
  int ends = 0;
  for (int a = 0; a < 3; ++a) ends += cell.index[a] == 0 || cell.index[a] == last;
  return {kFinerCheck, ends >= 2 ? 3u : 2u};
}
int finer_samples(const SplineBasis& basis, std::size_t e) {
  int n = 0;
  for (const Grid& grid : finer_check(basis, e)) n += grid.n * grid.n * grid.n;
  return n;
}

// The 1D B-splines and their slopes at the watched fractions (one table serves every check
// of every step).
struct WatchedAxes : detail::SpanTable {
  explicit WatchedAxes(const SplineBasis& basis)
      : SpanTable(basis, kWatchedFractions, static_cast<int>(std::size(kWatchedFractions))) {}
};
using detail::grid_determinants;

// What Newton steps keep between steps, shared by G and M (one basis, one round): the local
// B-splines at every data sample (64 each, quadrature.data's order) and the Hessian on the
// rows (its shape the basis's, its values each step's).
struct NewtonStorage {
  std::vector<double> sample_value;
  detail::RowMatrix matrix;
};

// A field F = Σ c_i φ_i of `Dim` components (3: G; 1: M) under fit on one basis.
template <int Dim>
struct FieldFit {
  const SplineBasis& basis;
  const Quadrature& quadrature;
  const TetSamples& samples;
  const Gather& gather_map;
  const SolidFitOptions& options;
  int target_offset;  // 0: x, y, z; 3: m
  std::vector<double>& c;
  NewtonStorage& shared;
  std::vector<double> element_error;   // per element, Σ w |r|² over its data (measure())
  std::vector<double> element_weight;  // per element, Σ w over its data (measure())
  // Per function, a Gershgorin bound of the regularisers' Hessian row (bound_stiffness()).
  std::vector<double> stiffness;
  std::size_t solve_iterations = 0;  // Newton steps' conjugate-gradient iterations
  std::size_t held = 0;              // functions whose step was held back (fold_free)
  WatchedAxes axes{basis};           // where det J_G is checked
  bool watch_children = true;        // hold_unfolded() watches the children's Gauss points
  // Per element, points where the fold certificate found det J_G ≤ 0 between the grids'
  // points (open_found_folds()): watched like theirs from then on.
  std::vector<std::vector<std::array<double, 3>>> found{};
  std::vector<char> dense{};  // per element, whether `found` holds a dense patch

  // The regularisers are stiff on fine elements (their Hessian grows as 1 / h): an explicit
  // step of ε is stable only while ε · Σ_j |H_ij| ≤ 1. This bounds Σ_j |H_ij| per function
  // (first derivatives, and second for M's thin plate, of the local B-splines; |G_a|² at the
  // current G for the area term), so that step() can cap the regulariser's step where it
  // would not be stable. It binds only deep in the octree.
  void bound_stiffness(const Gather& gather_map) {
    const std::vector<double> rows = row_coefficients(basis, c, Dim);
    const std::size_t elements = basis.elements.size();
    std::vector<double> slot(elements * 64, 0.0);
    detail::parallel_for(elements, 16, [&](std::size_t begin, std::size_t end) {
      for (std::size_t e = begin; e < end; ++e) {
        const auto local = local_coefficients(rows, e);
        for (int s = 0; s < kCellSamples; ++s) {
          const std::size_t at = e * kCellSamples + s;
          const LocalBasis b = local_basis(basis, e, quadrature.uvw[at], Dim == 1 ? 2 : 1);
          const LocalValue<Dim> x(b, local.data(), 1);
          double grad2 = 0;
          for (int a = 0; a < 3; ++a)
            for (int d = 0; d < Dim; ++d) grad2 += x.first[a][d] * x.first[a][d];
          std::array<double, 3> sum1{};
          std::array<double, 6> sum2{};
          for (int k = 0; k < 64; ++k) {
            for (int a = 0; a < 3; ++a) sum1[a] += std::abs(b.first[a][k]);
            for (int t = 0; t < 6; ++t) sum2[t] += std::abs(b.second[t][k]);
          }
          const double first = 2 * (options.lambda1 + (Dim == 3 ? 2 * options.lambda2 * grad2 : 0));
          for (int k = 0; k < 64; ++k) {
            double h = 0;
            for (int a = 0; a < 3; ++a) h += first * std::abs(b.first[a][k]) * sum1[a];
            if constexpr (Dim == 1)
              for (int t = 0; t < 6; ++t)
                h += 2 * options.lambda2 * (t < 3 ? 1 : 2) * std::abs(b.second[t][k]) * sum2[t];
            slot[e * 64 + k] += quadrature.weight[at] * h;
          }
        }
      }
    });
    stiffness = gather(basis, gather_map, slot, 1);
  }

  std::array<double, 64 * Dim> local_coefficients(const std::vector<double>& rows,
                                                  std::size_t e) const {
    std::array<double, 64 * Dim> local{};
    for (int k = 0; k < 64; ++k)
      for (int d = 0; d < Dim; ++d)
        local[k * Dim + d] = rows[std::size_t(basis.element_rows[64 * e + k]) * Dim + d];
    return local;
  }

  // The data term's L2 norm, ‖I − F‖ = (Σ_k w_k |r_k|²)^½, and each element's share of its
  // square and of the weights.
  double measure() {
    const std::vector<double> rows = row_coefficients(basis, c, Dim);
    const std::size_t elements = basis.elements.size();
    element_error.assign(elements, 0.0);
    element_weight.assign(elements, 0.0);
    detail::parallel_for(elements, 64, [&](std::size_t begin, std::size_t end) {
      for (std::size_t e = begin; e < end; ++e) {
        const auto local = local_coefficients(rows, e);
        for (std::uint32_t i = quadrature.data_start[e]; i < quadrature.data_start[e + 1]; ++i) {
          const std::uint32_t k = quadrature.data[i];
          const LocalValue<Dim> at(local_basis(basis, e, samples.uvw[k], 0), local.data(), 0);
          double r2 = 0;
          for (int d = 0; d < Dim; ++d) {
            const double r = samples.target[k][target_offset + d] - at.f[d];
            r2 += r * r;
          }
          element_error[e] += samples.weight[k] * r2;
          element_weight[e] += samples.weight[k];
        }
      }
    });
    double total = 0;
    for (double x : element_error) total += x;
    return std::sqrt(total);
  }

  // J_G from an element's local B-splines at a point and its local coefficients:
  // [r][a] = ∂_a G_r.
  static detail::Matrix3 jacobian_of(const LocalBasis& b,
                                     const std::array<double, 64 * Dim>& local) requires(Dim == 3) {
    const LocalValue<Dim> at(b, local.data(), 1);
    detail::Matrix3 j;
    for (int r = 0; r < 3; ++r)
      for (int a = 0; a < 3; ++a) j[3 * r + a] = at.first[a][r];
    return j;
  }

  detail::Matrix3 jacobian_at(const std::array<double, 64 * Dim>& local, std::size_t e,
                              std::array<double, 3> uvw) const requires(Dim == 3) {
    return jacobian_of(local_basis(basis, e, uvw, 1), local);
  }

  // Per element, its Gauss points where det J_G ≤ 0 (and, `fine`, the finer check's);
  // `least`, when given, gets the point where det J_G is least.
  std::vector<std::uint32_t> folds_per_element(std::array<double, 3>* least = nullptr,
                                               bool fine = false) const requires(Dim == 3) {
    const std::vector<double> rows = row_coefficients(basis, c, Dim);
    std::vector<std::uint32_t> count(basis.elements.size(), 0);
    std::vector<std::pair<double, std::array<double, 3>>> lowest(count.size());
    detail::parallel_for(count.size(), 64, [&](std::size_t begin, std::size_t end) {
      for (std::size_t e = begin; e < end; ++e) {
        const auto local = local_coefficients(rows, e);
        lowest[e].first = std::numeric_limits<double>::infinity();
        const auto visit = [&](const Grid& grid) {
          grid_determinants(basis, axes, e, local.data(), grid, [&](int p, double det) {
            count[e] += det <= 0;
            if (det < lowest[e].first)
              lowest[e] = {det, grid.point(basis.elements[e], basis.spans, p)};
          });
        };
        visit(kGaussGrid);
        if (fine)
          for (const Grid& grid : finer_check(basis, e)) visit(grid);
      }
    });
    if (least)
      *least = std::min_element(lowest.begin(), lowest.end(), [](const auto& a, const auto& b) {
                 return a.first < b.first;
               })->second;
    return count;
  }

  // The fold certificate's verdicts on G now: per element 1 where it finds a fold, whose
  // point joins `found`.
  std::vector<std::uint32_t> bound_folds() requires(Dim == 3) {
    const std::vector<detail::ElementVerdict> verdicts =
        detail::element_verdicts(basis, row_coefficients(basis, c, Dim), detail::kCertificateDepth);
    found.resize(basis.elements.size());
    std::vector<std::uint32_t> count(verdicts.size(), 0);
    for (std::size_t e = 0; e < verdicts.size(); ++e)
      if (verdicts[e].kind == detail::ElementVerdict::Kind::folded)
        found[e].push_back(verdicts[e].uvw), count[e] = 1;
    return count;
  }

  // Per element, its points `found` by the fold certificate where det J_G ≤ 0 now.
  std::vector<std::uint32_t> found_folded() const requires(Dim == 3) {
    std::vector<std::uint32_t> count(basis.elements.size(), 0);
    if (found.empty()) return count;
    const std::vector<double> rows = row_coefficients(basis, c, Dim);
    detail::parallel_for(count.size(), 64, [&](std::size_t begin, std::size_t end) {
      for (std::size_t e = begin; e < end; ++e) {
        if (found[e].empty()) continue;
        const auto local = local_coefficients(rows, e);
        for (const std::array<double, 3>& uvw : found[e])
          count[e] += detail::determinant(jacobian_at(local, e, uvw)) <= 0;
      }
    });
    return count;
  }

  // Points of the finer check (5³ evenly inside every element, 4³ reaching its faces, the
  // eighths along the cube's edges) where det J_G ≤ 0: folds between the Gauss points and on
  // the elements' faces.
  std::size_t fine_folds() const requires(Dim == 3) {
    const std::vector<double> rows = row_coefficients(basis, c, Dim);
    std::vector<std::uint32_t> count(basis.elements.size(), 0);
    detail::parallel_for(count.size(), 64, [&](std::size_t begin, std::size_t end) {
      for (std::size_t e = begin; e < end; ++e) {
        const auto local = local_coefficients(rows, e);
        for (const Grid& grid : finer_check(basis, e))
          grid_determinants(basis, axes, e, local.data(), grid,
                            [&](int, double det) { count[e] += det <= 0; });
      }
    });
    std::size_t total = 0;
    for (std::uint32_t n : count) total += n;
    return total;
  }

  // A watched point where det J_G ≤ 0, and det J_G there before the step that folded it;
  // visit_linearised() fills in det J_G and its gradient in c (per function over the element).
  struct Fold {
    std::array<double, 3> uvw;
    double det_was;
    double det = 0;
    std::vector<std::pair<std::uint32_t, std::array<double, 3>>> gradient{};
  };

  // Per element (those `dirty`), the watched points (Gauss, finer check's, those `found` and,
  // while watch_children, the children's Gauss points) where det J_G ≤ 0 on `rows`; with
  // `was`, only those where it was > 0 on it; with `floor` (and no `was`), those where
  // det J_G < floor(uvw), folded or not.
  std::vector<std::vector<Fold>> folded_points(
      const std::vector<double>& rows, const std::vector<double>* was,
      const std::vector<char>& dirty,
      const std::function<double(std::array<double, 3>)>* floor = nullptr) const
      requires(Dim == 3) {
    std::vector<std::vector<Fold>> folded(basis.elements.size());
    detail::parallel_for(folded.size(), 64, [&](std::size_t begin, std::size_t end) {
      for (std::size_t e = begin; e < end; ++e) {
        if (!dirty[e]) continue;
        const auto now = local_coefficients(rows, e);
        const auto watch = [&](const Grid& grid) {
          if (floor) {
            grid_determinants(basis, axes, e, now.data(), grid, [&](int p, double det) {
              const std::array<double, 3> uvw = grid.point(basis.elements[e], basis.spans, p);
              if (det < (*floor)(uvw)) folded[e].push_back({uvw, 1.0});
            });
            return;
          }
          bool any = false;
          grid_determinants(basis, axes, e, now.data(), grid,
                            [&](int, double det) { any = any || det <= 0; });
          if (!any) return;
          std::vector<double> det_was(grid.n * grid.n * grid.n, 1.0);
          if (was) {
            const auto then = local_coefficients(*was, e);
            grid_determinants(basis, axes, e, then.data(), grid,
                              [&](int p, double det) { det_was[p] = det; });
          }
          grid_determinants(basis, axes, e, now.data(), grid, [&](int p, double det) {
            if (det <= 0 && det_was[p] > 0)
              folded[e].push_back({grid.point(basis.elements[e], basis.spans, p), det_was[p]});
          });
        };
        watch(kGaussGrid);
        if (watch_children) watch(kChildGrid);
        for (const Grid& grid : finer_check(basis, e)) watch(grid);
        if (found.empty()) continue;
        for (const std::array<double, 3>& uvw : found[e]) {
          if (floor) {
            if (detail::determinant(jacobian_at(now, e, uvw)) < (*floor)(uvw))
              folded[e].push_back({uvw, 1.0});
            continue;
          }
          if (detail::determinant(jacobian_at(now, e, uvw)) > 0) continue;
          const double det_was =
              was ? detail::determinant(jacobian_at(local_coefficients(*was, e), e, uvw)) : 1.0;
          if (det_was > 0) folded[e].push_back({uvw, det_was});
        }
      }
    });
    return folded;
  }

  // Visits every fold, element by element, with det J_G on `rows` and ∂ det / ∂c_f for every
  // function f over its element: Σ_k w_kf cof(J_G) ∇φ_k, summed per function (one may name
  // several rows). The gradients are made in parallel, a batch of about 4,096 folds at a
  // time (a step of fandisk's folds 50,000 points at first: 3 times the fit's memory when all
  // were held at once), and visited point after point, as the projections need.
  template <class Visit>
  void visit_linearised(std::vector<std::vector<Fold>>& folded, const std::vector<double>& rows,
                        const Visit& visit) const requires(Dim == 3) {
    constexpr std::size_t kBatch = 4096;
    for (std::size_t first = 0; first < folded.size();) {
      std::size_t last = first, count = 0;
      while (last < folded.size() && count < kBatch) count += folded[last++].size();
      detail::parallel_for(last - first, 4, [&](std::size_t begin, std::size_t end) {
        std::vector<std::int32_t> slot;  // per function, its place in a gradient, or −1
        for (std::size_t e = first + begin; e < first + end; ++e) {
          if (folded[e].empty()) continue;
          if (slot.empty()) slot.assign(basis.functions.size(), -1);
          const auto local = local_coefficients(rows, e);
          for (Fold& fold : folded[e]) {
            const LocalBasis b = local_basis(basis, e, fold.uvw, 1);
            const detail::Matrix3 jg = jacobian_of(b, local);
            const detail::Matrix3 cof = detail::cofactor(jg);
            fold.det = detail::determinant(jg);
            auto& out = fold.gradient;
            detail::for_each_term(basis, e, [&](int k, std::uint32_t f, double w) {
              if (w == 0) return;
              if (slot[f] < 0) {
                slot[f] = static_cast<std::int32_t>(out.size());
                out.push_back({f, {}});
              }
              std::array<double, 3>& d = out[slot[f]].second;
              for (int r = 0; r < 3; ++r)
                for (int a = 0; a < 3; ++a) d[r] += w * cof[3 * r + a] * b.first[a][k];
            });
            for (const auto& [f, d] : out) slot[f] = -1;
          }
        }
      });
      for (std::size_t e = first; e < last; ++e)
        for (Fold& fold : folded[e]) {
          visit(fold);
          std::vector<std::pair<std::uint32_t, std::array<double, 3>>>().swap(fold.gradient);
        }
      first = last;
    }
  }

  // Marks the elements under the functions `moved` names (and clears it).
  void mark_reached(std::vector<char>& moved, std::vector<char>& dirty) const {
    for (std::size_t f = 0; f < moved.size(); ++f) {
      if (!moved[f]) continue;
      moved[f] = 0;
      for (std::uint32_t i = gather_map.function_start[f]; i < gather_map.function_start[f + 1];
           ++i) {
        const std::uint32_t r = gather_map.function_row[i];
        for (std::uint32_t k = gather_map.row_start[r]; k < gather_map.row_start[r + 1]; ++k)
          dirty[gather_map.row_slot[k] / 64] = 1;
      }
    }
  }

  // After a step from `before` to c: where the step folds G at a watched point (det J_G ≤ 0
  // where it was > 0), the step slides along the fold rather than into it: the part of it
  // that lowers det J_G there, to first order, is taken out until det J_G keeps half its value
  // (a projection onto that half-space, point after point). What the first order misses is
  // tried again; after kSlides tries, the functions whose step lowers det J_G there take half
  // of it, and none on the last try, so that a G fold-free at its watched points stays so
  // whatever the step. (Holding back every function over a folded element cost bear's one
  // round 7 points of RS, sliding 1.) Returns the functions whose step changed.
  std::size_t hold_unfolded(const std::vector<double>& before) requires(Dim == 3) {
    const std::vector<double> rows_before = row_coefficients(basis, before, Dim);
    std::vector<double> share(basis.functions.size(), 1.0);
    std::vector<char> changed(share.size(), 0), moved(share.size(), 0);
    // The elements to check: all after the step, then those still folded or under a function
    // the last try moved.
    std::vector<char> dirty(basis.elements.size(), 1);
    constexpr int kSlides = 4, kHalvings = 6;
    for (int attempt = 0;; ++attempt) {
      std::vector<std::vector<Fold>> folded =
          folded_points(row_coefficients(basis, c, Dim), &rows_before, dirty);
      const bool slide = attempt < kSlides;
      std::vector<char> marked(share.size(), 0);
      bool worse = false;
      visit_linearised(folded, rows_before, [&](const Fold& fold) {  // before the step
        worse = true;
        const auto& gradient = fold.gradient;
        if (slide) {
          double change = 0, norm = 0;  // first-order change of det J_G, |∂ det / ∂c|²
          for (const auto& [f, d] : gradient)
            for (int r = 0; r < 3; ++r) {
              change += d[r] * (c[3 * f + r] - before[3 * f + r]);
              norm += d[r] * d[r];
            }
          const double deficit = 0.5 * fold.det_was - (fold.det_was + change);
          if (!(deficit > 0) || !(norm > 0)) return;
          for (const auto& [f, d] : gradient) {
            for (int r = 0; r < 3; ++r) c[3 * f + r] += deficit / norm * d[r];
            changed[f] = moved[f] = 1;
          }
          return;
        }
        bool lowered = false;
        for (const auto& [f, d] : gradient) {
          if (share[f] == 0) continue;
          double change = 0;
          for (int r = 0; r < 3; ++r) change += d[r] * (c[3 * f + r] - before[3 * f + r]);
          if (change < 0) marked[f] = 1, lowered = true;
        }
        // Second order only: every function still moving there.
        if (!lowered)
          for (const auto& [f, d] : gradient)
            if (share[f] > 0) marked[f] = 1;
      });
      // Ends: an element whose functions all take none of the step is as it was, and each try
      // after the slides holds back a function still moving over every folded point.
      if (!worse) break;
      const int halving = attempt - kSlides;
      for (std::size_t f = 0; f < share.size() && !slide; ++f) {
        if (!marked[f]) continue;
        changed[f] = moved[f] = 1;
        const double factor = halving + 1 < kHalvings ? 0.5 : 0;
        share[f] *= factor;
        for (int d = 0; d < 3; ++d)
          c[3 * f + d] = before[3 * f + d] + factor * (c[3 * f + d] - before[3 * f + d]);
      }
      // A folded element stays to check even if no function over it moved (its fold was
      // second order).
      for (std::size_t e = 0; e < dirty.size(); ++e) dirty[e] = !folded[e].empty();
      mark_reached(moved, dirty);
    }
    std::size_t held = 0;
    for (char x : changed) held += x;
    return held;
  }

  // Opens the folds G starts a round with (det J_G ≤ 0 at a watched point: the Greville
  // start's, or a refined G's at the finer elements' points) without folding it elsewhere:
  // each folded point's det J_G is pushed, to first order, up to `target(uvw)` (a projection,
  // point after point), and hold_unfolded() keeps the push from folding another point.
  // With `lift`, folds left after those sweeps get up to `sweeps` more, each pushing every
  // watched point under its target in the elements the folds' functions reach, folded or
  // not: a fold whose neighbours sit just above 0 cannot open alone, as the hold keeps each
  // neighbour from folding in its place (the upper femur's uniform 40³, a face v = 0: its
  // last found folds stayed 3 → 2, 7 → 7, 10 → 10 over ten sweeps; lifted, each opened).
  // Returns the watched points folded at first, and after the sweeps.
  std::pair<std::size_t, std::size_t> open_folds(
      const std::function<double(std::array<double, 3>)>& target, int sweeps,
      bool lift = false) requires(Dim == 3) {
    std::size_t first = 0;
    std::vector<char> all(basis.elements.size(), 1);
    for (int sweep = 0;; ++sweep) {
      const std::vector<double> rows = row_coefficients(basis, c, Dim);
      std::vector<std::vector<Fold>> folded = folded_points(rows, nullptr, all);
      std::size_t left = 0;
      for (const auto& points : folded) left += points.size();
      if (sweep == 0) first = left;
      if (left == 0 || sweep == (lift ? 2 * sweeps : sweeps)) return {first, left};
      if (sweep >= sweeps) {
        std::vector<char> moved(basis.functions.size(), 0), region(folded.size(), 0);
        for (std::size_t e = 0; e < folded.size(); ++e)
          if (!folded[e].empty())
            detail::for_each_term(basis, e, [&](int, std::uint32_t f, double w) {
              if (w != 0) moved[f] = 1;
            });
        mark_reached(moved, region);
        folded = folded_points(rows, nullptr, region, &target);
      }
      const std::vector<double> before = c;
      visit_linearised(folded, rows, [&](const Fold& fold) {
        // The deficit counts what the points pushed before moved here: pushed each by its own
        // deficit alone, points sharing functions added up their pushes, and the lower
        // femur's 128,641 folded start points became 2.9 M after one sweep (a fit of over an
        // hour; with this, 0 after 6 sweeps).
        double change = 0, norm = 0;  // first-order change of det J_G so far, |∂ det / ∂c|²
        for (const auto& [f, d] : fold.gradient)
          for (int r = 0; r < 3; ++r) {
            change += d[r] * (c[3 * f + r] - before[3 * f + r]);
            norm += d[r] * d[r];
          }
        const double deficit = target(fold.uvw) - (fold.det + change);
        if (!(deficit > 0) || !(norm > 0)) return;
        for (const auto& [f, d] : fold.gradient)
          for (int r = 0; r < 3; ++r) c[3 * f + r] += deficit / norm * d[r];
      });
      held += hold_unfolded(before);
    }
  }

  // Watches element e densely around `uvw`: a 9³ grid over half its side, centred there
  // (moved inside the element where it would reach past it), joins found[e].
  void add_patch(std::size_t e, std::array<double, 3> uvw) requires(Dim == 3) {
    const OctreeCell& cell = basis.elements[e];
    const double h = 1.0 / basis.spans[cell.level], side = h / 2;
    std::array<double, 3> from;
    for (int a = 0; a < 3; ++a) {
      const double lo = cell.index[a] * h;
      from[a] = std::clamp(uvw[a] - side / 2, lo, lo + h - side);
    }
    for (int k = 0; k < 9; ++k)
      for (int j = 0; j < 9; ++j)
        for (int i = 0; i < 9; ++i)
          found[e].push_back(
              {from[0] + side * i / 8, from[1] + side * j / 8, from[2] + side * k / 8});
  }

  // The folds the fold certificate finds between the grids' points (element_verdicts(): the
  // least corner seen where det J_G ≤ 0, one an element), watched from then on and pushed
  // open like a round's start's (lifted: open_folds()), then the certificate again, up to
  // `passes` times. A fold opened at its point may surface again beside it: an element
  // takes up to kFoundPerElement points, and from its kDenseAfter-th on a dense patch
  // around it. Returns the points found (the certificate's, not the patches').
  std::size_t open_found_folds(const std::function<double(std::array<double, 3>)>& target,
                               int sweeps, int passes,
                               const std::function<void()>& poll) requires(Dim == 3) {
    const int depth = detail::kCertificateDepth;
    // An element whose fold outlives so many pushes at its points is left (bear: one at a
    // corner of the cube, pushed from a pass's fifth to its sixteenth to no end, before the
    // lift). At 4 points (and 12 passes), without the lift and the patches, the upper
    // femur's uniform 40³ kept 2 elements folded and its THB (the seed's marking) 10, each
    // fold found again beside its last point on a face of the cube; at 16 (and 40) with the
    // lift, 0 and 4; with the patches too, 1 (on a cube edge) and 0 (docs/benchmarks.md §21b,
    // part 17: which elements should get a patch is not settled).
    constexpr std::size_t kFoundPerElement = 16;
    constexpr std::size_t kDenseAfter = 4, kDense = 729;  // the patch: 9³ points
    found.resize(basis.elements.size());
    dense.resize(basis.elements.size(), 0);
    std::size_t count = 0;
    for (int pass = 0; pass < passes; ++pass) {
      poll();  // a pass takes seconds on a large G: Ctrl-C is heard between them
      const std::vector<detail::ElementVerdict> verdicts =
          detail::element_verdicts(basis, row_coefficients(basis, c, Dim), depth);
      std::size_t added = 0;
      for (std::size_t e = 0; e < verdicts.size(); ++e) {
        if (verdicts[e].kind != detail::ElementVerdict::Kind::folded ||
            found[e].size() >= kFoundPerElement + (dense[e] ? kDense : 0))
          continue;
        found[e].push_back(verdicts[e].uvw), ++added;
        // A fold found again and again beside its last points: watch the region around it.
        if (found[e].size() >= kDenseAfter && !dense[e])
          dense[e] = 1, add_patch(e, verdicts[e].uvw);
      }
      if (added == 0) break;
      count += added;
      open_folds(target, sweeps, true);
    }
    return count;
  }

  // One Euler step.
  void step() {
    const std::vector<double> rows = row_coefficients(basis, c, Dim);
    const std::size_t elements = basis.elements.size();
    std::vector<double> slot_data(elements * 64 * Dim, 0.0), slot_smooth(slot_data.size(), 0.0);
    std::vector<double> slot_mass(elements * 64, 0.0);
    detail::parallel_for(elements, 16, [&](std::size_t begin, std::size_t end) {
      for (std::size_t e = begin; e < end; ++e) {
        const auto local = local_coefficients(rows, e);
        data_forces(e, local, slot_data.data() + e * 64 * Dim, slot_mass.data() + e * 64);
        smoothing_gradient(e, local, slot_smooth.data() + e * 64 * Dim);
        if constexpr (Dim == 3) boundary_gradient(e, local, slot_smooth.data() + e * 64 * Dim);
      }
    });
    // The seed's step: the data term normalised per function (R_i) by its own weights
    // Σ_k w_k g_k φ_i(x_k), so that it moves each control value by a weighted mean of its
    // residuals; the regularisers' exact gradients as they are, their step capped where it
    // would not be stable. (Normalised by Σ_k w_k φ_i(x_k) alone, the step shrank by g where
    // the map squeezes the solid, |∇G| large and g ≈ 1/|∇G|: there the step was 2εg of a full
    // one, and bear's material RS stopped at 40 %; 58 % with this alone, docs/method.md step 8.)
    const std::vector<double> data = gather(basis, gather_map, slot_data, Dim);
    const std::vector<double> smooth = gather(basis, gather_map, slot_smooth, Dim);
    const std::vector<double> mass = gather(basis, gather_map, slot_mass, 1);
    for (std::size_t f = 0; f < basis.functions.size(); ++f) {
      const double cap = std::max(1.0, options.step * stiffness[f]);
      for (int d = 0; d < Dim; ++d)
        c[f * Dim + d] += options.step * ((mass[f] > 0 ? data[f * Dim + d] / mass[f] : 0) -
                                          smooth[f * Dim + d] / cap);
    }
  }

  // One damped Newton step (SolidFitMethod::Newton): g, and the area term's stiffness per
  // element, frozen at c; the gradient exact; K δ = −∇E by conjugate gradients, K the energy's
  // Hessian with g frozen (the area term's replaced by its isotropic bound 2|G_b|² I per
  // direction, element by element, which keeps K positive where the exact one need not be);
  // then halved until E falls. With `hold`, each trial step is held fold-free
  // (hold_unfolded()) before its E is measured, so the step taken is one that lowers E as
  // held: held after the search, a step that lowered E could rise above it, and on the upper
  // femur's uniform 40³ G's RS fell from 43.7 % to −572 % in 50 steps (with the hold inside:
  // 55.7 %, docs/benchmarks.md §21b part 16).
  // `between` runs within the solve (iterate() reports the step's progress again there, so
  // that a cancel is honoured within a conjugate-gradient iteration, not after the step).
  void newton_step(const std::function<void()>& between, bool hold) {
    const std::vector<double> rows = row_coefficients(basis, c, Dim);
    const std::size_t elements = basis.elements.size();
    std::vector<double>& sample_value = shared.sample_value;
    if (sample_value.empty()) {
      sample_value.resize(quadrature.data.size() * 64);
      detail::parallel_for(elements, 16, [&](std::size_t begin, std::size_t end) {
        for (std::size_t e = begin; e < end; ++e)
          for (std::uint32_t i = quadrature.data_start[e]; i < quadrature.data_start[e + 1]; ++i) {
            const LocalBasis b = local_basis(basis, e, samples.uvw[quadrature.data[i]], 0);
            std::copy(b.value.begin(), b.value.end(), sample_value.begin() + std::size_t(i) * 64);
          }
      });
    }
    // The data term per control point, kDataWeight · Σ w g |r|² · n / Σ w. The seed normalises
    // each function's data force by its own weights (R_i, the Euler step) and leaves the
    // regularisers' as they are, so its λ weighs them against a mean residual: scaled by n / Σ w
    // alone, the energy's minimum is the seed's fixed point where the data are spread evenly.
    // Unscaled, λ = 10⁻³ outweighed the data a hundredfold and the minimum shrank G. The seed's
    // steps stop long before that fixed point, so its λ never bites in full: at it, bear's M
    // fitted worse than the Euler steps (RS 22 % against 39 %, one round), and 100 times the
    // data's weight gave 38 % (docs/benchmarks.md §21).
    double total_weight = 0;
    for (double w : samples.weight) total_weight += w;
    const double data_scale = kDataWeight * double(basis.functions.size()) / total_weight;
    // The anchor: every element's Gauss points fit the tets' map too, with kAnchor of the
    // data's total weight spread by parameter volume. Where the map squeezes the solid its
    // tets are large in the cube and a function's support may hold no sample: the
    // regularisers alone then decided its value, which a converged fit drove anywhere (uniform
    // 31³ on bear: G max error 1.5 mm); Euler steps had left it at its Greville start.
    const double anchor = kAnchor * kDataWeight * double(basis.functions.size());
    std::vector<double> mass(elements, 2 * anchor);
    std::vector<double> g(quadrature.data.size()), sample_weight(g.size());
    std::vector<std::array<double, 3>> first(elements);
    std::vector<double> plate(Dim == 1 ? elements : 0, 2 * options.lambda2);
    std::vector<double> slot_data(elements * 64 * Dim, 0.0), slot_smooth(slot_data.size(), 0.0);
    std::vector<double> slot_mass(elements * 64, 0.0);
    detail::parallel_for(elements, 16, [&](std::size_t begin, std::size_t end) {
      for (std::size_t e = begin; e < end; ++e) {
        const auto local = local_coefficients(rows, e);
        for (std::uint32_t i = quadrature.data_start[e]; i < quadrature.data_start[e + 1]; ++i) {
          const LocalBasis b = local_basis(basis, e, samples.uvw[quadrature.data[i]], 1);
          const LocalValue<Dim> at(b, local.data(), 1);
          double grad2 = 0;
          for (int d = 0; d < Dim; ++d)
            for (int a = 0; a < 3; ++a) grad2 += at.first[a][d] * at.first[a][d];
          g[i] = data_scale / std::sqrt(options.gamma + grad2);
          sample_weight[i] = 2 * samples.weight[quadrature.data[i]] * g[i];
          add_data_force(quadrature.data[i], g[i], b, at, slot_data.data() + e * 64 * Dim,
                         slot_mass.data() + e * 64);
        }
        first[e].fill(2 * options.lambda1);
        if constexpr (Dim == 3) {
          // The element's mean |G_a|², for the bound of the area term's Hessian.
          std::array<double, 3> mean{};
          double volume = 0;
          for (int s = 0; s < kCellSamples; ++s) {
            const std::size_t at = e * kCellSamples + s;
            const LocalValue<Dim> x(local_basis(basis, e, quadrature.uvw[at], 1), local.data(), 1);
            for (int a = 0; a < 3; ++a)
              for (int d = 0; d < 3; ++d)
                mean[a] += quadrature.weight[at] * x.first[a][d] * x.first[a][d];
            volume += quadrature.weight[at];
          }
          for (int a = 0; a < 3; ++a)
            first[e][a] += 2 * options.lambda2 * (mean[(a + 1) % 3] + mean[(a + 2) % 3]) / volume;
        }
        smoothing_gradient(e, local, slot_smooth.data() + e * 64 * Dim);
        if constexpr (Dim == 3) boundary_gradient(e, local, slot_smooth.data() + e * 64 * Dim);
        anchor_gradient(e, local, anchor, slot_smooth.data() + e * 64 * Dim);
      }
    });
    const std::vector<double> data = gather(basis, gather_map, slot_data, Dim);
    const std::vector<double> smooth = gather(basis, gather_map, slot_smooth, Dim);
    std::vector<double> downhill(data.size());  // −∇E
    for (std::size_t i = 0; i < data.size(); ++i) downhill[i] = data[i] - smooth[i];
    detail::RowMatrix& matrix = shared.matrix;
    if (matrix.value.empty()) matrix = detail::row_matrix(basis, gather_map);
    detail::assemble_row_matrix(basis, gather_map,
                                {&quadrature.data_start, &sample_value, &sample_weight, &first,
                                 Dim == 1 ? &plate : nullptr, &mass},
                                matrix);
    std::vector<double> delta;
    const detail::SolveReport solved =
        detail::solve_conjugate_gradients(basis, gather_map, matrix, downhill, Dim, kSolveTolerance,
                                          kSolveIterations, delta, between);
    solve_iterations += solved.iterations;
    double slope = 0;  // ∇E · δ
    for (std::size_t i = 0; i < delta.size(); ++i) slope -= downhill[i] * delta[i];
    if (!(slope < 0)) return;  // at the minimum to round-off
    const double before = energy(c, g, anchor);
    const std::vector<double> start = c;
    for (double t = 1; t >= 1.0 / 64; t /= 2) {
      for (std::size_t i = 0; i < c.size(); ++i) c[i] = start[i] + t * delta[i];
      std::size_t changed = 0;
      if constexpr (Dim == 3)
        if (hold) changed = hold_unfolded(start);
      if (energy(c, g, anchor) <= before + 1e-4 * t * slope) {
        held += changed;
        return;
      }
    }
    c = start;
  }

  // E at coefficients `at`, g per data sample given: Σ w g |r|² + λ1 ∫ B + λ2 ∫ C (+ λ3 D_G),
  // summed element by element in order.
  double energy(const std::vector<double>& at, const std::vector<double>& g, double anchor) const {
    const std::vector<double> rows = row_coefficients(basis, at, Dim);
    std::vector<double> per_element(basis.elements.size(), 0.0);
    detail::parallel_for(per_element.size(), 16, [&](std::size_t begin, std::size_t end) {
      for (std::size_t e = begin; e < end; ++e) {
        const auto local = local_coefficients(rows, e);
        double sum = 0;
        for (std::uint32_t i = quadrature.data_start[e]; i < quadrature.data_start[e + 1]; ++i) {
          const std::uint32_t k = quadrature.data[i];
          double f[Dim] = {};
          for (int l = 0; l < 64; ++l)
            for (int d = 0; d < Dim; ++d)
              f[d] += shared.sample_value[std::size_t(i) * 64 + l] * local[l * Dim + d];
          for (int d = 0; d < Dim; ++d) {
            const double r = samples.target[k][target_offset + d] - f[d];
            sum += samples.weight[k] * g[i] * r * r;
          }
        }
        for (int s = 0; s < kCellSamples; ++s) {
          const std::size_t q = e * kCellSamples + s;
          const LocalValue<Dim> x(local_basis(basis, e, quadrature.uvw[q], Dim == 1 ? 2 : 1),
                                  local.data(), Dim == 1 ? 2 : 1);
          double b = 0, c2 = 0;
          for (int a = 0; a < 3; ++a)
            for (int d = 0; d < Dim; ++d) b += x.first[a][d] * x.first[a][d];
          if constexpr (Dim == 3) {
            for (int a = 0; a < 3; ++a) {
              const Vec3 n = cross(
                  Vec3{x.first[a][0], x.first[a][1], x.first[a][2]},
                  Vec3{x.first[(a + 1) % 3][0], x.first[(a + 1) % 3][1], x.first[(a + 1) % 3][2]});
              c2 += dot(n, n);
            }
          } else {
            for (int t = 0; t < 6; ++t) c2 += (t < 3 ? 1 : 2) * x.second[t] * x.second[t];
          }
          double miss = 0;
          for (int d = 0; d < Dim; ++d) {
            const double r = quadrature.target[q][target_offset + d] - x.f[d];
            miss += r * r;
          }
          sum +=
              quadrature.weight[q] * (options.lambda1 * b + options.lambda2 * c2 + anchor * miss);
        }
        if constexpr (Dim == 3) sum += options.lambda3 * normal_misfit(e, local);
        per_element[e] = sum;
      }
    });
    double total = 0;
    for (double x : per_element) total += x;
    return total;
  }

  // G_b and G_c at face point `at` of element e (b, c the face's axes after its normal's), and
  // the local B-splines there.
  struct FacePoint {
    LocalBasis b;
    int bi, ci;
    double side;  // ±1: outward on the face
    Vec3 gb, gc;
  };

  FacePoint face_point(std::size_t e, std::uint32_t at,
                       const std::array<double, 64 * Dim>& local) const {
    FacePoint p{local_basis(basis, e, quadrature.face_uvw[at], 1), 0, 0, 0, {}, {}};
    const int axis = quadrature.face[at] / 2;
    p.bi = (axis + 1) % 3, p.ci = (axis + 2) % 3;
    p.side = quadrature.face[at] % 2 ? 1 : -1;
    for (int k = 0; k < 64; ++k) {
      const Vec3 c{local[k * Dim], local[k * Dim + 1], local[k * Dim + 2]};
      p.gb = p.gb + p.b.first[p.bi][k] * c;
      p.gc = p.gc + p.b.first[p.ci][k] * c;
    }
    return p;
  }

  // D_G over element e's face points: Σ w |n_G − n_I|².
  double normal_misfit(std::size_t e, const std::array<double, 64 * Dim>& local) const {
    double sum = 0;
    for (std::uint32_t at = quadrature.face_start[e]; at < quadrature.face_start[e + 1]; ++at) {
      const FacePoint p = face_point(e, at, local);
      const Vec3 cr = cross(p.gb, p.gc);
      const double length = norm(cr);
      if (!(length > 0)) continue;
      const Vec3 miss = (p.side / length) * cr - quadrature.face_normal[at];
      sum += quadrature.face_weight[at] * dot(miss, miss);
    }
    return sum;
  }

  // Per local B-spline of element e: Σ_k 2 w_k g_k φ(x_k) r_k over the element's data, and
  // the normalisation Σ_k w_k g_k φ(x_k), g the seed's, capped where the Euler step would not
  // be stable.
  void data_forces(std::size_t e, const std::array<double, 64 * Dim>& local, double* data,
                   double* weighted_mass) const {
    const double g_cap = 1 / (2 * options.step);
    for (std::uint32_t i = quadrature.data_start[e]; i < quadrature.data_start[e + 1]; ++i) {
      const std::uint32_t k = quadrature.data[i];
      const LocalBasis b = local_basis(basis, e, samples.uvw[k], 1);
      const LocalValue<Dim> at(b, local.data(), 1);
      double grad2 = 0;
      for (int d = 0; d < Dim; ++d)
        for (int a = 0; a < 3; ++a) grad2 += at.first[a][d] * at.first[a][d];
      add_data_force(k, std::min(1 / std::sqrt(options.gamma + grad2), g_cap), b, at, data,
                     weighted_mass);
    }
  }

  // Sample k's share of data_forces() with velocity weight g, F there `at`.
  void add_data_force(std::uint32_t k, double g, const LocalBasis& b, const LocalValue<Dim>& at,
                      double* data, double* weighted_mass) const {
    std::array<double, Dim> scaled{};
    for (int d = 0; d < Dim; ++d)
      scaled[d] = 2 * samples.weight[k] * g * (samples.target[k][target_offset + d] - at.f[d]);
    for (int j = 0; j < 64; ++j) {
      for (int d = 0; d < Dim; ++d) data[j * Dim + d] += b.value[j] * scaled[d];
      weighted_mass[j] += samples.weight[k] * g * b.value[j];
    }
  }

  // Per local B-spline of element e: the anchor's gradient, 2 μ Σ_q w_q φ (F − I) over its
  // Gauss points.
  void anchor_gradient(std::size_t e, const std::array<double, 64 * Dim>& local, double anchor,
                       double* smooth) const {
    for (int s = 0; s < kCellSamples; ++s) {
      const std::size_t at = e * kCellSamples + s;
      const LocalBasis b = local_basis(basis, e, quadrature.uvw[at], 0);
      const LocalValue<Dim> x(b, local.data(), 0);
      std::array<double, Dim> scaled{};
      for (int d = 0; d < Dim; ++d)
        scaled[d] = 2 * anchor * quadrature.weight[at] *
                    (x.f[d] - quadrature.target[at][target_offset + d]);
      for (int k = 0; k < 64; ++k)
        for (int d = 0; d < Dim; ++d) smooth[k * Dim + d] += b.value[k] * scaled[d];
    }
  }

  // Per local B-spline of element e: the gradient of λ1 ∫ B + λ2 ∫ C over the element.
  void smoothing_gradient(std::size_t e, const std::array<double, 64 * Dim>& local,
                          double* smooth) const {
    for (int s = 0; s < kCellSamples; ++s) {
      const std::size_t at = e * kCellSamples + s;
      const LocalBasis b = local_basis(basis, e, quadrature.uvw[at], Dim == 1 ? 2 : 1);
      const LocalValue<Dim> x(b, local.data(), Dim == 1 ? 2 : 1);
      const double w = quadrature.weight[at];
      // smooth = Σ_a ∂_a φ · v[a] + Σ_t ∂²_t φ · thin[t].
      std::array<std::array<double, Dim>, 3> v{};
      for (int a = 0; a < 3; ++a)
        for (int d = 0; d < Dim; ++d) v[a][d] = w * options.lambda1 * 2 * x.first[a][d];
      std::array<double, 6> thin{};
      if constexpr (Dim == 3) {
        const Vec3 ga[3] = {{x.first[0][0], x.first[0][1], x.first[0][2]},
                            {x.first[1][0], x.first[1][1], x.first[1][2]},
                            {x.first[2][0], x.first[2][1], x.first[2][2]}};
        // d|G_a × G_b|²/dP = 2 [∂_a φ (G_b × (G_a × G_b)) + ∂_b φ ((G_a × G_b) × G_a)].
        for (int a = 0; a < 3; ++a) {
          const int b2 = (a + 1) % 3;
          const Vec3 n = cross(ga[a], ga[b2]);
          const Vec3 for_a = cross(ga[b2], n), for_b = cross(n, ga[a]);
          const double scale = w * options.lambda2 * 2;
          v[a][0] += scale * for_a.x, v[a][1] += scale * for_a.y, v[a][2] += scale * for_a.z;
          v[b2][0] += scale * for_b.x, v[b2][1] += scale * for_b.y, v[b2][2] += scale * for_b.z;
        }
      } else {
        // Thin plate: M_uu² + M_vv² + M_ww² + 2 (M_uv² + M_vw² + M_wu²).
        for (int t = 0; t < 6; ++t)
          thin[t] = w * options.lambda2 * 2 * (t < 3 ? 1 : 2) * x.second[t];
      }
      for (int k = 0; k < 64; ++k)
        for (int d = 0; d < Dim; ++d) {
          double sum = 0;
          for (int a = 0; a < 3; ++a) sum += b.first[a][k] * v[a][d];
          if constexpr (Dim == 1)
            for (int t = 0; t < 6; ++t) sum += b.second[t][k] * thin[t];
          smooth[k * Dim + d] += sum;
        }
    }
  }

  // λ3 D_G: d|n_G − n_I|²/dP = −2 s / |c| [∂_b φ (G_c × q) + ∂_c φ (q × G_b)], c = G_b × G_c,
  // n_G = s c / |c| (s = ±1: outward on the side), q = n_I − n_G (n_G · n_I).
  void boundary_gradient(std::size_t e, const std::array<double, 64 * Dim>& local,
                         double* smooth) const {
    for (std::uint32_t at = quadrature.face_start[e]; at < quadrature.face_start[e + 1]; ++at) {
      const FacePoint p = face_point(e, at, local);
      const Vec3 cr = cross(p.gb, p.gc);
      const double length = norm(cr);
      if (!(length > 0)) continue;
      const double s = p.side;
      const Vec3 n = (s / length) * cr, target = quadrature.face_normal[at];
      const Vec3 q = target - dot(n, target) * n;
      const double factor = -options.lambda3 * quadrature.face_weight[at] * 2 * s / length;
      const Vec3 along_b = cross(p.gc, q), along_c = cross(q, p.gb);
      for (int k = 0; k < 64; ++k) {
        const Vec3 f = factor * (p.b.first[p.bi][k] * along_b + p.b.first[p.ci][k] * along_c);
        smooth[k * Dim] += f.x, smooth[k * Dim + 1] += f.y, smooth[k * Dim + 2] += f.z;
      }
    }
  }
};

// The mesh's points with their element and local B-spline values, where RS is measured.
struct Probe {
  std::vector<std::uint32_t> point;
  std::vector<std::uint32_t> element;
  std::vector<std::array<double, 64>> value;
};

Probe make_probe(const SplineBasis& basis, const CubeMap& map) {
  Probe probe;
  for (std::uint32_t p = 0; p < map.uvw.size(); ++p)
    if (!std::isnan(map.uvw[p][0])) probe.point.push_back(p);
  probe.element.resize(probe.point.size());
  probe.value.resize(probe.point.size());
  detail::parallel_for(probe.point.size(), 256, [&](std::size_t begin, std::size_t end) {
    for (std::size_t i = begin; i < end; ++i) {
      std::array<double, 3> uvw = map.uvw[probe.point[i]];
      for (double& x : uvw) x = std::clamp(x, 0.0, 1.0);  // as the samples (tet_samples)
      probe.element[i] = static_cast<std::uint32_t>(basis_element_at(basis, uvw));
      probe.value[i] = local_basis(basis, probe.element[i], uvw, 0).value;
    }
  });
  return probe;
}

struct ProbeError {
  double l2 = 0, rms = 0, max = 0;  // in the fit's units
};

// |F − target| over the probe's points; `targets` per mesh point (Dim values each).
template <int Dim>
ProbeError probe_error(const SplineBasis& basis, const Probe& probe, const std::vector<double>& c,
                       const std::vector<double>& targets) {
  const std::vector<double> rows = row_coefficients(basis, c, Dim);
  std::vector<double> squared(probe.point.size());
  detail::parallel_for(probe.point.size(), 256, [&](std::size_t begin, std::size_t end) {
    for (std::size_t i = begin; i < end; ++i) {
      std::array<double, Dim> f{};
      for (int k = 0; k < 64; ++k) {
        const std::uint32_t row = basis.element_rows[64 * std::size_t(probe.element[i]) + k];
        for (int d = 0; d < Dim; ++d) f[d] += probe.value[i][k] * rows[std::size_t(row) * Dim + d];
      }
      double s = 0;
      for (int d = 0; d < Dim; ++d) {
        const double r = targets[std::size_t(probe.point[i]) * Dim + d] - f[d];
        s += r * r;
      }
      squared[i] = s;
    }
  });
  ProbeError out;
  for (double s : squared) out.l2 += s, out.max = std::max(out.max, s);
  out.rms = squared.empty() ? 0 : std::sqrt(out.l2 / squared.size());
  out.l2 = std::sqrt(out.l2);
  out.max = std::sqrt(out.max);
  return out;
}

double similarity(double error, double start) {
  return start > 1e-14 ? (1 - error / start) * 100 : 100;
}

void check_options(const TetMesh& mesh, const CubeMap& map, const SolidFitOptions& o) {
  if (map.uvw.size() != mesh.points.size())
    throw InputError("the cube map is not of this tet mesh (" + std::to_string(map.uvw.size()) +
                     " points mapped, " + std::to_string(mesh.points.size()) + " in the mesh)");
  if (!(o.step > 0 && o.step <= 1)) throw InputError("the fit's step must be in (0, 1]");
  if (!(o.lambda1 >= 0 && o.lambda2 >= 0 && o.lambda3 >= 0 && o.gamma >= 0))
    throw InputError("the fit's lambdas and gamma must not be negative");
  if (o.max_iterations < 1) throw InputError("the fit needs at least 1 iteration");
  if (!(o.rs_change >= 0)) throw InputError("the fit's RS tolerance must not be negative");
  if (o.refinements < 0) throw InputError("the fit's refinement rounds must not be negative");
  if (!(o.refine_share >= 0 && o.refine_share <= 1))
    throw InputError(
        "the share of the residual a refinement round splits must be in [0, 1] (0: the "
        "leaves whose residual exceeds the mean by 2 standard deviations)");
  if (o.uniform != 0 && o.uniform < 4)
    throw InputError("a uniform cubic spline needs at least 4 control points per axis");
  // Newton steps hold the Hessian on the rows too: about 11 KB a control point (38³ peaked at
  // 581 MB on bear, benchmarks §21).
  if (o.method == SolidFitMethod::Newton && o.uniform > 64)
    throw InputError("Newton steps on a uniform spline of " + std::to_string(o.uniform) +
                     "³ control points would need about " +
                     std::to_string(std::lround(1.1e-5 * std::pow(o.uniform, 3))) +
                     " GB; at most 64 per axis (262,144 control points), or Euler steps");
  // About 4 KB a control point while fitting (50³ = 125,000 peaked at 504 MB, benchmarks §21).
  if (o.uniform > 100)
    throw InputError("a uniform spline of " + std::to_string(o.uniform) +
                     "³ control points would "
                     "need about " +
                     std::to_string(std::lround(4e-6 * std::pow(o.uniform, 3))) +
                     " GB to fit; at most 100 per axis (1,000,000 control points)");
}

// A field's residual per leaf: Σ w |r|² and Σ w over the leaf's data.
struct LeafResiduals {
  const std::vector<double>& squared;
  const std::vector<double>& weight;
};

// The leaves a refinement round splits, chosen per field (SolidFitOptions::refine_share says
// which and why): `share` 0, those whose RMS residual exceeds the mean by 2σ; in (0, 1],
// Dörfler's marking, the fewest leaves whose squared residuals sum to `share` of the field's.
std::vector<std::size_t> leaves_to_split(const LeafResiduals& g, const LeafResiduals& m,
                                         double share) {
  std::vector<char> chosen(g.squared.size(), 0);
  for (const LeafResiduals* field : {&g, &m}) {
    const std::vector<double>& squared = field->squared;
    if (squared.empty()) continue;
    // Never below 1e-7 of the part's size: round-off is not an error worth refining.
    const double floor = 1e-7;
    if (share > 0) {
      double total = 0;
      for (double x : squared) total += x;
      if (!(std::sqrt(total) > floor)) continue;
      std::vector<std::size_t> order(squared.size());
      for (std::size_t e = 0; e < order.size(); ++e) order[e] = e;
      std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
        return squared[a] != squared[b] ? squared[a] > squared[b] : a < b;
      });
      double sum = 0;
      for (std::size_t e : order) {
        if (sum >= share * total) break;
        chosen[e] = 1;
        sum += squared[e];
      }
      continue;
    }
    std::vector<double> rms(squared.size(), 0.0);
    for (std::size_t e = 0; e < squared.size(); ++e)
      if (field->weight[e] > 0) rms[e] = std::sqrt(squared[e] / field->weight[e]);
    double mean = 0, var = 0;
    for (double x : rms) mean += x;
    mean /= rms.size();
    for (double x : rms) var += (x - mean) * (x - mean);
    const double limit = std::max(mean + 2 * std::sqrt(var / rms.size()), floor);
    for (std::size_t e = 0; e < rms.size(); ++e)
      if (rms[e] > limit) chosen[e] = 1;
  }
  std::vector<std::size_t> out;
  for (std::size_t e = 0; e < chosen.size(); ++e)
    if (chosen[e]) out.push_back(e);
  return out;
}

// Every control value at I_G and I_M of its Greville point.
void greville_start(const SplineBasis& basis, const CubeLookup& lookup, const Units& units,
                    std::vector<double>& g, std::vector<double>& m) {
  const std::vector<std::array<double, 3>> greville = greville_points(basis);
  g.assign(greville.size() * 3, 0.0);
  m.assign(greville.size(), 0.0);
  detail::parallel_for(greville.size(), 256, [&](std::size_t begin, std::size_t end) {
    for (std::size_t f = begin; f < end; ++f) {
      const std::array<double, 4> t = target_at(lookup, units, greville[f]);
      g[3 * f] = t[0], g[3 * f + 1] = t[1], g[3 * f + 2] = t[2], m[f] = t[3];
    }
  });
}

// A fit whose RS ends this many points below the best it passed goes back to that step.
constexpr double kUndoDrop = 1;

// Steps on one field until RS settles: (steps, RS). `progress(step)` after each. Where RS
// ends more than kUndoDrop points below the best step's, the field goes back to that step and
// `undone` counts the steps after it: the data term's weight g falls as |∇G| grows, so a step
// that lowers E with g frozen can still lower RS, and such a G must not be the one written.
template <int Dim, class Progressed>
std::pair<int, double> iterate(FieldFit<Dim>& field, double start, const SolidFitOptions& options,
                               const Progressed& progress, int& undone) {
  const bool euler = options.method == SolidFitMethod::Euler;
  if (euler) field.bound_stiffness(field.gather_map);
  const double now = field.measure();
  double rs = similarity(now, start);
  // Already exact to round-off (a part whose map is affine, a linear material): the
  // regularisers would only pull it off the data.
  if (!(now > 1e-12)) return {0, rs};
  // Fold-free: each step is held back where it would fold G (hold_unfolded()).
  const bool hold = Dim == 3 && options.fold_free;
  std::vector<double> before, best = field.c;
  double best_rs = rs;
  int best_it = 0;
  auto finish = [&](int it) -> std::pair<int, double> {
    if (rs < best_rs - kUndoDrop) {
      field.c = best;
      field.measure();  // the residuals per element, for the leaves to split
      undone += it - best_it;
      rs = best_rs;
    }
    return {it, rs};
  };
  for (int it = 1; it <= options.max_iterations; ++it) {
    if constexpr (Dim == 3)
      if (hold && euler) before = field.c;
    if (euler) {
      field.step();
      if constexpr (Dim == 3)
        if (hold) field.held += field.hold_unfolded(before);
    } else {
      field.newton_step([&progress, it] { progress(it - 1); }, hold);
    }
    const double next = similarity(field.measure(), start);
    const bool settled = std::abs(next - rs) < options.rs_change;
    rs = next;
    if (rs > best_rs) {
      best_rs = rs;
      best = field.c;
      best_it = it;
    }
    progress(it);
    if (settled) return finish(it);
  }
  return finish(options.max_iterations);
}

// The tets' own map's Jacobian at each point of the cube, R = ∂X/∂(u, v, w) in the fit's units,
// inverted: the ideal the untangled G keeps near where the fitted G folds (untangle_spline.hpp).
// Where the tet's image is flat or inverted (a map the untangling left folded), an even scale
// of the solid's volume stands in.
class ReferenceJacobians {
 public:
  ReferenceJacobians(const CubeLookup& lookup, const Units& units)
      : lookup_(lookup), units_(units) {
    double volume = 0;
    for (const Tet& t : lookup.tets) volume += std::abs(detail::determinant(edges_of_points(t)));
    even_ = std::cbrt(std::max(volume / 6, 1e-300));
  }

  // R⁻¹ and det R at (u, v, w).
  std::pair<detail::Matrix3, double> at(std::array<double, 3> uvw) const {
    const Tet& t = lookup_.tets[cube_lookup(lookup_, uvw).tet];
    const detail::Matrix3 x = edges_of_points(t);
    detail::Matrix3 u;
    for (int k = 0; k < 3; ++k)
      for (int r = 0; r < 3; ++r) u[3 * r + k] = lookup_.uvw[t[k + 1]][r] - lookup_.uvw[t[0]][r];
    const double dx = detail::determinant(x), du = detail::determinant(u);
    const double det = dx / du;
    if (!(det > 1e-12 * even_ * even_ * even_) || !std::isfinite(det)) {
      detail::Matrix3 even{};
      for (int a = 0; a < 3; ++a) even[4 * a] = 1 / even_;
      return {even, even_ * even_ * even_};
    }
    // R⁻¹ = U X⁻¹.
    const detail::Matrix3 x_inverse = detail::inverse(x, dx);
    detail::Matrix3 inverse{};
    for (int r = 0; r < 3; ++r)
      for (int col = 0; col < 3; ++col)
        for (int m = 0; m < 3; ++m) inverse[3 * r + col] += u[3 * r + m] * x_inverse[3 * m + col];
    return {inverse, det};
  }

 private:
  detail::Matrix3 edges_of_points(const Tet& t) const {
    detail::Matrix3 x;
    for (int k = 0; k < 3; ++k) {
      const Vec3 e = (1 / units_.size) * (lookup_.points[t[k + 1]] - lookup_.points[t[0]]);
      x[k] = e.x, x[3 + k] = e.y, x[6 + k] = e.z;
    }
    return x;
  }

  const CubeLookup& lookup_;
  const Units& units_;
  double even_ = 1;
};

// A fold G starts a round with is pushed open to this share of the tets' map's det J there,
// in at most so many sweeps (FieldFit::open_folds()).
constexpr double kOpenTo = 0.25;
constexpr int kOpenSweeps = 10;
// Rounds of the fold certificate and pushes on the last G (FieldFit::open_found_folds()).
constexpr int kFoundPasses = 40;

// The position term's weight against the Jacobian term's when G is untangled.
constexpr double kUntangleFidelity = 1;
std::size_t total(const std::vector<std::uint32_t>& counts) {
  std::size_t sum = 0;
  for (std::uint32_t n : counts) sum += n;
  return sum;
}

// Makes G fold-free at its Gauss points where the fit folded it (`folded`: its folded Gauss
// points per element, some): the functions over the
// elements with a folded point move (then, if folds remain, those over every element they
// reach), the rest of G stays; the barrier holds at every Gauss point of the elements they
// touch, and the fit's data samples there keep G near the tets. (Watching only the points
// where det J_G was under half the tets' map's, then the elements that folded on the way,
// cost more than it saved: bunny00 74 s against 51, fandisk 282 against 180, bear 47 against
// 62, each fit 0.4-2.7 points of RS lower.) Returns the functions moved; G is left as fitted
// if the untangling would end with more folds.
std::size_t unfold_geometry(FieldFit<3>& fit, std::vector<std::uint32_t> folded, bool fine,
                            const ReferenceJacobians& reference,
                            const std::function<void(double)>& report, int rings = 2) {
  const SplineBasis& basis = fit.basis;
  const Quadrature& quadrature = fit.quadrature;
  const Gather& gather_map = fit.gather_map;
  // With `fine`, the points the fold certificate found are watched too (fit.found): a fold
  // between the grids that pushes at its points did not open (bear's at a cube corner).
  const bool with_found = fine && !fit.found.empty();
  const auto folds_now = [&] {
    std::vector<std::uint32_t> count = fit.folds_per_element(nullptr, fine);
    if (with_found) {
      const std::vector<std::uint32_t> more = fit.found_folded();
      for (std::size_t e = 0; e < count.size(); ++e) count[e] += more[e];
    }
    return count;
  };
  const std::size_t before = total(folded);
  std::vector<char> movable(basis.functions.size(), 0), element_moves(basis.elements.size(), 0);
  for (std::size_t e = 0; e < folded.size(); ++e) element_moves[e] = folded[e] > 0;
  const std::vector<double> fitted = fit.c;
  const std::vector<double> rows = row_coefficients(basis, fitted, 3);
  // The watched points of an element: its Gauss points, then (`fine`) the finer check's, whose
  // weights sum to the element's volume.
  const auto per = [&](std::size_t e) {
    return kCellSamples + (fine ? finer_samples(basis, e) : 0);
  };
  const auto point = [&](std::size_t e, int s) {
    if (s < kCellSamples) return quadrature.uvw[e * kCellSamples + s];
    s -= kCellSamples;
    for (const Grid& grid : finer_check(basis, e)) {
      const int n = grid.n * grid.n * grid.n;
      if (s < n) return grid.point(basis.elements[e], basis.spans, s);
      s -= n;
    }
    throw std::logic_error("unfold_geometry: a watched point past its element's");
  };
  const auto weight = [&](std::size_t e, int s) {
    if (s < kCellSamples) return quadrature.weight[e * kCellSamples + s];
    const double h = 1.0 / basis.spans[basis.elements[e].level];
    return h * h * h / finer_samples(basis, e);
  };
  // Per watched point, its ideal: the fitted G's own Jacobian, so that the energy starts at
  // its least but where G folds (or nearly: det J_G under a tenth of the tets'), where the
  // tets' map's stands in. Filled a block per element as the region grows (only the region's:
  // all elements' would be 72 bytes · 216 points each, bear's 220 MB).
  constexpr std::size_t kNone = ~std::size_t(0);
  std::vector<std::size_t> block(basis.elements.size(), kNone);  // its first point in `ideal`
  std::vector<detail::Matrix3> ideal;
  std::vector<double> ideal_det;
  std::size_t moved = 0;
  for (int ring = 0; ring < rings; ++ring) {
    // The functions non-zero on a marked element, then every element they reach.
    for (std::size_t e = 0; e < element_moves.size(); ++e)
      if (element_moves[e])
        detail::for_each_term(basis, e, [&](int, std::uint32_t f, double w) {
          if (w != 0) movable[f] = 1;
        });
    std::vector<char> active(basis.elements.size(), 0);
    for (std::size_t f = 0; f < movable.size(); ++f) {
      if (!movable[f]) continue;
      for (std::uint32_t i = gather_map.function_start[f]; i < gather_map.function_start[f + 1];
           ++i) {
        const std::uint32_t r = gather_map.function_row[i];
        for (std::uint32_t s = gather_map.row_start[r]; s < gather_map.row_start[r + 1]; ++s)
          active[gather_map.row_slot[s] / 64] = 1;
      }
    }
    std::vector<std::uint32_t> fresh;
    std::size_t points = ideal_det.size();
    for (std::size_t e = 0; e < active.size(); ++e)
      if (active[e] && block[e] == kNone)
        block[e] = points, points += per(e), fresh.push_back(static_cast<std::uint32_t>(e));
    ideal.resize(points);
    ideal_det.resize(points, 0);
    detail::parallel_for(fresh.size(), 16, [&](std::size_t begin, std::size_t end) {
      for (std::size_t i = begin; i < end; ++i) {
        const std::size_t e = fresh[i];
        const auto local = fit.local_coefficients(rows, e);
        for (int s = 0; s < per(e); ++s) {
          const std::size_t at = block[e] + s;
          auto [inverse, det] = reference.at(point(e, s));
          const detail::Matrix3 jg = fit.jacobian_at(local, e, point(e, s));
          const double fitted_det = detail::determinant(jg);
          if (fitted_det > 0.1 * det) inverse = detail::inverse(jg, fitted_det), det = fitted_det;
          ideal[at] = inverse, ideal_det[at] = det;
        }
      }
    });
    std::vector<detail::PositionSample> positions;
    for (std::uint32_t e = 0; e < active.size(); ++e)
      if (active[e])
        for (std::uint32_t i = quadrature.data_start[e]; i < quadrature.data_start[e + 1]; ++i) {
          const std::uint32_t k = quadrature.data[i];
          const auto& t = fit.samples.target[k];
          positions.push_back({e, fit.samples.uvw[k], fit.samples.weight[k], {t[0], t[1], t[2]}});
        }
    std::vector<detail::JacobianSample> jacobians;
    for (std::uint32_t e = 0; e < active.size(); ++e)
      for (int s = 0; active[e] && s < per(e); ++s) {
        const std::size_t at = block[e] + s;
        jacobians.push_back({e, point(e, s), weight(e, s) * ideal_det[at], ideal[at]});
      }
    for (std::uint32_t e = 0; with_found && e < active.size(); ++e) {
      if (!active[e]) continue;
      const double h = 1.0 / basis.spans[basis.elements[e].level];
      for (const std::array<double, 3>& uvw : fit.found[e]) {  // as a finer check's point
        const auto [inverse, det] = reference.at(uvw);
        jacobians.push_back({e, uvw, h * h * h / kFineSamples * det, inverse});
      }
    }
    moved = 0;
    for (char m : movable) moved += m;
    fit.c = fitted;
    detail::untangle_spline(basis, movable, jacobians, positions, kUntangleFidelity, fit.c,
                            [&](double f) { report((ring + f) / rings); });
    folded = folds_now();
    if (total(folded) == 0) return moved;
    if (ring == 0) element_moves = active;
  }
  if (total(folded) > before) fit.c = fitted;
  return moved;
}

// The mesh's points in the fit's units (x, y, z per point; the material per point).
struct PointTargets {
  std::vector<double> g, m;
};

PointTargets point_targets(const TetMesh& mesh, const Units& units) {
  PointTargets t{std::vector<double>(mesh.points.size() * 3),
                 std::vector<double>(mesh.points.size())};
  for (std::size_t p = 0; p < mesh.points.size(); ++p) {
    const Vec3 x = mesh.points[p];
    t.g[3 * p] = (x.x - units.centre.x) / units.size;
    t.g[3 * p + 1] = (x.y - units.centre.y) / units.size;
    t.g[3 * p + 2] = (x.z - units.centre.z) / units.size;
    t.m[p] = mesh.material.empty() ? 0 : (mesh.material[p] - units.m0) / units.m_range;
  }
  return t;
}

SolidSpline to_millimetres(SplineBasis basis, const std::vector<double>& g,
                           const std::vector<double>& m, bool has_material, const Units& units) {
  SolidSpline spline;
  spline.basis = std::move(basis);
  spline.geometry.resize(spline.basis.functions.size());
  for (std::size_t f = 0; f < spline.geometry.size(); ++f)
    spline.geometry[f] = units.centre + units.size * Vec3{g[3 * f], g[3 * f + 1], g[3 * f + 2]};
  if (has_material)
    for (double x : m) spline.material.push_back(units.m0 + units.m_range * x);
  return spline;
}

}  // namespace

SolidFit fit_solid_spline(const TetMesh& mesh, const CubeMap& map, const SolidFitOptions& options) {
  check_options(mesh, map, options);
  const bool has_material = !mesh.material.empty();
  detail::begin_stage(options.progress, "spline fit");
  const Units units = units_of(mesh, map);
  const CubeLookup lookup = build_cube_lookup(mesh, map);
  const PointTargets points = point_targets(mesh, units);
  const std::vector<std::array<double, 3>> centroids = tet_centroids(mesh, map);
  const TetSamples samples = tet_samples(mesh, map, units, options.surface);
  const ReferenceJacobians reference(lookup, units);
  CubeOctree octree;
  SplineBasis basis;
  if (options.uniform > 0) {
    basis = tensor_basis(options.uniform);
  } else {
    octree = build_cube_octree(centroids, options.octree);
    basis = thb_basis(octree);
  }
  std::vector<double> g, m;
  greville_start(basis, lookup, units, g, m);
  SolidFit fit;
  double start_g = 0, start_m = 0;
  const int rounds = options.uniform > 0 ? 1 : options.refinements + 1;
  const int fields = has_material ? 2 : 1;
  for (int round = 0; round < rounds; ++round) {
    const auto clock = std::chrono::steady_clock::now();
    const Quadrature quadrature = make_quadrature(
        basis, lookup, samples, options.method == SolidFitMethod::Newton ? &units : nullptr);
    const Gather gather_map = detail::make_gather(basis);
    const Probe probe = make_probe(basis, map);
    NewtonStorage shared;
    FieldFit<3> fit_g{basis, quadrature, samples, gather_map, options, 0, g, shared, {}, {}, {}, 0};
    FieldFit<1> fit_m{basis, quadrature, samples, gather_map, options, 3, m, shared, {}, {}, {}, 0};
    if (round == 0) {
      start_g = fit_g.measure();
      start_m = has_material ? fit_m.measure() : 0;
      fit.greville_geometry_rms = probe_error<3>(basis, probe, g, points.g).rms * units.size;
      fit.greville_material_rms = probe_error<1>(basis, probe, m, points.m).rms * units.m_range;
    }
    FitRound report;
    report.control_points = basis.functions.size();
    report.elements = basis.elements.size();
    report.samples = quadrature.uvw.size();  // where folds are counted
    // A round's progress: its start's untangling (when the pushes leave folds) the first tenth,
    // the fields' steps to 0.9, the last G's untangling and bound to the end, so that a long
    // untangling (the lower femur's start: 20 minutes) moves the count too.
    const auto at = [&](double from, double to) {
      return [&, from, to](double fraction) {
        detail::report_or_cancel(options.progress,
                                 (round + from + (to - from) * fraction) / rounds);
      };
    };
    const auto progress = [&](int field) {
      return [&, field](int it) {
        at(0.1, 0.9)((field + double(it) / options.max_iterations) / fields);
      };
    };
    // Fold-free: G starts each round fold-free at its watched points (the Greville start, or
    // a refined G at the finer elements' points, folds in places), and its steps keep it so
    // (hold_unfolded()). The last round watches the finer check's points too, and no
    // children's.
    const bool last = round + 1 == rounds;
    fit_g.watch_children = !last;
    if (options.fold_free) {
      std::size_t left = 0;
      std::tie(report.fitted_folded_samples, left) = fit_g.open_folds(
          [&](std::array<double, 3> uvw) { return kOpenTo * reference.at(uvw).second; },
          kOpenSweeps);
      // What the pushes could not open, the foldover-free energy does (slower).
      const std::vector<std::uint32_t> folded = fit_g.folds_per_element(nullptr, last);
      if (left > 0 && total(folded) > 0)
        report.untangled_functions = unfold_geometry(fit_g, folded, last, reference, at(0, 0.1));
    }
    std::tie(report.geometry_iterations, report.geometry_rs) =
        iterate(fit_g, start_g, options, progress(0), report.undone_steps);
    report.held_functions = fit_g.held;
    if (has_material)
      std::tie(report.material_iterations, report.material_rs) =
          iterate(fit_m, start_m, options, progress(1), report.undone_steps);
    // The steps are explicit: one that is not stable blows up rather than slows down, and a
    // model with a non-finite control point must not reach a file.
    for (const std::vector<double>* field : {&g, &m})
      for (double x : *field)
        if (!std::isfinite(x))
          throw InputError("the spline fit diverged in round " + std::to_string(round + 1) +
                           " (a control value is not finite); try a smaller step (the seed's "
                           "0.4-0.6) or more tets per cell");
    report.solve_iterations = fit_g.solve_iterations + fit_m.solve_iterations;
    // The leaves to split are chosen from the fit's own residuals.
    std::vector<std::size_t> chosen;
    CubeOctree finer;
    if (round + 1 < rounds) {
      chosen = leaves_to_split({fit_g.element_error, fit_g.element_weight},
                               {fit_m.element_error, fit_m.element_weight}, options.refine_share);
      finer = split_octree_leaves(octree, chosen, centroids, options.octree);
      report.split = finer.leaves.size() > octree.leaves.size() ? chosen.size() : 0;
    }
    // The G written: untangled again where its start's folds outlived the round's first
    // untangling (a round that ends the refinement early watches its finer points here first).
    if (options.fold_free && report.split == 0) {
      const std::vector<std::uint32_t> folded = fit_g.folds_per_element(nullptr, true);
      if (total(folded) > 0) {
        report.fitted_folded_samples += total(folded);
        report.untangled_functions +=
            unfold_geometry(fit_g, folded, true, reference, at(0.9, 0.95));
        report.geometry_rs = similarity(fit_g.measure(), start_g);
      }
    }
    // Positive at the watched points is not positive everywhere: the last G's folds between
    // them, found by det J_G's Bernstein bound, are opened too.
    if (options.fold_free && report.split == 0) {
      report.found_folds = fit_g.open_found_folds(
          [&](std::array<double, 3> uvw) { return kOpenTo * reference.at(uvw).second; },
          kOpenSweeps, kFoundPasses, [&] { at(0.95, 1)(0); });  // heard between passes
      // Folds the pushes left (the bound's last verdicts, added to the found points): the
      // foldover-free energy, watching them beside the grids' points, then the bound again.
      std::vector<std::uint32_t> left = fit_g.bound_folds();
      if (total(left) > 0) {
        const std::vector<std::uint32_t> grids = fit_g.folds_per_element(nullptr, true);
        for (std::size_t e = 0; e < left.size(); ++e) left[e] += grids[e];
        // One ring: the functions over the folded elements (fandisk's 5: 213 functions, about
        // 900 elements watched at 216 points each, 35 s); a second ring took 65 s and failed.
        report.untangled_functions +=
            unfold_geometry(fit_g, left, true, reference, at(0.95, 0.99), 1);
        report.found_folds += fit_g.open_found_folds(
            [&](std::array<double, 3> uvw) { return kOpenTo * reference.at(uvw).second; },
            kOpenSweeps, kFoundPasses, [&] { at(0.99, 1)(0); });
      }
      if (report.found_folds > 0) report.geometry_rs = similarity(fit_g.measure(), start_g);
    }
    const ProbeError eg = probe_error<3>(basis, probe, g, points.g);
    report.geometry_rms = eg.rms * units.size;
    report.geometry_max = eg.max * units.size;
    report.folded_samples = total(fit_g.folds_per_element(&report.worst_fold));
    if (report.split == 0) {  // the last round: its G is what is written
      for (std::size_t e = 0; e < basis.elements.size(); ++e)
        report.fine_samples += finer_samples(basis, e);
      report.fine_folded_samples = fit_g.fine_folds();
      if (report.fine_folded_samples > 0) fit_g.folds_per_element(&report.worst_fold, true);
    }
    if (has_material) {
      const ProbeError em = probe_error<1>(basis, probe, m, points.m);
      report.material_rms = em.rms * units.m_range;
      report.material_max = em.max * units.m_range;
    }
    if (report.split > 0) {
      SplineBasis next = thb_basis(finer);
      g = refine_coefficients(basis, next, g, 3);
      m = refine_coefficients(basis, next, m, 1);
      basis = std::move(next);
      octree = std::move(finer);
    }
    report.seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - clock).count();
    fit.rounds.push_back(report);
    if (round + 1 < rounds && report.split == 0) break;
  }
  fit.spline = to_millimetres(std::move(basis), g, m, has_material, units);
  detail::report_or_cancel(options.progress, 1.0);
  return fit;
}

SolidPoint detail::solid_point(const SolidSpline& spline, std::array<double, 3> uvw,
                               bool derivatives) {
  for (double& x : uvw) x = std::clamp(x, 0.0, 1.0);
  const std::size_t e = basis_element_at(spline.basis, uvw);
  const LocalBasis b = local_basis(spline.basis, e, uvw, derivatives ? 1 : 0);
  SolidPoint out;
  const bool has_material = !spline.material.empty();
  detail::for_each_term(spline.basis, e, [&](int k, std::uint32_t f, double w) {
    out.position = out.position + (w * b.value[k]) * spline.geometry[f];
    if (has_material) out.material += w * b.value[k] * spline.material[f];
    if (!derivatives) return;
    for (int a = 0; a < 3; ++a)
      out.jacobian[a] = out.jacobian[a] + (w * b.first[a][k]) * spline.geometry[f];
    if (has_material)
      out.material_gradient =
          out.material_gradient +
          (w * spline.material[f]) * Vec3{b.first[0][k], b.first[1][k], b.first[2][k]};
  });
  return out;
}

SolidPoint evaluate_solid(const SolidSpline& spline, std::array<double, 3> uvw) {
  return detail::solid_point(spline, uvw, true);
}

Box3 solid_box(const SolidSpline& spline) {
  Box3 box{{1e300, 1e300, 1e300}, {-1e300, -1e300, -1e300}};
  const SplineBasis& b = spline.basis;
  for (const OctreeCell& c : b.elements) {
    const std::uint32_t last = b.spans[c.level] - 1;
    const double h = 1.0 / b.spans[c.level];
    for (int axis = 0; axis < 3; ++axis)
      for (int side = 0; side < 2; ++side) {
        if (c.index[axis] != (side ? last : 0)) continue;
        for (int k = 0; k < 9; ++k) {  // the face's corners, edge midpoints and centre
          std::array<double, 3> uvw{};
          uvw[axis] = side;
          uvw[(axis + 1) % 3] = (c.index[(axis + 1) % 3] + 0.5 * (k % 3)) * h;
          uvw[(axis + 2) % 3] = (c.index[(axis + 2) % 3] + 0.5 * (k / 3)) * h;
          const Vec3 p = evaluate_solid(spline, uvw).position;
          box.min = {std::min(box.min.x, p.x), std::min(box.min.y, p.y), std::min(box.min.z, p.z)};
          box.max = {std::max(box.max.x, p.x), std::max(box.max.y, p.y), std::max(box.max.z, p.z)};
        }
      }
  }
  return box;
}

}  // namespace tpmsfill
