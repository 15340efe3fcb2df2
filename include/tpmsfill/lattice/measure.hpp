/// @file measure.hpp
/// @brief Stage "measure": pore size, wall (strut) thickness and void connectivity of a clipped
/// lattice, the numbers a scaffold is specified by, from the composed field φ on the grid.
///
/// Sizes are the diameters of the largest spheres that fit, in the style of local thickness
/// (Hildebrand & Rüegsegger 1997): the distance from every node to the other phase, sampled on
/// its ridge (the nodes where it is a local maximum, i.e. next to the medial axis, where the
/// largest spheres are centred). The distance is node-exact (the squared EDT behind
/// distance_transform) and is then moved onto the surface using φ at the nearest nodes of the
/// other phase, so it is sub-voxel accurate. See docs/method.md.
#pragma once

#include <cstdint>
#include <vector>

#include "tpmsfill/progress.hpp"
#include "tpmsfill/types.hpp"

namespace tpmsfill {

/// One measured diameter and where it was measured.
struct SizeSample {
  double diameter = 0;  ///< mm
  Vec3 at;              ///< the ridge node's position, mm

  friend bool operator==(const SizeSample&, const SizeSample&) = default;
};

/// Diameters measured at a phase's ridge nodes, mm.
struct SizeDistribution {
  std::uint64_t samples = 0;  ///< ridge nodes measured (0: nothing to measure, the rest is 0)
  double min = 0, mean = 0, max = 0;
  double p10 = 0, p50 = 0, p90 = 0;  ///< percentiles, linear between order statistics
  /// Histogram: bins + 1 equal-width edges from min to max (one voxel wide when min == max),
  /// mm; counts[b] samples lie in [bin_edges[b], bin_edges[b + 1]) (the last bin is closed).
  std::vector<double> bin_edges;
  std::vector<std::uint64_t> counts;
  /// The smallest samples away from the model's surface, smallest first (at most
  /// MeasureOptions::smallest; ties in node order): where the design's thinnest walls or
  /// narrowest pores are. A sample whose measuring sphere comes within a voxel of the model's
  /// surface is left out: there the surface cuts struts and walls into slivers, which say
  /// nothing about the design.
  std::vector<SizeSample> smallest;
  /// Samples below MeasureOptions' limit for this phase (min_wall, min_pore; 0 without one):
  /// away from the model's surface, and next to it.
  std::uint64_t below_limit = 0, below_limit_at_surface = 0;

  friend bool operator==(const SizeDistribution&, const SizeDistribution&) = default;
};

struct LatticeMeasures {
  SizeDistribution pore;  ///< diameter of the largest sphere that fits in the void
  SizeDistribution wall;  ///< the same in the solid: wall (sheet) or strut (network) thickness
  std::uint64_t void_components = 0;  ///< 6-connected regions of void nodes inside the model
  std::uint64_t labyrinths = 0;       ///< those holding at least min_labyrinth_fraction of the void
  double largest_void_fraction = 0;   ///< share of the void in the largest component (0: no void)

  friend bool operator==(const LatticeMeasures&, const LatticeMeasures&) = default;
};

struct MeasureOptions {
  /// A void component counts as a labyrinth when it holds at least this share of the void
  /// nodes, in [0, 1]. Smaller ones are pockets cut off where the model's surface clips a
  /// channel (they still connect outside the model).
  double min_labyrinth_fraction = 0.01;
  int histogram_bins = 16;  ///< bins of each SizeDistribution histogram (>= 1)
  int smallest = 10;        ///< SizeDistribution::smallest's length at most (>= 0)
  /// Printability limits, mm (0: none): samples below them are counted (below_limit).
  double min_wall = 0, min_pore = 0;
  Progress* progress = nullptr;  ///< stage "measure"; may cancel between phases
};

/// Pore and wall sizes and void connectivity of the lattice clipped to the model.
///
/// solid = inside ∧ φ < 0; void = inside ∧ φ >= 0, except nodes at the smallest positive
/// float, which compose.hpp puts on a surface (neither phase).
/// - pore: distance from void to solid where nodes outside the model also count as void (a
///   pore that the model's surface cuts is measured as if it went on) and nodes beyond the
///   grid too; sampled at inside void nodes.
/// - wall: distance from solid to non-solid (outside the model is not solid, nor is beyond
///   the grid); sampled at solid nodes.
/// - components: 6-connected void nodes inside the model (two void nodes touching only at an
///   edge or a corner are separated by the solid between them).
/// Accuracy (a = grid.spacing, φ a distance near its zero level, measured over random
/// placements by the DISABLED_AccuracySurvey test): a diameter reads within ±a/2 where the
/// ridge is a sheet (between flat walls; +0.3a to +0.5a when the walls are oblique to the
/// grid), within −0.2a..+0.3a where it is a curve (a round channel), and within −1.1a..+0.2a
/// where it is a point (a spherical pore, the worst case being a centre mid-cell).
/// Near the model's surface, wall samples include the thin slivers where the surface cuts a
/// strut or sheet (they are real, and more of them are resolved on a finer grid), and pores may
/// read larger than the lattice's where a sphere can bulge out of the model past the cut walls.
/// Deterministic for any thread count.
/// @param phi     the composed field (solid where phi < 0), mm, on inside.grid
/// @param inside  the model's occupancy (1 = inside the model)
/// @throws InputError  grids or sizes disagree, histogram_bins < 1, smallest < 0, a limit
///                     negative or not finite, or min_labyrinth_fraction is not in [0, 1];
///                     the grid is too large for 32-bit node indices
/// @throws Cancelled   options.progress asked to stop
LatticeMeasures measure_lattice(const Field& phi, const Mask& inside,
                                const MeasureOptions& options = {});

}  // namespace tpmsfill
