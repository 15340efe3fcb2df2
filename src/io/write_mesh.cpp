// Writers, piece by piece: a header with the counts, then points, then triangles, then a
// footer, each piece formatted into a buffer and written to a temporary file beside the target
// that is renamed over it at the end, so readers of the target never see a half-written mesh.
// write_mesh is a MeshWriter given the whole soup in one piece of each. A ".gz" target gets
// the same bytes deflated on their way to the file (zlib, gzip wrapper, level 1). 3MF is a zip
// package that lib3mf builds whole: its pieces are held and handed over at commit.

// GCC 12 at -O3 warns falsely (-Wrestrict, GCC bug 105651) inside <string> on `"literal" +
// std::string` once inlined. The warning is located in the library header, so it can only be
// silenced before the first include.
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC diagnostic ignored "-Wrestrict"
#endif
#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>
#include <zlib.h>

#include <algorithm>
#include <array>
#include <bit>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <optional>
#include <span>
#include <string_view>
#include <utility>

#include "core/index_limits.hpp"
#include "core/parallel.hpp"
#include "io/file_bytes.hpp"
#include "io/float_coordinates.hpp"
#include "io/interrupt_cleanup.hpp"
#include "io/number_text.hpp"
#include "io/three_mf.hpp"
#include "tpmsfill/error.hpp"
#include "tpmsfill/io.hpp"

namespace tpmsfill {
namespace {

using io::append_number;

void append_u64(std::string& out, std::uint64_t value) {
  append_number(out, value);
}

template <typename T>
void append_le(std::string& out, T value) {
  auto bytes = std::bit_cast<std::array<char, sizeof(T)>>(value);
  if constexpr (std::endian::native == std::endian::big) std::reverse(bytes.begin(), bytes.end());
  out.append(bytes.data(), bytes.size());
}

// Positions of the ids [first, first + points.size()): all that a piece of triangles sees of
// the points.
struct Window {
  std::span<const Vec3> points;
  std::uint64_t first = 0;
  const Vec3& operator[](std::uint32_t id) const { return points[id - first]; }
};

// Unit normal of a triangle as floats (zero for a degenerate one), as STL stores it.
std::array<float, 3> facet_normal(const Window& points, const Triangle& t) {
  const Vec3 n = cross(points[t[1]] - points[t[0]], points[t[2]] - points[t[0]]);
  const double length = norm(n);
  if (!(length > 0) || !std::isfinite(length)) return {0, 0, 0};
  return {static_cast<float>(n.x / length), static_cast<float>(n.y / length),
          static_cast<float>(n.z / length)};
}

template <typename T>
char* put_le(char* out, T value) {
  auto bytes = std::bit_cast<std::array<char, sizeof(T)>>(value);
  if constexpr (std::endian::native == std::endian::big) std::reverse(bytes.begin(), bytes.end());
  std::memcpy(out, bytes.data(), bytes.size());
  return out + bytes.size();
}

using io::append_xyz;

// ---- the formats, piece by piece ------------------------------------------------------------
// A file is format_header, then append_points over the points in order, then append_triangles
// over the triangles in order, then format_footer: however the pieces are cut, the bytes are
// those of the whole mesh in one piece.

// OBJ, OFF and PLY list every point before the first face; STL has no points of its own.
bool indexed(MeshFormat format) {
  return format == MeshFormat::Obj || format == MeshFormat::Off || format == MeshFormat::Ply;
}

std::string format_header(MeshFormat format, std::uint64_t points, std::uint64_t triangles) {
  std::string out;
  switch (format) {
    case MeshFormat::Auto:
    case MeshFormat::StlBinary:
      // Must not start with "solid": readers that trust the first word would take it for ASCII.
      out = "binary STL written by tpmsfill";
      out.resize(80, ' ');
      append_le(out, static_cast<std::uint32_t>(triangles));
      break;
    case MeshFormat::StlAscii:
      out = "solid tpmsfill\n";
      break;
    case MeshFormat::Obj:
      out = "# written by tpmsfill\n";
      break;
    case MeshFormat::Off:
      out = "OFF\n";
      append_u64(out, points);
      out += ' ';
      append_u64(out, triangles);
      out += " 0\n";
      break;
    case MeshFormat::Ply:
      out = "ply\nformat binary_little_endian 1.0\ncomment written by tpmsfill\nelement vertex ";
      append_u64(out, points);
      out += "\nproperty double x\nproperty double y\nproperty double z\nelement face ";
      append_u64(out, triangles);
      out += "\nproperty list uchar uint vertex_indices\nend_header\n";
      break;
    case MeshFormat::ThreeMf:
    case MeshFormat::Scene:  // refused by writable_format
      break;                 // lib3mf writes the whole package at commit
  }
  return out;
}

void append_points(MeshFormat format, std::string& out, std::span<const Vec3> points) {
  switch (format) {
    case MeshFormat::Auto:
    case MeshFormat::StlBinary:
    case MeshFormat::StlAscii:
    case MeshFormat::ThreeMf:
    case MeshFormat::Scene:
      break;  // STL stores the coordinates with each facet; 3MF's are held (State)
    case MeshFormat::Obj:
      for (const Vec3& p : points) {
        out += "v ";
        append_xyz(out, p);
      }
      break;
    case MeshFormat::Off:
      for (const Vec3& p : points) append_xyz(out, p);
      break;
    case MeshFormat::Ply:
      out.reserve(out.size() + 24 * points.size());
      for (const Vec3& p : points) {
        append_le(out, p.x);
        append_le(out, p.y);
        append_le(out, p.z);
      }
      break;
  }
}

// Precondition: `window` holds every corner.
void append_triangles(MeshFormat format, std::string& out, std::span<const Triangle> triangles,
                      const Window& window) {
  switch (format) {
    case MeshFormat::Auto:
    case MeshFormat::StlBinary: {
      // Fixed 50 bytes per facet: sized once and filled in parallel (outputs reach millions).
      const std::size_t start = out.size();
      out.resize(start + 50 * triangles.size());
      char* const facets = out.data() + start;
      detail::parallel_for(triangles.size(), 4096, [&](std::size_t begin, std::size_t end) {
        for (std::size_t i = begin; i < end; ++i) {
          const Triangle& t = triangles[i];
          char* at = facets + 50 * i;
          for (const float c : facet_normal(window, t)) at = put_le(at, c);
          for (const std::uint32_t v : t) {
            const Vec3& p = window[v];
            at = put_le(at, static_cast<float>(p.x));
            at = put_le(at, static_cast<float>(p.y));
            at = put_le(at, static_cast<float>(p.z));
          }
          put_le(at, std::uint16_t{0});
        }
      });
      break;
    }
    case MeshFormat::StlAscii:
      // Floats, like binary STL: both STL flavours then read back the same coordinates.
      for (const Triangle& t : triangles) {
        out += "facet normal";
        for (const float c : facet_normal(window, t)) {
          out += ' ';
          append_number(out, c);
        }
        out += "\nouter loop\n";
        for (const std::uint32_t v : t) {
          const Vec3& p = window[v];
          out += "vertex";
          for (const double c : {p.x, p.y, p.z}) {
            out += ' ';
            append_number(out, static_cast<float>(c));
          }
          out += '\n';
        }
        out += "endloop\nendfacet\n";
      }
      break;
    case MeshFormat::Obj:
      for (const Triangle& t : triangles) {
        out += 'f';
        for (const std::uint32_t v : t) {
          out += ' ';
          append_u64(out, std::uint64_t{v} + 1);
        }
        out += '\n';
      }
      break;
    case MeshFormat::Off:
      for (const Triangle& t : triangles) {
        out += '3';
        for (const std::uint32_t v : t) {
          out += ' ';
          append_u64(out, v);
        }
        out += '\n';
      }
      break;
    case MeshFormat::Ply:
      out.reserve(out.size() + 13 * triangles.size());
      for (const Triangle& t : triangles) {
        out += '\3';
        for (const std::uint32_t v : t) append_le(out, v);
      }
      break;
    case MeshFormat::ThreeMf:
    case MeshFormat::Scene:  // refused by writable_format
      break;                 // held (State)
  }
}

std::string_view format_footer(MeshFormat format) {
  return format == MeshFormat::StlAscii ? "endsolid tpmsfill\n" : "";
}

// Points or triangles formatted per buffer: enough that writes and parallel loops are few and
// long, few enough that the buffer stays small beside the mesh (binary STL: 13 MB).
constexpr std::size_t kChunk = std::size_t{1} << 18;

// The format write_mesh and MeshWriter write to `path`, or InputError if there is none or it
// cannot number that many elements.
MeshFormat writable_format(const std::filesystem::path& path, const WriteOptions& options,
                           std::uint64_t points, std::uint64_t triangles) {
  MeshFormat format = options.format;
  if (format == MeshFormat::Auto) format = format_from_extension(path);
  if (format == MeshFormat::Auto) throw InputError("cannot write " + unknown_mesh_extension(path));
  if (format == MeshFormat::Scene)
    throw InputError("cannot write " + path.string() +
                     ": scenes are read only (write .stl, .obj, .ply, .off or .3mf)");
  if ((format == MeshFormat::StlBinary && !detail::fits_32bit_ids(triangles)) ||
      (format == MeshFormat::Ply && !detail::fits_32bit_ids(points)) ||
      (format == MeshFormat::ThreeMf &&
       !(detail::fits_32bit_ids(points) && detail::fits_32bit_ids(triangles))))
    throw InputError("cannot write " + path.string() + ": too many elements for the format");
  return format;
}

// Whether write_mesh and MeshWriter deflate what they write to `path`.
bool writes_gzip(const std::filesystem::path& path, const WriteOptions& options) {
  return options.compression == Compression::Gzip ||
         (options.compression == Compression::Auto && is_gzip_name(path));
}

// writes_gzip, refused for 3MF (a zip package: deflating it again gains nothing and no slicer
// would open it).
bool checked_gzip(const std::filesystem::path& path, const WriteOptions& options,
                  MeshFormat format) {
  const bool gzip = writes_gzip(path, options);
  if (gzip && format == MeshFormat::ThreeMf)
    throw InputError("cannot write " + path.string() +
                     ": a 3MF package is compressed already; write it without gzip");
  return gzip;
}

// ---- files ----------------------------------------------------------------------------------

std::string os_error() {
  return std::strerror(errno);
}

// IoError "cannot write <target>: <what>: <errno's text>"; call it before errno changes.
[[noreturn]] void throw_os_error(const std::filesystem::path& target, const std::string& what) {
  throw IoError("cannot write " + target.string() + ": " + what + ": " + os_error());
}

// A new empty file beside `target`, named "." + its name + ".tmp-XXXXXX" (one left by a crash
// is then recognisable); `name` receives its name.
int create_temporary(const std::filesystem::path& target, std::string& name) {
  const std::filesystem::path folder = target.has_parent_path() ? target.parent_path() : ".";
  name = (folder / ("." + target.filename().string() + ".tmp-XXXXXX")).string();
  const int fd = ::mkstemp(name.data());
  if (fd < 0)
    throw IoError("cannot write " + target.string() + ": cannot create a temporary file in " +
                  folder.string() + ": " + os_error());
  return fd;
}

// All of `bytes`, across partial writes and signals.
void write_all(int fd, std::string_view bytes, const std::filesystem::path& target) {
  std::size_t done = 0;
  while (done < bytes.size()) {
    const ssize_t n = ::write(fd, bytes.data() + done, bytes.size() - done);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) {
      if (n == 0) errno = EIO;  // no progress and no reason given
      throw_os_error(target, "write failed");
    }
    done += static_cast<std::size_t>(n);
  }
}

// Calls sink(bytes) on the next `size` bytes of `from`, a few MB at a time.
template <class Sink>
void read_chunks(int from, std::uint64_t size, const std::filesystem::path& target,
                 const Sink& sink) {
  if (size == 0) return;
  std::string buffer(std::min<std::uint64_t>(size, std::uint64_t{4} << 20), '\0');
  while (size > 0) {
    const ssize_t n =
        ::read(from, buffer.data(),
               static_cast<std::size_t>(std::min<std::uint64_t>(size, buffer.size())));
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) {
      if (n == 0) errno = EIO;  // the temporary is shorter than what was written to it
      throw_os_error(target, "read failed");
    }
    sink(std::string_view{buffer.data(), static_cast<std::size_t>(n)});
    size -= static_cast<std::uint64_t>(n);
  }
}

// Appends the first `size` bytes of `from` at `to`'s offset: in the kernel where the file
// system can (no copy through user space), through a buffer where it cannot.
void copy_all(int from, int to, std::uint64_t size, const std::filesystem::path& target) {
  if (::lseek(from, 0, SEEK_SET) != 0) throw_os_error(target, "read failed");
  while (size > 0) {
    const ssize_t n = ::copy_file_range(
        from, nullptr, to, nullptr,
        static_cast<std::size_t>(std::min<std::uint64_t>(size, std::uint64_t{1} << 30)), 0);
    if (n < 0 && errno == EINTR) continue;
    // Not supported here (EXDEV, ENOSYS, EINVAL, ...): the loop below goes on from the offsets
    // reached, and reports any real failure itself.
    if (n <= 0) break;
    size -= static_cast<std::uint64_t>(n);
  }
  read_chunks(from, size, target, [&](std::string_view bytes) { write_all(to, bytes, target); });
}

// The process's umask, read without changing it (umask(2) sets as it reads, which races with
// other threads): Linux shows it in /proc/self/status; 022 where it does not.
mode_t process_umask() {
  static const mode_t mask = [] {
    mode_t m = 022;
    if (FILE* f = std::fopen("/proc/self/status", "r")) {
      char line[256];
      while (std::fgets(line, sizeof line, f))
        if (std::strncmp(line, "Umask:", 6) == 0)
          m = static_cast<mode_t>(std::strtoul(line + 6, nullptr, 8));
      std::fclose(f);
    }
    return m;
  }();
  return mask;
}

// A temporary file beside the target (mode 0666 less the umask, as any new file) that
// commit() flushes and renames over it.
// Destroyed uncommitted (a failure included), it is closed and removed and the target is
// untouched.
class AtomicFile {
 public:
  explicit AtomicFile(std::filesystem::path target) : target_(std::move(target)) {
    fd_ = create_temporary(target_, temp_);
    interrupt_ = detail::RemovedOnInterrupt(temp_, detail::RemovedOnInterrupt::Kind::File);
    // mkstemp creates 0600; a mesh is an ordinary document (the service's umask keeps its
    // jobs' files private).
    if (::fchmod(fd_, 0666 & ~process_umask()) != 0) {
      const std::string reason = os_error();
      discard();
      throw IoError("cannot write " + target_.string() + ": cannot set permissions: " + reason);
    }
  }
  ~AtomicFile() { discard(); }
  AtomicFile(const AtomicFile&) = delete;
  AtomicFile& operator=(const AtomicFile&) = delete;

  int fd() const { return fd_; }
  void write(std::string_view bytes) { write_all(fd_, bytes, target_); }

  void commit() {
    if (::fsync(fd_) != 0) throw_os_error(target_, "flush failed");
    // Closed whatever close() says (POSIX leaves the descriptor unusable either way).
    if (::close(std::exchange(fd_, -1)) != 0) throw_os_error(target_, "close failed");
    std::error_code ec;
    std::filesystem::rename(temp_, target_, ec);
    if (ec) throw IoError("cannot write " + target_.string() + ": rename failed: " + ec.message());
    temp_.clear();
    interrupt_.release();
  }

 private:
  void discard() noexcept {
    if (fd_ >= 0) ::close(std::exchange(fd_, -1));
    if (!temp_.empty()) ::unlink(temp_.c_str());
    temp_.clear();
  }

  std::filesystem::path target_;
  std::string temp_;  // empty once renamed or removed
  int fd_ = -1;
  detail::RemovedOnInterrupt interrupt_;
};

// A gzip stream onto a file descriptor: bytes in, deflated bytes written as its buffer fills.
class GzipSink {
 public:
  explicit GzipSink(const std::filesystem::path& target) : target_(target) {
    // windowBits 15 + 16: a gzip wrapper, as gzip(1) and the readers expect. Level 1: on a
    // lattice STL it deflates 3 times faster than the default level 6 for a file 9 % larger
    // (docs/formats.md, "Writers"); meshes here run to gigabytes.
    if (deflateInit2(&z_, Z_BEST_SPEED, Z_DEFLATED, 15 + 16, 8, Z_DEFAULT_STRATEGY) != Z_OK)
      throw IoError("cannot write " + target_.string() + ": zlib could not start compressing");
  }
  ~GzipSink() { deflateEnd(&z_); }
  GzipSink(const GzipSink&) = delete;
  GzipSink& operator=(const GzipSink&) = delete;

  void write(int fd, std::string_view bytes) { pump(fd, bytes, Z_NO_FLUSH); }
  void finish(int fd) { pump(fd, {}, Z_FINISH); }

 private:
  void pump(int fd, std::string_view bytes, int flush) {
    // zlib counts in 32 bits: feed at most 1 GiB a call.
    do {
      const std::size_t take = std::min<std::size_t>(bytes.size(), std::size_t{1} << 30);
      z_.next_in = reinterpret_cast<Bytef*>(const_cast<char*>(bytes.data()));
      z_.avail_in = static_cast<uInt>(take);
      const int f = take == bytes.size() ? flush : Z_NO_FLUSH;
      int status;
      do {
        z_.next_out = reinterpret_cast<Bytef*>(out_.data());
        z_.avail_out = static_cast<uInt>(out_.size());
        status = deflate(&z_, f);
        if (status == Z_STREAM_ERROR)
          throw IoError("cannot write " + target_.string() + ": compression failed");
        write_all(fd, {out_.data(), out_.size() - z_.avail_out}, target_);
      } while (z_.avail_out == 0 || (f == Z_FINISH && status != Z_STREAM_END));
      bytes.remove_prefix(take);
    } while (!bytes.empty());
  }

  std::filesystem::path target_;
  z_stream z_{};
  std::string out_ = std::string(std::size_t{1} << 20, '\0');
};

}  // namespace

void write_file_atomically(const std::filesystem::path& path, const std::string& bytes) {
  AtomicFile file(path);
  file.write(bytes);
  file.commit();
}

// ---- MeshWriter -----------------------------------------------------------------------------

struct MeshWriter::State {
  State(const std::filesystem::path& target, MeshFormat format_, bool gzip_, std::uint64_t points_,
        std::uint64_t triangles_, MeshMetadata metadata_)
      : path(target),
        format(format_),
        points(points_),
        triangles(triangles_),
        metadata(std::move(metadata_)) {
    file.emplace(path);
    if (gzip_) gzip.emplace(path);
  }
  ~State() { close_sidecar(); }

  [[noreturn]] void refuse(const std::string& why) const {
    throw InputError("cannot write " + path.string() + ": " + why);
  }
  [[noreturn]] void refuse_corner(std::uint64_t triangle, std::uint32_t v,
                                  const Window& window) const {
    const std::string which =
        "triangle " + std::to_string(triangle) + " refers to point " + std::to_string(v);
    if (v >= points) refuse(which + ", but there are only " + std::to_string(points) + " points");
    refuse(which + ", outside the window of points [" + std::to_string(window.first) + ", " +
           std::to_string(window.first + window.points.size()) + ") given with it");
  }
  void add_points(std::span<const Vec3> more);
  void add_triangles(std::span<const Triangle> more, const Window& window);
  void commit();
  // The file's next bytes, deflated first for a .gz target.
  void emit(std::string_view bytes) {
    if (gzip)
      gzip->write(file->fd(), bytes);
    else
      file->write(bytes);
  }
  // Everything removed at once after a failure; later calls are refused.
  void die() noexcept {
    dead = true;
    close_sidecar();
    file.reset();
    gzip.reset();
    buffer = {};
    held_xyz = {};
    held_ids = {};
  }
  void close_sidecar() noexcept {
    if (sidecar >= 0) ::close(std::exchange(sidecar, -1));
  }

  const std::filesystem::path path;
  const MeshFormat format;
  const std::uint64_t points, triangles;  // declared
  std::uint64_t points_added = 0, triangles_added = 0;
  std::optional<AtomicFile> file;  // empty once committed or dead
  std::optional<GzipSink> gzip;    // set for a compressed target
  bool dead = false;
  // Faces that came before the last point (OBJ, OFF, PLY only): a temporary beside the target,
  // unlinked as soon as it is made, appended after the last point.
  int sidecar = -1;
  std::uint64_t sidecar_bytes = 0;
  std::string buffer;  // one chunk, formatted
  // 3MF: the points as floats and the triangles' ids, for lib3mf at commit.
  MeshMetadata metadata;
  std::vector<float> held_xyz;
  std::vector<std::uint32_t> held_ids;
};

void MeshWriter::State::add_points(std::span<const Vec3> more) {
  if (more.size() > points - points_added)
    refuse(std::to_string(points_added + more.size()) + " points added, but " +
           std::to_string(points) + " were declared");
  if (format == MeshFormat::ThreeMf) {
    if (held_xyz.empty()) held_xyz.reserve(3 * points);
    for (const Vec3& p : more)
      for (const double c : {p.x, p.y, p.z}) held_xyz.push_back(static_cast<float>(c));
  }
  if (indexed(format))
    for (std::size_t begin = 0; begin < more.size(); begin += kChunk) {
      buffer.clear();
      append_points(format, buffer, more.subspan(begin, std::min(kChunk, more.size() - begin)));
      emit(buffer);
    }
  points_added += more.size();
  if (points_added == points && sidecar >= 0) {
    // The last point is in: the faces that came early follow it, later ones go straight on.
    if (gzip) {
      if (::lseek(sidecar, 0, SEEK_SET) != 0) throw_os_error(path, "read failed");
      read_chunks(sidecar, sidecar_bytes, path, [&](std::string_view bytes) { emit(bytes); });
    } else {
      copy_all(sidecar, file->fd(), sidecar_bytes, path);
    }
    close_sidecar();
  }
}

void MeshWriter::State::add_triangles(std::span<const Triangle> more, const Window& window) {
  if (more.size() > triangles - triangles_added)
    refuse(std::to_string(triangles_added + more.size()) + " triangles added, but " +
           std::to_string(triangles) + " were declared");
  const bool early = indexed(format) && points_added < points;  // to the sidecar, raw
  if (early && sidecar < 0) sidecar = detail::open_scratch_file(path, "faces");
  for (std::size_t begin = 0; begin < more.size(); begin += kChunk) {
    const auto chunk = more.subspan(begin, std::min(kChunk, more.size() - begin));
    // Checked before it is formatted, which trusts every corner to be in the window.
    for (std::size_t i = 0; i < chunk.size(); ++i)
      for (const std::uint32_t v : chunk[i])
        if (v >= points || v < window.first || v - window.first >= window.points.size())
          refuse_corner(triangles_added + begin + i, v, window);
    if (format == MeshFormat::ThreeMf) {
      if (held_ids.empty()) held_ids.reserve(3 * triangles);
      for (const Triangle& t : chunk) held_ids.insert(held_ids.end(), t.begin(), t.end());
      continue;
    }
    buffer.clear();
    append_triangles(format, buffer, chunk, window);
    if (early) {
      write_all(sidecar, buffer, path);
      sidecar_bytes += buffer.size();
    } else {
      emit(buffer);
    }
  }
  triangles_added += more.size();
}

void MeshWriter::State::commit() {
  if (points_added < points)
    refuse("only " + std::to_string(points_added) + " of the " + std::to_string(points) +
           " declared points were added");
  if (triangles_added < triangles)
    refuse("only " + std::to_string(triangles_added) + " of the " + std::to_string(triangles) +
           " declared triangles were added");
  emit(format_footer(format));
  if (format == MeshFormat::ThreeMf) {
    io::write_3mf(file->fd(), path, held_xyz, held_ids, metadata);
    held_xyz = {};
    held_ids = {};
  }
  if (gzip) gzip->finish(file->fd());
  file->commit();
  file.reset();
  buffer = {};
}

MeshWriter::MeshWriter(const std::filesystem::path& path, std::uint64_t points,
                       std::uint64_t triangles, const WriteOptions& options)
    : state_([&] {
        const MeshFormat format = writable_format(path, options, points, triangles);
        return std::make_unique<State>(path, format, checked_gzip(path, options, format), points,
                                       triangles, options.metadata);
      }()) {
  state_->emit(format_header(state_->format, points, triangles));
}

MeshWriter::~MeshWriter() = default;

MeshWriter::State& MeshWriter::open_state() {
  if (state_->dead) state_->refuse("an earlier error ended this MeshWriter");
  if (!state_->file) state_->refuse("this MeshWriter was committed already");
  return *state_;
}

void MeshWriter::add_points(std::span<const Vec3> points) {
  State& state = open_state();
  try {
    state.add_points(points);
  } catch (...) {
    state.die();
    throw;
  }
}

void MeshWriter::add_triangles(std::span<const Triangle> triangles, std::span<const Vec3> window,
                               std::uint64_t first_id) {
  State& state = open_state();
  try {
    state.add_triangles(triangles, Window{window, first_id});
  } catch (...) {
    state.die();
    throw;
  }
}

void MeshWriter::set_metadata(MeshMetadata metadata) {
  open_state().metadata = std::move(metadata);
}

void MeshWriter::commit() {
  State& state = open_state();
  try {
    state.commit();
  } catch (...) {
    state.die();
    throw;
  }
}

CoordinateRounding rounding_for(MeshFormat format) {
  switch (format) {
    case MeshFormat::StlBinary:
    case MeshFormat::StlAscii:
      return CoordinateRounding::Float;
    case MeshFormat::ThreeMf:
      return CoordinateRounding::ThreeMf;
    default:
      return CoordinateRounding::None;
  }
}

Vec3 round_coordinates(CoordinateRounding rounding, Vec3 p) {
  switch (rounding) {
    case CoordinateRounding::None:
      return p;
    case CoordinateRounding::Float:
      return detail::float_rounded(p);
    case CoordinateRounding::ThreeMf:
      return {io::three_mf_rounded(static_cast<float>(p.x)),
              io::three_mf_rounded(static_cast<float>(p.y)),
              io::three_mf_rounded(static_cast<float>(p.z))};
    case CoordinateRounding::SixDecimals:
      return {detail::six_decimals_value(p.x), detail::six_decimals_value(p.y),
              detail::six_decimals_value(p.z)};
  }
  return p;
}

void round_coordinates(CoordinateRounding rounding, TriangleSoup& soup) {
  if (rounding == CoordinateRounding::None) return;
  detail::parallel_for(soup.points.size(), 4096, [&](std::size_t begin, std::size_t end) {
    for (std::size_t i = begin; i < end; ++i)
      soup.points[i] = round_coordinates(rounding, soup.points[i]);
  });
}

WriteOptions write_options_for(const std::filesystem::path& path) {
  return {.format = format_from_extension(path),
          .compression = is_gzip_name(path) ? Compression::Gzip : Compression::None,
          .metadata = {.title = path.stem().string(), .description = {}, .attachments = {}}};
}

void write_mesh(const std::filesystem::path& path, const TriangleSoup& soup,
                const WriteOptions& options) {
  MeshWriter writer(path, soup.points.size(), soup.triangles.size(), options);
  writer.add_points(soup.points);
  writer.add_triangles(soup.triangles, soup.points, 0);
  writer.commit();
}

}  // namespace tpmsfill
