/// @file inflate.hpp
/// @brief gzip or zlib data (the header says which) inflated, with a size limit and the byte
/// offset of any damage: what the mesh and volume readers share.
#pragma once

#include <cstdint>
#include <functional>
#include <string>
#include <string_view>

namespace tpmsfill::detail {

/// The whole size a format's first bytes declare (a binary STL's triangle count, a volume's
/// dimensions): once `head` bytes are inflated (at once when `head` is 0: a header read
/// before), `total(head bytes)` gives it, or 0 where they declare none. Inflating stops as
/// soon as the data runs past it. Without `total`, nothing is declared.
struct DeclaredSize {
  std::size_t head = 0;
  std::function<std::uint64_t(std::string_view)> total;
};

/// Inflates a gzip stream (concatenated members too) or a zlib stream. The output grows as
/// the data proves itself: a gzip of zeros is refused when it passes the declared size or
/// `max_bytes`, not after it has all been inflated.
/// @throws ParseError  corrupt or truncated data (the byte offset in the compressed data)
/// @throws InputError  the result would exceed max_bytes, or the size its head declares
std::string inflate_bytes(std::string_view data, const std::string& source, std::uint64_t max_bytes,
                          const DeclaredSize& declared = {});

}  // namespace tpmsfill::detail
