/// @file material_layers.hpp
/// @brief A solid's direct slice as a printer layer with its material (Li & Fu 2021),
/// for layer_files.hpp's writers: CLI gets the contours (CLI has no material); SVG fills each
/// triangle of the section with the colour of its mean material (blue → green → yellow from
/// material_min to material_max), the contours over them; PNG stacks write 0 outside the
/// section and 1 + 254 (m − material_min) / (material_max − material_min) inside, m
/// interpolated over each triangle at the pixel's centre: a multi-material printer's mix per
/// pixel.
#pragma once

#include <cstdint>
#include <vector>

#include "tpmsfill/solid/solid_slice.hpp"
#include "tpmsfill/types.hpp"

namespace tpmsfill {

/// Layer `index` spanning [bottom, top] from its section (taken at section.z), its material
/// drawn on the scale [lo, hi].
Layer material_layer(const SolidSection& section, std::uint64_t index, double bottom, double top,
                     double lo, double hi);

/// The section's area per material bin: `bins` equal bins over [lo, hi] (values outside go to
/// the end bins), each triangle's area in the bin of its mean material; a multi-nozzle
/// printer's share of each material in the layer, mm².
std::vector<double> material_histogram(const SolidSection& section, double lo, double hi, int bins);

}  // namespace tpmsfill
