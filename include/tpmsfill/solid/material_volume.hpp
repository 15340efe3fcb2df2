/// @file material_volume.hpp
/// @brief A fitted solid's material in mm, m(p) = M(G⁻¹(p)), sampled onto a volume (beyond
/// Li & Fu 2021): what a lattice is graded by, so that a density-graded scaffold follows a
/// CT or a stiffness map (design.hpp's RampShape::Volume).
///
/// Inverting G at every node of a fill's grid would cost a Newton solve per node; the
/// material is smooth, so it is sampled once on a coarse grid of cubic cells over the solid's
/// box and read back trilinearly (volume.hpp's sample_volume). Nodes outside the solid take
/// the mean of their sampled neighbours, layer by layer outwards, so the volume is continuous
/// across the surface and a lattice clipped there sees the surface's own material.
#pragma once

#include <filesystem>

#include "tpmsfill/io/volume.hpp"
#include "tpmsfill/progress.hpp"
#include "tpmsfill/solid/solid_spline.hpp"

namespace tpmsfill {

struct MaterialVolumeOptions {
  int cells = 64;                ///< samples along the solid's longest side (4 to 512)
  int padding = 2;               ///< sample layers beyond the solid's box on every side
  Progress* progress = nullptr;  ///< stage "material volume"
};

/// What was sampled, beside the volume.
struct MaterialVolume {
  ScalarVolume volume;      ///< values at the samples, mm spacing, FieldSign::Unknown
  std::size_t inside = 0;   ///< samples inside the solid (M(G⁻¹) there); the rest extended
  double min = 0, max = 0;  ///< the material's range over the inside samples
};

/// m(p) = M(G⁻¹(p)) at the centres of cubic cells over G's image (solid_inverse.hpp), extended
/// outwards past the surface. Deterministic whatever the thread count.
/// @throws InputError  a spline without material, cells outside 4 to 512, padding outside 1
///                     to 16, no sample inside the solid
/// @throws Cancelled   the progress asked to stop
MaterialVolume material_volume(const SolidSpline& spline,
                               const MaterialVolumeOptions& options = {});

/// The volume a lattice is graded by, from a file: a fitted model's material (.tsm, sampled by
/// material_volume) or a volume file (NRRD, MetaImage, INR, .tdf/.tdfb: a CT's intensities)
/// with a physical size.
/// @throws IoError, ParseError  as read_solid_model() or read_volume_file()
/// @throws InputError  a model without material, a volume without a physical size
ScalarVolume read_grading_volume(const std::filesystem::path& path,
                                 const MaterialVolumeOptions& options = {});

}  // namespace tpmsfill
