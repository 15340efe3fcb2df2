/// @file file_bytes.hpp
/// @brief A whole file into memory, refusing folders and files over a size limit before
/// reading: what every reader starts from.
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>

namespace tpmsfill::detail {

/// @throws IoError     the file cannot be opened or read, or is a folder
/// @throws InputError  the file is larger than max_bytes
std::string read_file_bytes(const std::filesystem::path& path, std::uint64_t max_bytes);

}  // namespace tpmsfill::detail
