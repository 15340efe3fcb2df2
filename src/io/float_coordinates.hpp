/// @file float_coordinates.hpp
/// @brief Points rounded to float before a mesh is validated, so that formats storing floats
/// (binary STL, PLY) hold exactly the mesh that was validated: fill and repair both do it; and
/// as the layer files' six decimals hold them.
#pragma once

#include <array>
#include <charconv>

#include "tpmsfill/types.hpp"

namespace tpmsfill::detail {

/// `c` rounded to the nearest float. The volatile is a fence: GCC 12 at -O2 and above (its
/// SLP vectorizer) drops the double -> float -> double round trip of a single point in place,
/// leaving it unrounded (seen on Debian's 12.2 with fill_to_file's records).
inline double float_value(double c) {
  volatile float f = static_cast<float>(c);
  return f;
}

/// `c` as six decimals of fixed point (std::to_chars, as the layer files print it) read back.
inline double six_decimals_value(double c) {
  std::array<char, 400> text;  // the longest double in fixed notation, with room to spare
  const auto printed =
      std::to_chars(text.data(), text.data() + text.size(), c, std::chars_format::fixed, 6);
  double read = c;
  std::from_chars(text.data(), printed.ptr, read);
  return read;
}

/// `p` with each coordinate rounded to the nearest float.
inline Vec3 float_rounded(Vec3 p) {
  return {float_value(p.x), float_value(p.y), float_value(p.z)};
}

/// Every coordinate rounded to the nearest float (round to nearest, ties to even).
inline void round_to_float(TriangleSoup& soup) {
  for (Vec3& p : soup.points) p = float_rounded(p);
}

}  // namespace tpmsfill::detail
