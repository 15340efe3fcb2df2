// Plain data to bytes and back, for what ranks send each other (ranks.hpp): trivially
// copyable values and vectors of them, in this machine's representation (ranks of one job run
// the same build).
#pragma once

#include <cstdint>
#include <cstring>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <vector>

namespace tpmsfill::cli::wire {

template <class T>
void put(std::string& out, const T& value) {
  static_assert(std::is_trivially_copyable_v<T>);
  out.append(reinterpret_cast<const char*>(&value), sizeof value);
}

template <class T>
void put(std::string& out, const std::vector<T>& values) {
  static_assert(std::is_trivially_copyable_v<T>);
  put(out, static_cast<std::uint64_t>(values.size()));
  out.append(reinterpret_cast<const char*>(values.data()), values.size() * sizeof(T));
}

inline void put(std::string& out, const std::string& text) {
  put(out, std::vector<char>(text.begin(), text.end()));
}

/// Reads back what put() wrote, in the same order.
class Reader {
 public:
  explicit Reader(const std::string& bytes) : bytes_(bytes) {}
  template <class T>
  void get(T& value) {
    static_assert(std::is_trivially_copyable_v<T>);
    take(&value, sizeof value);
  }
  template <class T>
  void get(std::vector<T>& values) {
    std::uint64_t n = 0;
    get(n);
    if (n > (bytes_.size() - at_) / sizeof(T)) throw std::runtime_error("wire: truncated message");
    values.resize(n);
    take(values.data(), n * sizeof(T));
  }
  void get(std::string& text) {
    std::vector<char> chars;
    get(chars);
    text.assign(chars.begin(), chars.end());
  }

 private:
  void take(void* to, std::size_t n) {
    if (n > bytes_.size() - at_) throw std::runtime_error("wire: truncated message");
    std::memcpy(to, bytes_.data() + at_, n);
    at_ += n;
  }
  const std::string& bytes_;
  std::size_t at_ = 0;
};

}  // namespace tpmsfill::cli::wire
