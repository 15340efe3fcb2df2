/// @file thread_flags.hpp
/// @brief `--threads N`, the one flag every command that runs parallel work takes, and the TBB
/// limit it sets.
#pragma once

#include <tbb/global_control.h>

#include <CLI/CLI.hpp>
#include <cstddef>
#include <optional>

#include "cli/validators.hpp"

namespace tpmsfill::cli {

/// Adds `--threads N` (1 to 1024; 0, the default, means all cores) to `sub`.
inline void add_threads_option(CLI::App* sub, int& threads) {
  sub->add_option("--threads", threads, "Worker threads (default: all cores)")
      ->check(between(1, 1024, "1 to 1024"));
}

/// The TBB limit for `--threads` (none for 0): keep it alive while the command runs.
inline std::optional<tbb::global_control> thread_limit(int threads) {
  if (threads <= 0) return std::nullopt;
  return std::optional<tbb::global_control>(std::in_place,
                                            tbb::global_control::max_allowed_parallelism,
                                            static_cast<std::size_t>(threads));
}

}  // namespace tpmsfill::cli
