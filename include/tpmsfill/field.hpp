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

/// The simplest source: `at` called at every node (Grid::node), from several threads at once.
/// @param at  φ at a point, mm; must be thread-safe and return the same value for the same point
FieldSource function_source(std::function<float(Vec3)> at);

/// φ at every node of `grid`, evaluated in parallel by blocks of rows. Reports the stage
/// "field" to `progress`.
/// @throws InputError  `source` is empty
/// @throws Cancelled   when progress says so
/// @throws whatever the source throws (tpmsfill::Error)
Field sample_field(const FieldSource& source, const Grid& grid, Progress* progress = nullptr);

/// φ at one point, mm (the source on a grid of one node at p).
/// @throws InputError  `source` is empty
float field_value(const FieldSource& source, Vec3 p);

}  // namespace tpmsfill
