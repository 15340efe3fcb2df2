// --progress, one flag for every command that shows progress: the same name, values and sentence.
#pragma once

#include <CLI/CLI.hpp>
#include <string>

#include "cli/terminal_progress.hpp"

namespace tpmsfill::cli {

/// Adds --progress to `sub`; it sets progress_mode() for the run. main.cpp adds it to every
/// command that takes --quiet; a command that shows progress without one adds it itself.
inline CLI::Option* add_progress_flag(CLI::App* sub) {
  return sub
      ->add_option_function<std::string>(
          "--progress",
          [](const std::string& name) { progress_mode() = progress_mode_named(name); },
          "How progress is shown on stderr: auto (a bar on a terminal, else a line every 10 s "
          "once a job has run 5 s), bar, lines, json (one object a line: stage, percent, "
          "overall, seconds) or none")
      ->check(CLI::IsMember({"auto", "bar", "lines", "json", "none"}));
}

}  // namespace tpmsfill::cli
