/// @file parameterize.hpp
/// @brief Stage "parameterize": a surface with one or two boundary loops laid flat on the unit
/// square, for lattices that follow a freeform surface (conformal.hpp).
///
/// Mean-value coordinates (Floater 2003) with the boundary fixed on the square's sides by arc
/// length, solved by Eigen's sparse LU (the solve the cube map's patches use too). With a convex
/// boundary and positive weights the map is a bijection: no triangle flips (Floater), which
/// the stage counts rather than assumes.
///
/// A disk (one loop, genus 0) is laid out as it is. A tube (two loops, genus 0: a blade, a
/// pipe) is first cut along a seam, the shortest edge path from one loop to the other, whose
/// vertices are doubled; the seam's two sides become u = 0 and u = 1 and the loops v = 0 and
/// v = 1, so a lattice whose period along u divides the length closes around the tube.
///
/// A deep surface (a head, a mushroom's cap) is squeezed by a fixed square: its middle gets a
/// small share of the square and cells there come out large. The free layout (as rigid as
/// possible: surface/internal/arap.hpp), started from the square's, lets the boundary move so
/// each triangle keeps its own shape and size as far as the surface allows; a tube's seam stays
/// closed (its sides one period apart). LayoutMethod::Auto takes it when it has no flips and
/// narrows the area scale's spread (p95/p5) by 5 % or more.
///
/// Distortion is measured per triangle against the square scaled to length_u × length_v (the
/// boundary's proportions at the surface's area): the area scale σ_A = A_3D / A_2D (a cell of
/// nominal size T appears as T·√σ_A on the surface) and the conformal distortion σ₁/σ₂ ≥ 1
/// of the map's Jacobian (1: angles kept).
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <string_view>
#include <vector>

#include "tpmsfill/progress.hpp"
#include "tpmsfill/types.hpp"

namespace tpmsfill {

/// Percentiles of a per-triangle quantity, area-weighted, and its range.
struct Spread {
  double min = 0, p5 = 0, p50 = 0, p95 = 0, max = 0;
};

/// How a surface is laid out: on the fixed square (mean-value coordinates), free (as rigid as
/// possible), or whichever spreads the area scale less (free only without flips).
enum class LayoutMethod { Square, Free, Auto };

struct ParameterizeOptions {
  LayoutMethod method = LayoutMethod::Auto;

  /// Disks: the input vertices (indices into the soup's points) placed at the square's
  /// corners (0,0), (1,0), (1,1), (0,1), all on the boundary loop and met in this order along
  /// it (either direction). Unset: the boundary vertex where the loop turns most, then the
  /// vertices a quarter, a half and three quarters of the loop's length on from it. Tubes
  /// take their corners from the seam and refuse these.
  std::optional<std::array<std::uint32_t, 4>> corners = {};
  Progress* progress = nullptr;  ///< reports the stage's start
};

struct SurfaceParameterization {
  /// The surface as laid out: the input's triangles over its distinct points (points with
  /// bit-identical coordinates merged, triangles with a repeated corner dropped), and for a
  /// tube the seam's vertices doubled. Triangle t here is triangle source_triangle[t] of the
  /// input.
  TriangleSoup mesh;
  std::vector<std::uint32_t> source_triangle;
  /// Per point of `mesh`: in [0, 1]² on the square; a free layout's bounding box is [0, 1]²
  /// (a tube's u: x over the period, from 0, so u + 1 is the seam's other side).
  std::vector<std::array<double, 2>> uv;
  LayoutMethod method = LayoutMethod::Square;  ///< the layout chosen: Square or Free
  /// Auto: the area scale of the layout not chosen (the square's or the free one's).
  std::optional<Spread> other_area_scale;
  int free_iterations = 0;                 ///< the free layout's local/global rounds (0: not tried)
  int boundary_loops = 0;                  ///< of the input: 1 (disk) or 2 (tube)
  bool periodic_u = false;                 ///< a tube: u = 0 and u = 1 are the seam's sides
  std::uint64_t seam_edges = 0;            ///< edges the seam cut (0 for a disk)
  std::array<std::uint32_t, 4> corners{};  ///< points of `mesh` at (0,0), (1,0), (1,1), (0,1)
  /// The slab size that keeps cells at their nominal size on average, mm: the boundary's mean
  /// lengths along u (the sides v = 0 and v = 1) and along v, scaled together so that
  /// length_u × length_v is the surface's area (the area scale σ_A averages 1). A free
  /// layout's: its bounding box (a tube's length_u: the period), scaled so σ_A's p5 and p95
  /// lie equally far from 1 (p5 · p95 = 1).
  double length_u = 0, length_v = 0;
  double area = 0;          ///< of the surface, mm²
  std::uint64_t flips = 0;  ///< triangles whose image is reversed or has no area
  Spread area_scale;        ///< σ_A against the length_u × length_v square
  Spread angle_distortion;  ///< σ₁/σ₂ of the Jacobian
};

/// Lays `surface` flat (see the file comment).
/// @param[in] surface  a connected, oriented 2-manifold with one boundary loop (a disk) or two
///                     (a tube), genus 0, as readers return it (duplicate points are merged)
/// @throws InputError  no triangles; an edge shared by more than two triangles, or by two that
///                     disagree on orientation; a vertex where two fans meet; several pieces;
///                     no boundary (closed), more than two loops, or a handle (genus > 0);
///                     corners not on the loop, repeated, or given for a tube or a free
///                     layout; the solver failing
SurfaceParameterization parameterize_surface(const TriangleSoup& surface,
                                             const ParameterizeOptions& options = {});

std::string_view layout_method_name(LayoutMethod method);  ///< "square", "free", "auto"
/// @throws InputError  none of "square", "free", "auto"
LayoutMethod layout_method_from_name(std::string_view name);

/// (u, v) at barycentric coordinates `b` of triangle t of `p.mesh`.
inline std::array<double, 2> uv_at(const SurfaceParameterization& p, std::size_t t,
                                   std::array<double, 3> b) {
  const Triangle& tri = p.mesh.triangles[t];
  std::array<double, 2> r{0, 0};
  for (int c = 0; c < 3; ++c)
    for (int a = 0; a < 2; ++a) r[a] += b[c] * p.uv[tri[c]][a];
  return r;
}

}  // namespace tpmsfill
