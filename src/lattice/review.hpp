/// @file review.hpp
/// @brief Stage "review": whether a design can come out as asked on this model at this
/// voxel size, before any work is done.
///
/// A closed 2-manifold is necessary, not sufficient: a lattice sampled too coarsely, a level
/// that leaves no solid, a ramp or blend that never reaches the model, or struts thinner than
/// two voxels all give valid meshes that are not the part the user asked for. The review
/// refuses what cannot come out as asked (InputError, one sentence with the number that
/// fits) and returns a warning for what is doubtful. It looks at every layer the design can
/// produce: the base, each end of each ramp, and each blend.
///
///  refused                                   warned
///  model smaller than one cell               model spans fewer than 3 cells
///  voxel > ½ of the smallest cell            voxel > ¼ of the smallest cell (aliased)
///  a layer with < 1 % solid or void          < 3 % solid or void
///  a ramp's range misses the model           the model sees < 10 % of the ramp's change
///  a blend region misses the model's box     covers < 8 of its cells; radial centre outside
///                                            struts, walls or pores thinner than 2 voxels
#pragma once

#include <string>
#include <vector>

#include "tpmsfill/lattice/design.hpp"
#include "tpmsfill/types.hpp"
#include "tpmsfill/units.hpp"

namespace tpmsfill {

struct ReviewOptions {
  double voxel = 0.1;                     ///< the grid spacing the job will use, mm
  Units input_units = Units::Millimetre;  ///< the unit the model was read in (for size hints)
};

/// Reviews `design` (resolved: resolve_design against `model`) for a model with box `model`.
/// @return warnings, one sentence each (empty: nothing doubtful)
/// @throws InputError  the design cannot come out as asked (the sentence says why and what
///                     fits)
std::vector<std::string> review_design(const LatticeDesign& design, const Box3& model,
                                       const ReviewOptions& options = {});

/// Diameters of the largest spheres that fit in one TPMS's solid and in its void, mm (its
/// thickest strut or wall and its widest pore), from a sampled distance transform.
struct LayerSizes {
  double solid = 0, pore = 0;
};
LayerSizes layer_sizes(const TpmsOptions& tpms);

}  // namespace tpmsfill
