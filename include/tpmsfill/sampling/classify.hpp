/// @file classify.hpp
/// @brief Stage "classify": which grid nodes are inside the model (the occupancy I of the
/// paper), by one ray per grid row through the AABB tree.
///
/// For each row (j, k) one ray runs along +x. Its crossings with the triangles are decided
/// with exact predicates (CGAL Epick 2D orientation of the row against the triangle's
/// projection on the yz plane) and a fixed tie-break (symbolic perturbation of the row to
/// (y + ε, z + ε²)), so a ray through an edge or a vertex counts it exactly once and a
/// triangle seen edge-on never counts. Each crossing also has a direction (entering or
/// leaving, from the triangle's orientation). The crossings are sorted, and then:
///
/// - InsideRule::Parity: nodes between odd and even crossings are inside (the method paper's
///   rule; right only for closed meshes without overlapping shells).
/// - InsideRule::Winding: inside is the generalized winding number w ≥ ½. Along a row w
///   jumps by ±1 at each crossing and, for a closed mesh, is constant in between, so the
///   running sum J of crossing directions is w, exactly. Where the index holds hole caps C
///   (IndexOptions::hole_caps), model and caps are closed together and w = J − w_C: the
///   caps' own winding number is subtracted where it could change the answer, found by the
///   certified bounds of a small hierarchy over the caps (most rows are too far from any
///   cap to need it). On a closed, consistently oriented mesh whose shells do not overlap,
///   J is 0 or 1 and the two rules agree node for node.
///
/// Never one ray per node.
#pragma once

#include <cstdint>
#include <optional>
#include <string_view>
#include <vector>

#include "tpmsfill/progress.hpp"
#include "tpmsfill/sampling/spatial.hpp"
#include "tpmsfill/types.hpp"

namespace tpmsfill {

enum class InsideRule {
  Parity,   ///< odd number of crossings
  Winding,  ///< generalized winding number ≥ ½
};

/// "auto" (unset), "winding", "parity": FillOptions::inside as the CLI and recipes name it.
std::string_view inside_name(std::optional<InsideRule> rule);
/// @throws InputError  not one of those names
std::optional<InsideRule> inside_from_name(std::string_view name);

struct ClassifyOptions {
  InsideRule rule = InsideRule::Winding;
  Progress* progress = nullptr;  ///< reports per row chunk; may cancel
};

struct Occupancy {
  Mask inside;  ///< 1 = node inside the model
  /// Volume enclosed by the model, mm^3, measured along the rays: the summed lengths of the
  /// spans inside by parity (Parity) or with J ≥ 1 (Winding), times spacing² (exact along x,
  /// midpoint rule across rows). Rows whose answer needed the hole caps count their inside
  /// nodes times spacing instead.
  double volume = 0;
  std::uint64_t rows = 0;       ///< rows cast, one ray each (Grid::row_count())
  std::uint64_t crossings = 0;  ///< ray/triangle crossings counted, caps included
  /// Rows whose crossing count was odd (the mesh is not closed along them). Parity ignores
  /// their last crossing. Non-zero means the triangles in the index have holes.
  std::uint64_t odd_rows = 0;
  /// Winding rule: rows with a node where J is not 0 or 1 (shells overlap or are inside out).
  std::uint64_t overlap_rows = 0;
  /// Winding rule: rows whose crossing directions do not add up to 0, or with a node where J
  /// is negative: along them the triangles (caps included) are open or not consistently
  /// oriented outward. 0 for a closed, outward mesh.
  std::uint64_t unbalanced_rows = 0;
  /// Winding rule: nodes where the winding number and parity disagree.
  std::uint64_t parity_disagreements = 0;
  /// Winding rule: nodes whose answer needed the caps' winding number evaluated.
  std::uint64_t cap_evaluations = 0;

  /// The figures above for the rows of one node plane (rows (·, ·, k)): a slab's planes sum to
  /// what a whole grid reports for them. The totals above are these summed in plane order.
  struct PlaneCounts {
    double volume = 0;  ///< its rows' inside lengths × spacing²
    std::uint64_t rows = 0, crossings = 0, odd_rows = 0, overlap_rows = 0, unbalanced_rows = 0,
                  parity_disagreements = 0, cap_evaluations = 0;
    PlaneCounts& operator+=(const PlaneCounts& o);
  };
  std::vector<PlaneCounts> planes;  ///< one per node plane k
};

/// Classifies every node of `grid`. A node exactly on a crossing takes the lower of the
/// two sides' J (parity: counts as outside).
/// @param[in] index  AABB tree of the model
/// @param[in] grid   sample grid (make_grid); rays cover its whole x extent
/// @throws Cancelled  when options.progress says so
Occupancy classify_grid(const MeshIndex& index, const Grid& grid,
                        const ClassifyOptions& options = {});

}  // namespace tpmsfill
