// The subcommands of the `tpmsfill` program. Each registers its options on the CLI11 app and
// returns the function that runs it; main() maps exceptions to exit codes (docs/cli.md).
#pragma once

#include <CLI/CLI.hpp>
#include <functional>
#include <optional>

namespace tpmsfill::cli {

/// Exit codes shared by all commands.
enum ExitCode : int {
  kOk = 0,  ///< the command did what was asked (check: the mesh is valid)
  /// check: the mesh is not a valid closed 2-manifold; fill: the lattice failed validation;
  /// repair: the mesh could not be made valid (nothing written)
  kNotValid = 1,
  kBadInput = 2,  ///< the input cannot be read, or the command line is wrong
  kInternal = 3,  ///< a bug: an unexpected exception
};

using Command = std::function<int()>;

Command add_check_command(CLI::App& app);
Command add_fill_command(CLI::App& app);
Command add_repair_command(CLI::App& app);
Command add_decimate_command(CLI::App& app);
Command add_field_command(CLI::App& app);
Command add_conformal_command(CLI::App& app);
Command add_slice_command(CLI::App& app);
Command add_render_command(CLI::App& app);
Command add_material_command(CLI::App& app);
Command add_serve_command(CLI::App& app);
/// `material slice` and `material iso` (cmd_material_model.cpp): adds them to `material` and
/// returns what runs the one parsed (nothing when neither was).
std::function<std::optional<int>()> add_material_model_commands(CLI::App* material);

}  // namespace tpmsfill::cli
