// Writers: the whole file is formatted in memory, then written to a temporary file beside the
// target and renamed over it, so readers of the target never see a half-written mesh.
// GCC 12 at -O3 warns falsely (-Wrestrict, GCC bug 105651) inside <string> on `"literal" +
// std::string` once inlined. The warning is located in the library header, so it can only be
// silenced before the first include.
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC diagnostic ignored "-Wrestrict"
#endif
#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <bit>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstring>

#include "detail/index_limits.hpp"
#include "detail/parallel.hpp"
#include "detail/soup_indices.hpp"
#include "tpmsfill/error.hpp"
#include "tpmsfill/io.hpp"

namespace tpmsfill {
namespace {

// Shortest text that reads back to the same value (std::to_chars' round-trip guarantee).
template <typename T>
void append_number(std::string& out, T value) {
  std::array<char, 32> buf;
  const auto [end, ec] = std::to_chars(buf.data(), buf.data() + buf.size(), value);
  out.append(buf.data(), end);
}

void append_u64(std::string& out, std::uint64_t value) {
  append_number(out, value);
}

template <typename T>
void append_le(std::string& out, T value) {
  auto bytes = std::bit_cast<std::array<char, sizeof(T)>>(value);
  if constexpr (std::endian::native == std::endian::big) std::reverse(bytes.begin(), bytes.end());
  out.append(bytes.data(), bytes.size());
}

// Unit normal of a triangle as floats (zero for a degenerate one), as STL stores it.
std::array<float, 3> facet_normal(const TriangleSoup& soup, const Triangle& t) {
  const Vec3 n =
      cross(soup.points[t[1]] - soup.points[t[0]], soup.points[t[2]] - soup.points[t[0]]);
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

std::string format_stl_binary(const TriangleSoup& soup) {
  // Fixed 50 bytes per facet: sized once and filled in parallel (outputs reach millions).
  std::string out(84 + 50 * soup.triangles.size(), '\0');
  // Must not start with "solid": readers that trust the first word would take it for ASCII.
  std::string header = "binary STL written by tpmsfill";
  header.resize(80, ' ');
  out.replace(0, 80, header);
  put_le(out.data() + 80, static_cast<std::uint32_t>(soup.triangles.size()));
  detail::parallel_for(soup.triangles.size(), 4096, [&](std::size_t begin, std::size_t end) {
    for (std::size_t i = begin; i < end; ++i) {
      const Triangle& t = soup.triangles[i];
      char* at = out.data() + 84 + 50 * i;
      for (const float c : facet_normal(soup, t)) at = put_le(at, c);
      for (const std::uint32_t v : t) {
        const Vec3& p = soup.points[v];
        at = put_le(at, static_cast<float>(p.x));
        at = put_le(at, static_cast<float>(p.y));
        at = put_le(at, static_cast<float>(p.z));
      }
      put_le(at, std::uint16_t{0});
    }
  });
  return out;
}

// Floats, like binary STL: both STL flavours then read back the same coordinates.
std::string format_stl_ascii(const TriangleSoup& soup) {
  std::string out = "solid tpmsfill\n";
  for (const Triangle& t : soup.triangles) {
    out += "facet normal";
    for (const float c : facet_normal(soup, t)) {
      out += ' ';
      append_number(out, c);
    }
    out += "\nouter loop\n";
    for (const std::uint32_t v : t) {
      const Vec3& p = soup.points[v];
      out += "vertex";
      for (const double c : {p.x, p.y, p.z}) {
        out += ' ';
        append_number(out, static_cast<float>(c));
      }
      out += '\n';
    }
    out += "endloop\nendfacet\n";
  }
  out += "endsolid tpmsfill\n";
  return out;
}

void append_xyz(std::string& out, const Vec3& p) {
  append_number(out, p.x);
  out += ' ';
  append_number(out, p.y);
  out += ' ';
  append_number(out, p.z);
  out += '\n';
}

std::string format_obj(const TriangleSoup& soup) {
  std::string out = "# written by tpmsfill\n";
  for (const Vec3& p : soup.points) {
    out += "v ";
    append_xyz(out, p);
  }
  for (const Triangle& t : soup.triangles) {
    out += 'f';
    for (const std::uint32_t v : t) {
      out += ' ';
      append_u64(out, std::uint64_t{v} + 1);
    }
    out += '\n';
  }
  return out;
}

std::string format_off(const TriangleSoup& soup) {
  std::string out = "OFF\n";
  append_u64(out, soup.points.size());
  out += ' ';
  append_u64(out, soup.triangles.size());
  out += " 0\n";
  for (const Vec3& p : soup.points) append_xyz(out, p);
  for (const Triangle& t : soup.triangles) {
    out += '3';
    for (const std::uint32_t v : t) {
      out += ' ';
      append_u64(out, v);
    }
    out += '\n';
  }
  return out;
}

std::string format_ply(const TriangleSoup& soup) {
  std::string out =
      "ply\nformat binary_little_endian 1.0\ncomment written by tpmsfill\nelement vertex ";
  append_u64(out, soup.points.size());
  out += "\nproperty double x\nproperty double y\nproperty double z\nelement face ";
  append_u64(out, soup.triangles.size());
  out += "\nproperty list uchar uint vertex_indices\nend_header\n";
  out.reserve(out.size() + 24 * soup.points.size() + 13 * soup.triangles.size());
  for (const Vec3& p : soup.points) {
    append_le(out, p.x);
    append_le(out, p.y);
    append_le(out, p.z);
  }
  for (const Triangle& t : soup.triangles) {
    out += '\3';
    for (const std::uint32_t v : t) append_le(out, v);
  }
  return out;
}

std::string os_error() {
  return std::strerror(errno);
}

// Temporary file beside the target, synced, then renamed over it. On any failure the temporary
// is removed and the target is untouched.

}  // namespace

void write_file_atomically(const std::filesystem::path& path, const std::string& bytes) {
  const std::filesystem::path folder = path.has_parent_path() ? path.parent_path() : ".";
  std::string temp = (folder / ("." + path.filename().string() + ".tmp-XXXXXX")).string();
  const int fd = ::mkstemp(temp.data());
  if (fd < 0)
    throw IoError("cannot write " + path.string() + ": cannot create a temporary file in " +
                  folder.string() + ": " + os_error());
  auto fail = [&](const std::string& what) {
    const std::string reason = os_error();
    ::close(fd);
    ::unlink(temp.c_str());
    throw IoError("cannot write " + path.string() + ": " + what + ": " + reason);
  };
  // mkstemp creates 0600; a mesh is an ordinary document.
  if (::fchmod(fd, 0644) != 0) fail("cannot set permissions");
  std::size_t done = 0;
  while (done < bytes.size()) {
    const ssize_t n = ::write(fd, bytes.data() + done, bytes.size() - done);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) fail("write failed");
    done += static_cast<std::size_t>(n);
  }
  if (::fsync(fd) != 0) fail("flush failed");
  if (::close(fd) != 0) {
    const std::string reason = os_error();
    ::unlink(temp.c_str());
    throw IoError("cannot write " + path.string() + ": close failed: " + reason);
  }
  std::error_code ec;
  std::filesystem::rename(temp, path, ec);
  if (ec) {
    ::unlink(temp.c_str());
    throw IoError("cannot write " + path.string() + ": rename failed: " + ec.message());
  }
}

void write_mesh(const std::filesystem::path& path, const TriangleSoup& soup,
                const WriteOptions& options) {
  MeshFormat format = options.format;
  if (format == MeshFormat::Auto) format = format_from_extension(path);
  if (format == MeshFormat::Auto)
    throw InputError("cannot write " + path.string() +
                     ": unknown extension (use .stl, .obj, .ply or .off)");
  detail::require_indices_in_range(soup, "cannot write " + path.string() + ": ");
  if ((format == MeshFormat::StlBinary && !detail::fits_32bit_ids(soup.triangles.size())) ||
      (format == MeshFormat::Ply && !detail::fits_32bit_ids(soup.points.size())))
    throw InputError("cannot write " + path.string() + ": too many elements for the format");
  std::string bytes;
  switch (format) {
    case MeshFormat::Auto:
    case MeshFormat::StlBinary:
      bytes = format_stl_binary(soup);
      break;
    case MeshFormat::StlAscii:
      bytes = format_stl_ascii(soup);
      break;
    case MeshFormat::Obj:
      bytes = format_obj(soup);
      break;
    case MeshFormat::Ply:
      bytes = format_ply(soup);
      break;
    case MeshFormat::Off:
      bytes = format_off(soup);
      break;
  }
  write_file_atomically(path, bytes);
}

}  // namespace tpmsfill
