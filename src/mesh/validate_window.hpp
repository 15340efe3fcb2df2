/// @file validate_window.hpp
/// @brief validate_mesh() one window at a time, for meshes too large to hold (fill's streamed
/// output): each window is a piece of the mesh as a small soup, and the items it *owns* are
/// judged there as validate_mesh() judges them in the whole mesh. Summed over windows that own
/// every point and triangle once, the counts are validate_mesh()'s. Volume, area, components
/// and orientation are sums the caller keeps in the whole mesh's order.
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <vector>

#include "mesh/internal/self_intersections.hpp"
#include "tpmsfill/mesh/validate.hpp"
#include "tpmsfill/types.hpp"

namespace tpmsfill::detail {

/// What one window contributes; examples index the window's own triangles.
struct WindowValidation {
  std::uint64_t vertices = 0;  ///< owned points that some triangle uses
  std::uint64_t degenerate = 0, border = 0, non_manifold = 0, inconsistent = 0, pinched = 0;
  std::uint64_t duplicates = 0, intersecting_pairs = 0;
  /// Edges name the window's triangles.
  std::vector<EdgeLocation> border_examples, non_manifold_examples, inconsistent_examples;
  std::vector<Vec3> pinched_examples;
  std::vector<std::uint32_t> degenerate_examples;
  std::vector<TrianglePair> intersection_examples;
  bool searched_by_cells = false;
};

/// Validates the owned part of `window`, a piece of a larger mesh whose points and triangles
/// keep the whole mesh's relative order.
/// @param[in] window          the piece; preconditions (the caller's, not checked): every
///                            triangle using an owned point is in it, and so is every point
///                            at an owned point's position with a lower id; every triangle
///                            that an owned triangle may intersect is in it
/// @param[in] owned_points    [first, second) window points whose edges (at their smaller
///                            end), fans and duplicates count here
/// @param[in] first_owned_triangle  window triangles from here on are owned: their degeneracy
///                            counts here, and every intersecting pair with an owned member
/// @param[in] cell_grid, max_examples  as ValidateOptions
/// @param[in] self_intersections  search for them
WindowValidation validate_window(const TriangleSoup& window,
                                 std::array<std::size_t, 2> owned_points,
                                 std::size_t first_owned_triangle,
                                 const std::optional<Grid>& cell_grid, std::size_t max_examples,
                                 bool self_intersections);

}  // namespace tpmsfill::detail
