/// @file inflate.hpp
/// @brief gzip or zlib data (the header says which) inflated, with a size limit and the byte
/// offset of any damage: what the mesh and volume readers share.
#pragma once

#include <cstdint>
#include <string>
#include <string_view>

namespace tpmsfill::detail {

/// Inflates a gzip stream (concatenated members too) or a zlib stream.
/// @throws ParseError  corrupt or truncated data (the byte offset in the compressed data)
/// @throws InputError  the result would exceed max_bytes
std::string inflate_bytes(std::string_view data, const std::string& source,
                          std::uint64_t max_bytes);

}  // namespace tpmsfill::detail
