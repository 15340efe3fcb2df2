/// @file field.hpp
/// @brief The field seam: a signed field in millimetres, evaluated by blocks of grid rows.
///
/// Every source of geometry plugs in here and every consumer takes it from here:
///
///   sources:   a TPMS (tpms_source), a design (design_source: grading, blends), a function
///              of the point (function_source), a caller's own FieldSource
///   consumers: compose_field (clipped to the model, then marching cubes), sample_field (a
///              Field at every node), field_value (one point)
///
/// A field is negative in the solid it describes and positive outside it, and near its zero
/// level it should be a distance in mm (f/|∇f|, say), so that thicknesses, skins and the max
/// with the model's distance speak one unit. A source is evaluated in two steps: on_grid()
/// once per grid (the place for per-grid tables: per-axis trigonometry, basis functions),
/// then the returned RowFunction on blocks of whole rows, from several threads at once.
///
/// Rows: row r of a grid is the line of nodes (0 .. dims[0] − 1, j, k) with r = j + dims[1]·k,
/// 0 <= r < Grid::row_count(); a block of rows [first, first + count) is stored as a Field
/// stores those nodes, x fastest. Node coordinates are Grid::node(i, j, k), so a source sees
/// the same bit-identical coordinates every stage uses.
#pragma once

#include <cstddef>
#include <cstdint>
#include <functional>

#include "tpmsfill/progress.hpp"
#include "tpmsfill/types.hpp"

namespace tpmsfill {

/// A field bound to one grid: writes φ (mm) at the nodes of rows [first_row, first_row +
/// row_count) into `values` (row_count·dims[0] floats, x fastest). Where `need` is not null
/// and need[n] is 0, the value of node n of the block is not needed and may be left as it is
/// (compose skips the nodes outside the model). Must be safe to call from several threads at
/// once, and give a node the same value whatever the blocks it is asked in.
using RowFunction = std::function<void(std::size_t first_row, std::size_t row_count, float* values,
                                       const std::uint8_t* need)>;

/// A signed field in mm, negative in the solid it describes.
struct FieldSource {
  /// Prepares the field on `grid` and returns its rows. Called once per grid, before any row
  /// of it is asked for; may throw tpmsfill::Error (e.g. InputError for a grid it cannot use).
  std::function<RowFunction(const Grid& grid)> on_grid = {};
  /// An upper bound of |φ|, mm, where the source has one (0: unknown). Compose gives nodes far
  /// outside the model the value 1 + skin + bound, a plausible distance for the measures that
  /// read φ's gradient there.
  double bound = 0;

  explicit operator bool() const { return static_cast<bool>(on_grid); }
};

/// Binds `source` to `grid`: what every consumer calls before asking for rows.
/// @throws InputError  the source is empty, its bound is negative or not finite, or on_grid
///                     returned no row function
/// @throws whatever on_grid throws
RowFunction bind_source(const FieldSource& source, const Grid& grid);

/// Calls f(i, j, k, n) for the nodes of rows [first_row, first_row + row_count) of `grid` that
/// a RowFunction is asked for: every node when `need` is null, else those with need[n] != 0.
/// n is the node's place in the block (values[n]); (i, j, k) its grid indices, for
/// Grid::node(i, j, k). Row by row, x fastest: the loop every row function writes.
template <class F>
void for_each_needed_node(const Grid& grid, std::size_t first_row, std::size_t row_count,
                          const std::uint8_t* need, F&& f) {
  const std::size_t nx = static_cast<std::size_t>(grid.dims[0]);
  const std::size_t ny = static_cast<std::size_t>(grid.dims[1]);
  for (std::size_t r = 0; r < row_count; ++r) {
    const int j = static_cast<int>((first_row + r) % ny);
    const int k = static_cast<int>((first_row + r) / ny);
    for (std::size_t i = 0, n = r * nx; i < nx; ++i, ++n)
      if (!need || need[n]) f(static_cast<int>(i), j, k, n);
  }
}

/// The simplest source: `at` called at every node (Grid::node), from several threads at once.
/// @param at  φ at a point, mm; must be thread-safe and return the same value for the same point
FieldSource function_source(std::function<float(Vec3)> at);

/// φ at every node of `grid`, evaluated in parallel by blocks of rows. Reports the stage
/// "field" to `progress`.
/// @throws InputError  as bind_source
/// @throws Cancelled   when progress says so
/// @throws whatever the source throws (tpmsfill::Error)
Field sample_field(const FieldSource& source, const Grid& grid, Progress* progress = nullptr);

/// φ at one point, mm (the source on a grid of one node at p).
/// @throws InputError  as bind_source
float field_value(const FieldSource& source, Vec3 p);

}  // namespace tpmsfill
