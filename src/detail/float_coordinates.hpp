/// @file float_coordinates.hpp
/// @brief Points rounded to float before a mesh is validated, so that formats storing floats
/// (binary STL, PLY) hold exactly the mesh that was validated: fill and repair both do it.
#pragma once

#include "tpmsfill/types.hpp"

namespace tpmsfill::detail {

/// Every coordinate rounded to the nearest float (round to nearest, ties to even).
inline void round_to_float(TriangleSoup& soup) {
  for (Vec3& p : soup.points)
    p = {static_cast<float>(p.x), static_cast<float>(p.y), static_cast<float>(p.z)};
}

}  // namespace tpmsfill::detail
