/// @file file_bytes.hpp
/// @brief A whole file into memory, refusing folders and files over a size limit before
/// reading: what every reader starts from; and scratch files beside an output, for what a
/// writer cannot hold.
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>

namespace tpmsfill::detail {

/// @throws IoError     the file cannot be opened or read, or is a folder
/// @throws InputError  the file is larger than max_bytes
std::string read_file_bytes(const std::filesystem::path& path, std::uint64_t max_bytes);

/// A path's extension in lower case (".STL" and ".Tsm" name what ".stl" and ".tsm" do).
std::string lower_extension(const std::filesystem::path& path);

/// A new empty file in `output`'s folder (on the disk that must hold the output anyway),
/// removed from the folder at once: it lives while the returned descriptor is open and is gone
/// however the process ends. Named "." + output's name + "." + tag + "-XXXXXX" while it exists.
/// @throws IoError  "cannot write OUTPUT: cannot create a temporary file in FOLDER: ..."
int open_scratch_file(const std::filesystem::path& output, const std::string& tag);

}  // namespace tpmsfill::detail
