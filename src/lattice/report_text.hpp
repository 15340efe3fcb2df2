/// @file report_text.hpp
/// @brief The pieces of fill's human summary that other jobs on fill's field (slice) print
/// the same way.
#pragma once

#include <string>

#include "tpmsfill/report.hpp"

namespace tpmsfill::detail {

/// "lattice ...", "grading ...", "input ..." lines: what was asked, resolved.
std::string settings_text(const FillReport& report);
/// How inside was decided, one line's worth (no label, no newline).
std::string inside_text(const FillReport& report);
/// "warning ..." lines and the stage table with its total.
std::string closing_text(const FillReport& report);

}  // namespace tpmsfill::detail
