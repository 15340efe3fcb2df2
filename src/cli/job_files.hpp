// The files a command reads and writes, settled before any work: an output that would
// replace the input, or that cannot be written, is refused up front (not after a long job),
// and the outputs are written together (every one or none).
#pragma once

#include <filesystem>
#include <optional>
#include <string>
#include <tpmsfill/layer_files.hpp>

#include <tpmsfill/report.hpp>
#include <utility>
#include <vector>
#include "io/interrupt_cleanup.hpp"

namespace tpmsfill::cli {

/// The layer format `format` (--format) names, else OUT's extension's (.cli, .svg, in any case),
/// else PNG layers when `png_otherwise` (slice's --pixel asks for them).
/// @throws InputError  an unknown format name, or no format to tell
LayerFormat layer_format_for(const std::string& output, const std::optional<std::string>& format,
                             bool png_otherwise = false);

/// An output file and the option that named it ("OUT", "--report").
struct OutputFile {
  std::string option;
  std::filesystem::path path;
};

/// @param inputs  the files the command reads (the mesh, a recipe)
/// @throws InputError  an output is an input (same file, or the same path once resolved), two
///                     outputs are one file, an output names a folder, or its folder does not
///                     exist or cannot be written to
void require_writable_outputs(const std::vector<std::filesystem::path>& inputs,
                              const std::vector<OutputFile>& outputs);

/// Outputs staged in temporary files beside their targets and renamed onto them together by
/// commit(); whatever is not committed is removed, so a failure leaves every target as it was.
class StagedOutputs {
 public:
  StagedOutputs() = default;
  StagedOutputs(const StagedOutputs&) = delete;
  StagedOutputs& operator=(const StagedOutputs&) = delete;
  ~StagedOutputs();
  /// A temporary path in `target`'s folder to write `target`'s content to.
  std::filesystem::path stage(const std::filesystem::path& target);
  /// Renames every staged file onto its target.
  /// @throws IoError  a rename failed (the targets renamed before it are restored)
  void commit();

 private:
  std::vector<std::pair<std::filesystem::path, std::filesystem::path>> staged_;  // temp, target
  std::vector<detail::RemovedOnInterrupt> interrupt_;  // the temps, removed on SIGINT/SIGTERM
};

/// A folder of layers, written under a temporary name beside its target and renamed onto it
/// by commit(); a target that exists must be a folder tpmsfill wrote (it holds index.json) or
/// empty, so no other folder is ever replaced. Not committed: removed.
class StagedFolder {
 public:
  /// @throws InputError  the target is a file, or a folder with other files, or its folder
  ///                     does not exist
  /// @throws IoError     the temporary folder cannot be made
  explicit StagedFolder(std::filesystem::path target);
  StagedFolder(const StagedFolder&) = delete;
  StagedFolder& operator=(const StagedFolder&) = delete;
  ~StagedFolder();
  const std::filesystem::path& path() const { return temp_; }
  /// @throws IoError  the rename failed (the target is left as it was)
  void commit();

 private:
  std::filesystem::path target_, temp_;
  detail::RemovedOnInterrupt interrupt_;
};

/// SHA-256 of a file's bytes as stored, lower-case hex.
/// @throws IoError  the file cannot be read
std::string sha256_of_file(const std::filesystem::path& path);

/// Where a report came from: the input's path and SHA-256, the command line, the version.
void record_provenance(JobReport& report, const std::string& input);

/// One "tpmsfill: warning: ..." line on stderr for each.
void print_warnings(const std::vector<std::string>& warnings);

/// The command line as typed, each argument shell-quoted where it needs to be; set once by
/// main().
void set_command_line(int argc, const char* const* argv);
const std::string& command_line();

}  // namespace tpmsfill::cli
