// `--grade-along` and `--threshold-ramp`'s WHERE: one parser for both commands.
#pragma once

#include <string>
#include <tpmsfill/error.hpp>
#include <tpmsfill/lattice/design.hpp>

namespace tpmsfill::cli {

// --grade-along: a direction (x, y, z), radial from the model's centre (radial) or from an
// axis through it (radial-x, ...), or depth below the surface.
inline Ramp ramp_along(const std::string& along, const std::string& flag = "--grade-along") {
  static const char* axes = "xyz";
  for (int a = 0; a < 3; ++a) {
    Vec3 axis{};
    (a == 0 ? axis.x : a == 1 ? axis.y : axis.z) = 1;
    if (along == std::string(1, axes[a])) return {.shape = RampShape::Linear, .axis = axis};
    if (along == std::string("radial-") + axes[a])
      return {.shape = RampShape::Radial, .axis = axis};
  }
  if (along == "radial") return {.shape = RampShape::Radial, .axis = {0, 0, 0}};
  if (along == "depth") return {.shape = RampShape::Depth};
  throw InputError(flag + ": '" + along +
                   "' is not x, y, z, radial, radial-x, radial-y, radial-z or depth");
}

}  // namespace tpmsfill::cli
