/// @file rounded_grid.hpp
/// @brief Where a grid's nodes lie once a file holds them (STL, binary CLI: floats; 3MF:
/// lib3mf's micrometres; ASCII CLI, SVG: six decimals), and where the marching-cubes (or
/// marching-squares) vertex of each grid edge may go so that, as the file holds it, it stays
/// strictly inside its edge.
///
/// Why this is enough for a valid file: rounding gives a node coordinate the same value
/// wherever it appears, so the held nodes form a rectilinear grid again, and a marching-cubes
/// mesh whose every vertex lies strictly inside its edge of that grid (and each centroid
/// strictly inside its cube) is closed, manifold and free of self-intersections wherever
/// along the edges the vertices sit. Without it, vertices near a node were rounded onto the
/// node and onto each other: at 150 mm a float holds a coordinate every 1.5e-5 mm, coarser than
/// marching cubes' clamp of 1e-4 of a 0.1 mm voxel.
#pragma once

#include <algorithm>
#include <array>
#include <vector>

#include "io/float_coordinates.hpp"
#include "io/three_mf.hpp"
#include "tpmsfill/io.hpp"
#include "tpmsfill/types.hpp"

namespace tpmsfill::detail {

/// `x` as a file with `rounding` holds it (round_coordinates, one coordinate).
inline double held(CoordinateRounding rounding, double x) {
  switch (rounding) {
    case CoordinateRounding::None:
      return x;
    case CoordinateRounding::Float:
      return float_value(x);
    case CoordinateRounding::ThreeMf:
      return io::three_mf_rounded(static_cast<float>(x));
    case CoordinateRounding::SixDecimals:
      return six_decimals_value(x);
  }
  return x;
}

/// Where along a grid edge the field crosses `iso`, as a parameter in (0, 1) from the node
/// valued v0 to the one valued v1 (marching cubes' and marching squares' vertex). Clamped to
/// [1e-4, 1 − 1e-4]: a vertex never sits on a node, so vertices on edges that share a node
/// never coincide.
inline double edge_crossing(double v0, double v1, double iso) {
  constexpr double kMargin = 1e-4;
  return std::clamp((iso - v0) / (v1 - v0), kMargin, 1 - kMargin);
}

/// Spacing of the coordinates a file with `rounding` holds near ±magnitude, mm (0 for None:
/// doubles are exact enough for any grid the tool makes).
double held_step(CoordinateRounding rounding, double magnitude);

/// The finest voxel a grid reaching `magnitude` mm from the origin may have for `rounding`:
/// four held steps, so rounding moves a vertex by at most an eighth of a voxel.
double finest_held_voxel(CoordinateRounding rounding, double magnitude);

/// What the held coordinates are written into, for the refusal's advice.
enum class HeldFile { Mesh, Layers };

/// @throws InputError  the file's coordinates are too coarse where `grid` reaches for its
///                     voxel (finest_held_voxel): one sentence with the distance, the step,
///                     the voxel that would do and the formats that hold finer coordinates
void require_held_grid(const Grid& grid, CoordinateRounding rounding,
                       HeldFile file = HeldFile::Mesh);

/// A grid's nodes and edge interiors as a file with `rounding` holds them.
class RoundedGrid {
 public:
  /// @throws InputError  as require_held_grid
  RoundedGrid(const Grid& grid, CoordinateRounding rounding, HeldFile file = HeldFile::Mesh);

  /// `x` (on edge `i` along `axis`, between nodes i and i + 1) as the file holds it, moved to
  /// the nearest held value strictly inside the edge where rounding took it to a node or
  /// beyond. `x` itself for None.
  double inside_edge(int axis, int i, double x) const {
    if (low_[0].empty()) return x;
    const std::size_t e = static_cast<std::size_t>(i);
    const double r = held(rounding_, x);
    return r < low_[axis][e] ? low_[axis][e] : (r > high_[axis][e] ? high_[axis][e] : r);
  }

  CoordinateRounding rounding() const { return rounding_; }

  /// Node i's coordinate along `axis` as the file holds it.
  double node(int axis, int i) const {
    return low_[0].empty() ? grid_.coordinate(axis, i) : node_[axis][static_cast<std::size_t>(i)];
  }

 private:
  Grid grid_;
  CoordinateRounding rounding_;
  // Per axis: node i as held, and the lowest and highest held values strictly inside edge i.
  std::array<std::vector<double>, 3> node_, low_, high_;
};

}  // namespace tpmsfill::detail
