// Usage errors in the tool's own words: CLI11's exceptions and the arguments it could not
// place become one sentence each, with a did-you-mean for misspelt options and commands.
#pragma once

#include <CLI/CLI.hpp>
#include <string>

namespace tpmsfill::cli {

/// The sentence for a parse error (without the "tpmsfill: error: " prefix).
std::string usage_error(const CLI::App& app, const CLI::ParseError& error, int argc,
                        const char* const* argv);

/// The sentence for arguments `command` could not place (CLI11's remaining()), or "" when
/// there are none: an unknown option (with the nearest known one) or an unexpected value.
std::string unplaced_arguments(const CLI::App& command);

/// The sentence for a first argument that is neither a command nor a top-level option (with
/// the nearest command or option), or "" when it is one of them.
std::string unknown_command(const CLI::App& app, int argc, const char* const* argv);

}  // namespace tpmsfill::cli
