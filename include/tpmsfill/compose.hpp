/// @file compose.hpp
/// @brief Stage "compose": the field whose zero level is the clipped lattice,
/// φ = max(φ_model, φ_TPMS) (paper eq. 5), with φ_model sparse as in eq. 10.
///
/// Off the band, φ_model is a constant: below min φ_TPMS at inside nodes (so φ = φ_TPMS) and
/// above max φ_TPMS at outside nodes (so φ is that constant, and the TPMS is not evaluated
/// there at all). No node of the result equals 0: an exact zero (a model face on a grid
/// plane, the lattice surface through a node) becomes the smallest positive float, so marching
/// cubes never meets a sample on the iso-value.
#pragma once

#include <vector>

#include "tpmsfill/progress.hpp"
#include "tpmsfill/tpms.hpp"
#include "tpmsfill/types.hpp"

namespace tpmsfill {

/// The constants φ_model takes off the band (eq. 10): strictly outside tpms_range(lattice).
FieldRange off_band_values(const TpmsOptions& lattice);

/// φ at every node from the band's signed distances.
/// @param[in] inside         occupancy (1 = inside)
/// @param[in] band           nodes with exact distances (band_voxels), on inside.grid
/// @param[in] band_distance  signed distance at band.nodes, mm (band_distances)
/// @throws InputError  grids or sizes disagree
Field compose_field(const Mask& inside, const Band& band, const std::vector<float>& band_distance,
                    const TpmsOptions& lattice, Progress* progress = nullptr);

/// φ at every node from a full signed distance field (the --full-field reference path).
Field compose_field(const Field& model_distance, const TpmsOptions& lattice,
                    Progress* progress = nullptr);

}  // namespace tpmsfill
