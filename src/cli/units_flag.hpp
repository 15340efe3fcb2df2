// --units, one flag for every command that reads a model: the same name, values and sentence.
#pragma once

#include <CLI/CLI.hpp>

namespace tpmsfill::cli {

/// Adds --units to `sub`, stored in `units` (a std::string defaulting to "mm", or a
/// std::optional<std::string> where unset means the recipe's or mm).
template <typename Units>
CLI::Option* add_units_flag(CLI::App* sub, Units& units) {
  return sub->add_option("--units", units,
                         "Unit the input was modelled in: mm, cm, m, in or um (default mm); it is "
                         "converted to millimetres, the unit of every length read, reported or "
                         "written");
}

}  // namespace tpmsfill::cli
