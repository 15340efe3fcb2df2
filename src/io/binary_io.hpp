/// @file binary_io.hpp
/// @brief Little-endian binary files (ITDF, the solid spline model): a writer that appends
/// values, and a reader that names the byte offset of every failure and checks every length
/// against the bytes left before anything is taken.
#pragma once

#include <bit>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <string>
#include <string_view>

#include <zlib.h>

#include "io/parse_errors.hpp"
#include "tpmsfill/error.hpp"

namespace tpmsfill::detail {

static_assert(std::endian::native == std::endian::little,
              "tpmsfill's binary formats assume a little-endian host");

/// Appends little-endian values.
class Writer {
 public:
  template <class T>
  void put(T value) {
    char b[sizeof(T)];
    std::memcpy(b, &value, sizeof(T));
    bytes_.append(b, sizeof(T));
  }
  void put_bytes(std::string_view s) { bytes_.append(s); }
  /// The closing field of tpmsfill's binary files: the CRC-32 (zlib) of every byte before it.
  void put_crc32() { put<std::uint32_t>(crc32_of(bytes_)); }
  std::string& bytes() { return bytes_; }

  static std::uint32_t crc32_of(std::string_view bytes) {
    return static_cast<std::uint32_t>(
        crc32(0, reinterpret_cast<const Bytef*>(bytes.data()), static_cast<uInt>(bytes.size())));
  }

 private:
  std::string bytes_;
};

/// Reads little-endian values with the byte offset of every failure.
class Reader {
 public:
  Reader(std::string_view bytes, const std::string& source) : bytes_(bytes), source_(source) {}

  [[noreturn]] void fail(const std::string& why, std::size_t at) const {
    detail::fail_at_byte(source_, at, why);
  }
  [[noreturn]] void fail(const std::string& why) const { fail(why, at_); }
  void need(std::uint64_t n, const std::string& what) const {
    if (n > bytes_.size() - at_)
      fail("the file ends inside " + what + " (" + std::to_string(n) + " bytes needed, " +
           std::to_string(bytes_.size() - at_) + " left)");
  }
  template <class T>
  T get(const std::string& what) {
    need(sizeof(T), what);
    T value;
    std::memcpy(&value, bytes_.data() + at_, sizeof(T));
    at_ += sizeof(T);
    return value;
  }
  double finite(const std::string& what) {
    const double v = get<double>(what);
    if (!std::isfinite(v)) fail(what + " is not finite", at_ - 8);
    return v;
  }
  std::string_view take(std::size_t n, const std::string& what) {
    need(n, what);
    const std::string_view s = bytes_.substr(at_, n);
    at_ += n;
    return s;
  }
  std::size_t at() const { return at_; }
  std::size_t left() const { return bytes_.size() - at_; }

 private:
  std::string_view bytes_;
  const std::string& source_;
  std::size_t at_ = 0;
};

/// tpmsfill's binary files (ITDF, the solid spline model) open with 4 magic bytes and a u16
/// version and close with a CRC-32 of every byte before it. This checks the magic (`what`, e.g.
/// "an ITDF file", names the format when it is not there), the size (at least `min_size`) and
/// the version (`name` version `version`), and returns a Reader over the body, everything
/// before the CRC, positioned after the version: the body is parsed first, so that damage is
/// named where it is, and check_crc32() then catches what parses but changed.
inline Reader open_framed(std::string_view bytes, const std::string& source, std::string_view magic,
                          const std::string& what, const std::string& name, std::uint16_t version,
                          std::size_t min_size) {
  if (bytes.size() < magic.size() || bytes.substr(0, magic.size()) != magic)
    fail_at_byte(source, 0,
                 "not " + what + " (it does not start with \"" + std::string(magic) + "\")");
  if (bytes.size() < min_size)
    fail_at_byte(source, bytes.size(), "the file ends inside the header");
  Reader r(bytes.substr(0, bytes.size() - 4), source);
  r.take(magic.size(), "the magic");
  const auto found = r.get<std::uint16_t>("the version");
  if (found != version)
    throw InputError(source + " is " + name + " version " + std::to_string(found) +
                     "; this tpmsfill reads version " + std::to_string(version));
  return r;
}

/// The end of a framed file's body: nothing left before the CRC, and the CRC matching.
/// @throws ParseError  bytes left over, or a CRC that does not match (at its offset)
inline void check_crc32(const Reader& r, std::string_view bytes) {
  if (r.left() != 0) r.fail(std::to_string(r.left()) + " unexpected bytes before the CRC");
  const std::size_t body = bytes.size() - 4;
  std::uint32_t stored = 0;
  std::memcpy(&stored, bytes.data() + body, 4);
  if (stored != Writer::crc32_of(bytes.substr(0, body)))
    r.fail("the CRC-32 does not match the content (the file is damaged)", body);
}

}  // namespace tpmsfill::detail
