/// @file units.hpp
/// @brief Stage "units": the length unit a mesh file was modelled in, and the scale that takes
/// it to millimetres, tpmsfill's one unit.
///
/// Mesh files carry no unit. A part modelled in metres and read as millimetres is a thousand
/// times too small, and every millimetre setting (cell, voxel, skin) is then wrong by that
/// factor without any error. So every command takes the input's unit, converts the model to
/// millimetres on entry (outputs are millimetres), records both in its report, and names the
/// likely unit when a model's size is implausible for what was asked (likely_units).
#pragma once

#include <optional>
#include <string>
#include <string_view>

#include "tpmsfill/types.hpp"

namespace tpmsfill {

enum class Units { Millimetre, Centimetre, Metre, Inch, Micrometre };

/// How a model's coordinates become millimetres: × millimetres_per(units) × scale.
struct ModelUnits {
  Units units = Units::Millimetre;
  double scale = 1;  ///< a further factor (> 0), e.g. to print at another size
  /// Millimetres per model coordinate.
  double factor() const;
};

/// "mm", "cm", "m", "in", "um".
std::string_view units_name(Units units);
/// Inverse of units_name (also accepts "inch", "µm", "micron", "millimetre", ...).
/// @throws InputError  unknown name (the message lists the known ones)
Units units_from_name(std::string_view name);
/// 1, 10, 1000, 25.4, 0.001.
double millimetres_per(Units units);

/// @throws InputError  scale not finite and > 0
void require_valid(const ModelUnits& units);

/// `soup` in millimetres: its points multiplied by units.factor() (a copy; the soup itself
/// when the factor is 1).
TriangleSoup to_millimetres(TriangleSoup soup, const ModelUnits& units);

/// The unit a model most likely was modelled in, if reading it as `assumed` makes it
/// implausible for a printed part: its longest side (in that unit, as millimetres) below
/// `smallest_mm` or above 5000 mm. The guess is the unit that brings the longest side nearest
/// 100 mm (a typical part); none when no other unit does better.
std::optional<Units> likely_units(const Box3& box_mm, Units assumed, double smallest_mm = 1.0);

/// "; if it is in metres, add --units m" for likely_units' guess, "" without one: the hint
/// every size message ends with.
std::string units_hint(const Box3& box_mm, Units assumed, double smallest_mm = 1.0);

}  // namespace tpmsfill
