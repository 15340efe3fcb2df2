// Units: names, factors, and the guess at the unit a mis-scaled model was modelled in.
#include "tpmsfill/units.hpp"

#include <algorithm>
#include <cmath>

#include "core/names.hpp"
#include "tpmsfill/error.hpp"

namespace tpmsfill {
namespace {

constexpr detail::Named<Units> kUnits[] = {
    {Units::Millimetre, "mm"}, {Units::Centimetre, "cm"},    {Units::Metre, "m"},
    {Units::Inch, "in"},       {Units::Micrometre, "um"},    {Units::Millimetre, "millimetre"},
    {Units::Metre, "metre"},   {Units::Metre, "meter"},      {Units::Inch, "inch"},
    {Units::Micrometre, "µm"}, {Units::Micrometre, "micron"}};

// The unit's name in a sentence: "if it is in metres".
const char* spoken(Units units) {
  switch (units) {
    case Units::Millimetre:
      return "millimetres";
    case Units::Centimetre:
      return "centimetres";
    case Units::Metre:
      return "metres";
    case Units::Inch:
      return "inches";
    case Units::Micrometre:
      return "micrometres";
  }
  return "";
}

}  // namespace

double ModelUnits::factor() const {
  return millimetres_per(units) * scale;
}

std::string_view units_name(Units units) {
  return detail::name_of(kUnits, units);
}

Units units_from_name(std::string_view name) {
  return detail::from_name(kUnits, name, "unit");
}

double millimetres_per(Units units) {
  switch (units) {
    case Units::Millimetre:
      return 1;
    case Units::Centimetre:
      return 10;
    case Units::Metre:
      return 1000;
    case Units::Inch:
      return 25.4;
    case Units::Micrometre:
      return 0.001;
  }
  return 1;
}

void require_valid(const ModelUnits& units) {
  if (!(units.scale > 0) || !std::isfinite(units.scale))
    throw InputError("the scale must be a finite number > 0");
}

TriangleSoup to_millimetres(TriangleSoup soup, const ModelUnits& units) {
  require_valid(units);
  const double f = units.factor();
  if (f != 1)
    for (Vec3& p : soup.points) p = f * p;
  return soup;
}

std::optional<Units> likely_units(const Box3& box_mm, Units assumed, double smallest_mm) {
  const Vec3 s = box_mm.size();
  const double longest = std::max({s.x, s.y, s.z});
  if (!(longest > 0) || (longest >= smallest_mm && longest <= 5000)) return std::nullopt;
  // Distance from a typical 100 mm part on a log scale; the model as it would be read in
  // unit u is longest × millimetres_per(u) / millimetres_per(assumed).
  auto misfit = [&](Units u) {
    return std::fabs(std::log10(longest * millimetres_per(u) / millimetres_per(assumed) / 100));
  };
  Units best = assumed;
  for (Units u :
       {Units::Millimetre, Units::Metre, Units::Inch, Units::Centimetre, Units::Micrometre})
    if (misfit(u) < misfit(best) - 0.3) best = u;  // better by a factor of 2 at least
  if (best == assumed) return std::nullopt;
  return best;
}

std::string units_hint(const Box3& box_mm, Units assumed, double smallest_mm) {
  const std::optional<Units> u = likely_units(box_mm, assumed, smallest_mm);
  if (!u) return "";
  return "; if it is in " + std::string(spoken(*u)) + ", add --units " +
         std::string(units_name(*u));
}

}  // namespace tpmsfill
