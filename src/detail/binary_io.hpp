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

#include "detail/parse_errors.hpp"

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
  std::string& bytes() { return bytes_; }

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

}  // namespace tpmsfill::detail
