/// @file compose.hpp
/// @brief Stage "compose": the field whose zero level is the clipped lattice,
/// φ = max(φ_model, φ_L) (paper eq. 5), with φ_model sparse as in eq. 10, and an optional skin.
///
/// φ_L is any field source (field.hpp): a TPMS design (design_source), a caller's own. Off the
/// band φ_model is only known by its sign: at inside nodes it is below the lattice's values,
/// so φ = φ_L there; at outside nodes φ is the positive constant 1 + skin + source.bound and
/// the source is not evaluated at all. No node of the result equals 0: an exact zero (a model face
/// on a grid plane, the lattice surface through a node) becomes the smallest positive float, so
/// marching cubes never meets a sample on the iso-value.
///
/// Skin (Aremu et al. 2017): a solid shell of thickness s inside the model's surface, united
/// with the lattice so that no strut dangles at the boundary:
///   φ = max(φ_model, min(φ_L, −φ_model − s)).
/// A closed skin seals the lattice's void in; with windows the skin only covers what lies
/// within s/2 of the lattice's solid (φ_L < s/2), so every pore wider than s that meets the
/// surface opens through it (powder and resin can drain): skin = max(−φ_model − s, φ_L − s/2).
#pragma once

#include <vector>

#include "tpmsfill/field.hpp"
#include "tpmsfill/progress.hpp"
#include "tpmsfill/types.hpp"

namespace tpmsfill {

struct ComposeOptions {
  /// Skin thickness, mm (0: none). The band path needs distances that deep: the band's
  /// half-width must be at least skin_band_width(skin, grid.spacing) voxels.
  double skin = 0;
  /// Open the skin at the pores (see above) instead of sealing the void in.
  bool skin_windows = false;
  Progress* progress = nullptr;
};

/// @throws InputError  the skin is negative or not finite
void require_valid(const ComposeOptions& options);

/// Band half-width (voxels) whose distances reach a skin of `skin` mm: every node within
/// skin + one voxel of the surface is within this many 26-steps of the other side.
int skin_band_width(double skin, double spacing);

/// φ at every node from the band's signed distances.
/// @param[in] inside         occupancy (1 = inside)
/// @param[in] band           nodes with exact distances (band_voxels), on inside.grid
/// @param[in] band_distance  signed distance at band.nodes, mm (band_distances)
/// @param[in] lattice        φ_L, evaluated on inside.grid where the model does not decide
/// @throws InputError  grids or sizes disagree, the skin is negative, or bind_source refuses
///                     the source
/// @throws whatever the source throws
Field compose_field(const Mask& inside, const Band& band, const std::vector<float>& band_distance,
                    const FieldSource& lattice, const ComposeOptions& options = {});

/// φ at every node from a full signed distance field (the --full-field reference path).
Field compose_field(const Field& model_distance, const FieldSource& lattice,
                    const ComposeOptions& options = {});

}  // namespace tpmsfill
