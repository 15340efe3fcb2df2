// A folder of layer files (slice's svg-layers and png formats) as the one file a job's result
// is: a zip archive, through Debian's libzip.
#pragma once

#include <filesystem>

namespace tpmsfill::service {

/// Writes every regular file directly in `folder` into the zip `archive`, in name order: PNG
/// masks stored as they are (already compressed), everything else deflated. Written through a
/// temporary file beside `archive` and a rename: a failure leaves no archive.
/// @throws IoError  a file cannot be read, or the archive cannot be written
void zip_folder(const std::filesystem::path& folder, const std::filesystem::path& archive);

}  // namespace tpmsfill::service
