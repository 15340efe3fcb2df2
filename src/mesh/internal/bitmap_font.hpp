/// @file bitmap_font.hpp
/// @brief A 5×7 bitmap font for the text render_mesh() writes into pictures (the legend):
/// upper-case letters, digits and common punctuation, nothing to load at run time.
#pragma once

#include <array>
#include <cstdint>

namespace tpmsfill::detail {

/// Glyph cells: 5 columns, 7 rows; text advances 6 columns a character.
inline constexpr int kGlyphWidth = 5, kGlyphHeight = 7, kGlyphAdvance = 6;

/// The glyph of `c`, one byte a row from the top, bit 4 the leftmost column. Lower-case
/// letters give their capitals; characters the font lacks give '?'; ' ' is blank.
const std::array<std::uint8_t, kGlyphHeight>& glyph(char c);

}  // namespace tpmsfill::detail
