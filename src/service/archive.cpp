#include "service/archive.hpp"

#include <zip.h>

#include <algorithm>
#include <memory>
#include <string>
#include <tpmsfill/error.hpp>
#include <vector>

namespace tpmsfill::service {

namespace fs = std::filesystem;

void zip_folder(const fs::path& folder, const fs::path& archive) {
  std::vector<fs::path> files;
  for (const auto& entry : fs::directory_iterator(folder))
    if (entry.is_regular_file()) files.push_back(entry.path());
  std::sort(files.begin(), files.end());

  const fs::path temporary = archive.string() + ".part";
  std::error_code ec;
  fs::remove(temporary, ec);
  int error = 0;
  zip_t* zip = zip_open(temporary.c_str(), ZIP_CREATE | ZIP_EXCL, &error);
  if (!zip) throw IoError(temporary.string() + ": cannot make the archive");
  const auto fail = [&](const std::string& what) {
    const std::string reason = zip_strerror(zip);
    zip_discard(zip);
    fs::remove(temporary, ec);
    throw IoError(what + ": " + reason);
  };
  for (const fs::path& file : files) {
    // The source reads the file (0, -1: all of it) when the archive is closed; nothing is
    // held in memory.
    zip_source_t* source = zip_source_file(zip, file.c_str(), 0, -1);
    if (!source) fail(file.string());
    const zip_int64_t index = zip_file_add(zip, file.filename().c_str(), source, ZIP_FL_ENC_UTF_8);
    if (index < 0) {
      zip_source_free(source);
      fail(file.string());
    }
    const bool png = file.extension() == ".png";
    if (zip_set_file_compression(zip, static_cast<zip_uint64_t>(index),
                                 png ? ZIP_CM_STORE : ZIP_CM_DEFLATE, 0) != 0)
      fail(file.string());
  }
  if (zip_close(zip) != 0) fail(archive.string());
  fs::rename(temporary, archive, ec);
  if (ec) {
    fs::remove(temporary, ec);
    throw IoError(archive.string() + ": cannot write the archive");
  }
}

}  // namespace tpmsfill::service
