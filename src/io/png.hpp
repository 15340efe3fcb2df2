/// @file png.hpp
/// @brief An 8-bit PNG encoder over zlib: what the layer writer's masks and the docs' renderer
/// (render.hpp: `tpmsfill render`, `fill --preview`, `check --picture`) both write.
#pragma once

#include <cstdint>
#include <string>

namespace tpmsfill::detail {

/// PNG bytes: signature, IHDR (8 bits per sample, not interlaced), pHYs if asked, one IDAT,
/// IEND. Each row takes the filter (None, Sub, Up, Average, Paeth) whose output has the
/// smallest sum of |signed bytes|, the heuristic the PNG specification recommends.
/// @param[in] width, height       pixels (> 0)
/// @param[in] channels            1: greyscale (colour type 0); 3: RGB (colour type 2)
/// @param[in] pixels              width·height·channels bytes, rows top to bottom, channels
///                                interleaved
/// @param[in] pixels_per_metre    written as a pHYs chunk (same on both axes) when > 0, so
///                                printing software sees the physical scale
/// @throws std::invalid_argument  a size or channel count outside the above
/// @throws std::runtime_error     zlib failed (out of memory)
std::string encode_png(int width, int height, int channels, const std::uint8_t* pixels,
                       std::uint32_t pixels_per_metre = 0);

}  // namespace tpmsfill::detail
