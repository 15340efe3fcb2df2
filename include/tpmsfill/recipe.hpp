/// @file recipe.hpp
/// @brief Recipes: everything a fill job sets (grid, inside rule, TPMS design, grading,
/// blends, skin) as one JSON object, for reproducible jobs. recipe_json(FillResult::resolved)
/// is the recipe of the job as it ran (porosities solved, ramp positions fixed), so rerunning
/// it reproduces the output exactly; `tpmsfill fill --report` echoes it. Keys and an example:
/// docs/recipes.md.
#pragma once

#include <string>
#include <string_view>

#include "tpmsfill/fill.hpp"

namespace tpmsfill {

/// Options from a recipe. Keys the recipe leaves out keep their values in `defaults`; inside
/// a blend, lattice keys left out are the base lattice's.
/// @param source  file name for messages
/// @throws ParseError  "SOURCE:LINE: not valid JSON: ..." for malformed JSON
/// @throws InputError  "SOURCE: KEY.PATH: ..." for an unknown key, a value of the wrong type, or
///                     a value out of range; "SOURCE: ..." for a design that fails require_valid
FillOptions read_recipe(std::string_view json, const std::string& source,
                        const FillOptions& defaults = {});
/// read_recipe on a file's bytes.
/// @throws IoError  unreadable file
FillOptions read_recipe_file(const std::string& path, const FillOptions& defaults = {});

/// The recipe that sets `options` (2-space indent). A custom field source cannot be written:
/// the recipe says "custom": true and read_recipe refuses it.
std::string recipe_json(const FillOptions& options);

}  // namespace tpmsfill
