/// @file report_text.hpp
/// @brief The job's part of a report (JobReport), which fill and slice write the same way:
/// its JSON keys and its human summary's lines.
#pragma once

#include <nlohmann/json.hpp>
#include <string>

#include "tpmsfill/report.hpp"

namespace tpmsfill::detail {

/// The job's keys of `tpmsfill fill --report`, in the report's order (docs/cli.md): warnings,
/// provenance, input, lattice, grid, the field's and classification's counts, inside, memory,
/// ranks, the model's volume, the unclipped porosity, printability (its limits; the figures
/// below them are null without measures), stages, total seconds, peak memory and the recipe.
nlohmann::ordered_json job_json(const JobReport& report);

/// "lattice ...", "grading ...", "input ..." lines: what was asked, resolved.
std::string settings_text(const JobReport& report);
/// How inside was decided, one line's worth (no label, no newline).
std::string inside_text(const JobReport& report);
/// "warning ..." lines and the stage table with its total.
std::string closing_text(const JobReport& report);

}  // namespace tpmsfill::detail
