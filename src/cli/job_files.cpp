// Output guards, staged outputs and the job's provenance (SHA-256 by nettle).
#include "cli/job_files.hpp"

#include <fcntl.h>
#include <nettle/sha2.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <system_error>
#include <tpmsfill/error.hpp>

#include "cli/printable.hpp"
#include "io/file_bytes.hpp"

namespace tpmsfill::cli {

LayerFormat layer_format_for(const std::string& output, const std::optional<std::string>& format,
                             bool png_otherwise) {
  if (format) return layer_format_from_name(*format);
  const std::string ext = tpmsfill::detail::lower_extension(output);
  if (ext == ".cli") return LayerFormat::Cli;
  if (ext == ".svg") return LayerFormat::Svg;
  if (png_otherwise) return LayerFormat::PngLayers;
  throw InputError(output +
                   ": unknown extension (use .cli or .svg, or --format svg-layers or png with a "
                   "folder)");
}
namespace fs = std::filesystem;

namespace {

// The same file: the same device and inode when both exist (hard links, symlinks, "./a"
// and "a"), else the same path once made absolute and normalised.
bool same_file(const fs::path& a, const fs::path& b) {
  std::error_code ec;
  if (fs::exists(a, ec) && fs::exists(b, ec)) return fs::equivalent(a, b, ec);
  return fs::weakly_canonical(fs::absolute(a), ec) == fs::weakly_canonical(fs::absolute(b), ec);
}

fs::path folder_of(const fs::path& p) {
  return p.has_parent_path() ? p.parent_path() : fs::path(".");
}

}  // namespace

void require_writable_outputs(const std::vector<fs::path>& inputs,
                              const std::vector<OutputFile>& outputs) {
  for (std::size_t i = 0; i < outputs.size(); ++i) {
    const OutputFile& out = outputs[i];
    const std::string name = out.option + " " + out.path.string();
    for (const fs::path& input : inputs)
      if (same_file(out.path, input))
        throw InputError(name + " is the input file " + input.string() +
                         ": it would be overwritten; write elsewhere");
    for (std::size_t j = 0; j < i; ++j)
      if (same_file(out.path, outputs[j].path))
        throw InputError(name + " is also " + outputs[j].option + ": give them different files");
    std::error_code ec;
    if (fs::is_directory(out.path, ec)) throw InputError(name + " is a folder, not a file");
    const fs::path folder = folder_of(out.path);
    if (!fs::is_directory(folder, ec))
      throw InputError(name + ": the folder " + folder.string() + " does not exist");
    if (::access(folder.c_str(), W_OK) != 0)
      throw InputError(name + ": the folder " + folder.string() +
                       " cannot be written to: " + std::strerror(errno));
  }
}

StagedOutputs::~StagedOutputs() {
  std::error_code ec;
  for (const auto& [temp, target] : staged_) fs::remove(temp, ec);
}

fs::path StagedOutputs::stage(const fs::path& target) {
  // Hidden, beside the target (a rename within a folder is atomic), and unique per process.
  std::string name(1, '.');
  name += target.filename().string();
  name += ".staged-";
  name += std::to_string(::getpid());
  name += '-';
  name += std::to_string(staged_.size());
  const fs::path temp = folder_of(target) / name;
  staged_.emplace_back(temp, target);
  interrupt_.emplace_back(temp, detail::RemovedOnInterrupt::Kind::File);
  return temp;
}

void StagedOutputs::commit() {
  // Each target is first moved aside, so a failure part-way can put the earlier ones back.
  std::vector<std::pair<fs::path, fs::path>> moved;  // backup, target
  std::error_code ec;
  auto roll_back = [&] {
    for (const auto& [backup, target] : moved) {
      fs::remove(target, ec);
      if (!backup.empty()) fs::rename(backup, target, ec);
    }
  };
  for (const auto& [temp, target] : staged_) {
    fs::path backup;
    if (fs::exists(target, ec)) {
      backup = temp;
      backup += ".previous";
      if (::rename(target.c_str(), backup.c_str()) != 0) {
        const std::string why = std::strerror(errno);
        roll_back();
        throw IoError("cannot replace " + target.string() + ": " + why);
      }
    }
    moved.emplace_back(backup, target);
    if (::rename(temp.c_str(), target.c_str()) != 0) {
      const std::string why = std::strerror(errno);
      roll_back();
      throw IoError("cannot write " + target.string() + ": " + why + "; nothing was written");
    }
  }
  for (const auto& [backup, target] : moved)
    if (!backup.empty()) fs::remove(backup, ec);
  staged_.clear();
  interrupt_.clear();
}

std::string sha256_of_file(const fs::path& path) {
  const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
  if (fd < 0) throw IoError("cannot open " + path.string() + ": " + std::strerror(errno));
  sha256_ctx ctx;
  sha256_init(&ctx);
  std::vector<std::uint8_t> buffer(1 << 20);
  for (;;) {
    const ssize_t n = ::read(fd, buffer.data(), buffer.size());
    if (n < 0 && errno == EINTR) continue;
    if (n < 0) {
      const std::string why = std::strerror(errno);
      ::close(fd);
      throw IoError("cannot read " + path.string() + ": " + why);
    }
    if (n == 0) break;
    sha256_update(&ctx, static_cast<std::size_t>(n), buffer.data());
  }
  ::close(fd);
  std::uint8_t digest[SHA256_DIGEST_SIZE];
  sha256_digest(&ctx, sizeof digest, digest);
  std::string hex;
  for (std::uint8_t b : digest) {
    char two[3];
    std::snprintf(two, sizeof two, "%02x", b);
    hex += two;
  }
  return hex;
}

namespace {
std::string& stored_command_line() {
  static std::string line;
  return line;
}
}  // namespace

void set_command_line(int argc, const char* const* argv) {
  std::string& line = stored_command_line();
  line.clear();
  for (int i = 0; i < argc; ++i) {
    const std::string a = argv[i];
    const bool plain = !a.empty() && a.find_first_not_of(
                                         "abcdefghijklmnopqrstuvwxyz"
                                         "ABCDEFGHIJKLMNOPQRSTUVWXYZ"
                                         "0123456789-_./=:,+@%") == std::string::npos;
    std::string quoted = "'";
    for (char c : a) quoted += c == '\'' ? std::string("'\\''") : std::string(1, c);
    line += (i ? " " : "") + (plain ? a : quoted + "'");
  }
}

const std::string& command_line() {
  return stored_command_line();
}

void record_provenance(JobReport& report, const std::string& input) {
  report.input_path = input;
  report.input_sha256 = sha256_of_file(input);
  report.command_line = command_line();
  report.version = TPMSFILL_VERSION;
}

void print_warnings(const std::vector<std::string>& warnings) {
  for (const std::string& w : warnings)
    std::fprintf(stderr, "tpmsfill: warning: %s\n", printable(w).c_str());
}

StagedFolder::StagedFolder(std::filesystem::path target) : target_(std::move(target)) {
  if (target_.filename().empty()) target_ = target_.parent_path();
  std::error_code ec;
  if (fs::exists(target_, ec)) {
    if (!fs::is_directory(target_, ec))
      throw InputError(target_.string() + ": exists and is not a folder (the layers need one)");
    if (!fs::is_empty(target_, ec) && !fs::exists(target_ / "index.json", ec))
      throw InputError(target_.string() +
                       ": a folder with other files in it; give a new or empty folder");
  }
  const fs::path parent = target_.has_parent_path() ? target_.parent_path() : fs::path(".");
  if (!fs::is_directory(parent, ec))
    throw InputError(target_.string() + ": its folder " + parent.string() + " does not exist");
  temp_ = parent / (target_.filename().string() + ".tmp-" + std::to_string(getpid()));
  fs::remove_all(temp_, ec);
  if (!fs::create_directory(temp_, ec))
    throw IoError(temp_.string() + ": cannot create the folder (" + ec.message() + ")");
  interrupt_ = detail::RemovedOnInterrupt(temp_, detail::RemovedOnInterrupt::Kind::Folder);
}

StagedFolder::~StagedFolder() {
  std::error_code ec;
  if (!temp_.empty()) fs::remove_all(temp_, ec);
}

void StagedFolder::commit() {
  std::error_code ec;
  const fs::path old = target_.string() + ".old-" + std::to_string(getpid());
  const bool existed = fs::exists(target_, ec);
  if (existed) fs::rename(target_, old, ec);
  if (!ec) fs::rename(temp_, target_, ec);
  if (ec) {
    if (existed) fs::rename(old, target_, ec);
    throw IoError(target_.string() + ": cannot put the layers in place");
  }
  temp_.clear();
  interrupt_.release();
  if (existed) fs::remove_all(old, ec);
}

}  // namespace tpmsfill::cli
