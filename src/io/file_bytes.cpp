#include "io/file_bytes.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cctype>
#include <cerrno>
#include <cstring>
#include <memory>

#include "tpmsfill/error.hpp"

namespace tpmsfill::detail {

int open_scratch_file(const std::filesystem::path& output, const std::string& tag) {
  const std::filesystem::path folder = output.has_parent_path() ? output.parent_path() : ".";
  std::string base(1, '.');
  base += output.filename().string();
  base += '.';
  base += tag;
  base += "-XXXXXX";
  std::string name = (folder / base).string();
  const int fd = ::mkstemp(name.data());
  if (fd < 0 || ::unlink(name.c_str()) != 0) {
    std::string message =
        "cannot write " + output.string() + ": cannot create a temporary file in ";
    message += folder.string();
    message += ": ";
    message += std::strerror(errno);
    if (fd >= 0) ::close(fd);
    throw IoError(message);
  }
  return fd;
}

std::string read_file_bytes(const std::filesystem::path& path, std::uint64_t max_bytes) {
  const std::string name = path.string();
  // O_NONBLOCK: opening a FIFO for reading would wait for a writer forever; it is refused
  // below with every other file that is not a regular one (devices, sockets).
  const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC | O_NONBLOCK);
  if (fd < 0) throw IoError("cannot open " + name + ": " + std::strerror(errno));
  const std::unique_ptr<const int, void (*)(const int*)> closer(&fd,
                                                                [](const int* f) { ::close(*f); });
  struct stat st {};
  if (::fstat(fd, &st) != 0) throw IoError("cannot read " + name + ": " + std::strerror(errno));
  if (S_ISDIR(st.st_mode)) throw IoError("cannot read " + name + ": it is a folder");
  if (!S_ISREG(st.st_mode))
    throw IoError("cannot read " + name + ": it is " +
                  (S_ISFIFO(st.st_mode)                         ? "a FIFO"
                   : S_ISSOCK(st.st_mode)                       ? "a socket"
                   : S_ISCHR(st.st_mode) || S_ISBLK(st.st_mode) ? "a device"
                                                                : "not a regular file") +
                  ", and only regular files are read");
  // Back to blocking reads: a regular file never waits, and O_NONBLOCK is not meant for it.
  ::fcntl(fd, F_SETFL, ::fcntl(fd, F_GETFL) & ~O_NONBLOCK);
  const auto size = static_cast<std::uint64_t>(st.st_size);
  if (size > max_bytes)
    throw InputError(name + " is larger than the limit of " + std::to_string(max_bytes) + " bytes");
  std::string bytes(size, '\0');
  std::uint64_t done = 0;
  while (done < size) {
    const ssize_t n = ::read(fd, bytes.data() + done, size - done);
    if (n < 0 && errno == EINTR) continue;
    if (n < 0) throw IoError("cannot read " + name + ": " + std::strerror(errno));
    if (n == 0) break;  // the file shrank while we read it
    done += static_cast<std::uint64_t>(n);
  }
  bytes.resize(done);
  return bytes;
}

std::string lower_extension(const std::filesystem::path& path) {
  std::string ext = path.extension().string();
  for (char& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return ext;
}

}  // namespace tpmsfill::detail
