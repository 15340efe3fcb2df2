/// @file number_text.hpp
/// @brief Internal: numbers as the text writers put them, so every text format's numbers read
/// back bit-identical (one helper for the mesh and the tet-mesh writers).
#pragma once

#include <array>
#include <charconv>
#include <string>

#include "tpmsfill/types.hpp"

namespace tpmsfill::io {

/// Appends the shortest text that reads back to the same value (std::to_chars' round-trip
/// guarantee); integers as their digits.
template <typename T>
void append_number(std::string& out, T value) {
  std::array<char, 32> buf;
  const auto [end, ec] = std::to_chars(buf.data(), buf.data() + buf.size(), value);
  out.append(buf.data(), end);
}

/// "x y z\n", each as append_number writes it.
inline void append_xyz(std::string& out, const Vec3& p) {
  append_number(out, p.x);
  out += ' ';
  append_number(out, p.y);
  out += ' ';
  append_number(out, p.z);
  out += '\n';
}

}  // namespace tpmsfill::io
