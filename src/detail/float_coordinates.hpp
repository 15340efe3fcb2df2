/// @file float_coordinates.hpp
/// @brief Points rounded to float before a mesh is validated, so that formats storing floats
/// (binary STL, PLY) hold exactly the mesh that was validated: fill and repair both do it.
#pragma once

#include "tpmsfill/types.hpp"

namespace tpmsfill::detail {

/// `c` rounded to the nearest float. The volatile is a fence: GCC 12 at -O2 and above (its
/// SLP vectorizer) drops the double -> float -> double round trip of a single point in place,
/// leaving it unrounded (seen on Debian's 12.2 with fill_to_file's records).
inline double float_value(double c) {
  volatile float f = static_cast<float>(c);
  return f;
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
