/// @file interrupt_cleanup.hpp
/// @brief Temporaries removed when the process is interrupted: a writer registers its staged
/// file or folder while it exists, and the command line's SIGINT/SIGTERM/SIGHUP handler removes
/// whatever is registered before the process ends (an interrupted fill left 100-195 MB
/// temporaries, and slice a folder of layers, beside the outputs).
#pragma once

#include <filesystem>

namespace tpmsfill::detail {

/// Registers `path` (a file, or a folder of files) for removal on interrupt while this object
/// lives. A path that cannot be registered (too long, or over 64 at once) is simply not
/// removed on interrupt; the writer's own clean-up still runs on errors.
class RemovedOnInterrupt {
 public:
  enum class Kind { File, Folder };
  RemovedOnInterrupt() = default;
  RemovedOnInterrupt(const std::filesystem::path& path, Kind kind);
  ~RemovedOnInterrupt() { release(); }
  RemovedOnInterrupt(RemovedOnInterrupt&& other) noexcept : slot_(other.slot_) { other.slot_ = -1; }
  RemovedOnInterrupt& operator=(RemovedOnInterrupt&& other) noexcept;

  /// The path is no longer this process's to remove (renamed into place, or removed).
  void release();

 private:
  int slot_ = -1;
};

/// Removes every registered path: async-signal-safe (unlink, and getdents64 with unlinkat for
/// a folder's files), for a signal handler.
void remove_registered_paths() noexcept;

/// Installs handlers for SIGINT, SIGTERM and SIGHUP that remove the registered paths and then
/// end the process as the signal would have (the exit status a shell shows stays 130, 143, ...).
/// A signal the process already ignores (nohup's SIGHUP) stays ignored.
void remove_registered_paths_on_signals();

}  // namespace tpmsfill::detail
