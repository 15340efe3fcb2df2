/// @file parse_errors.hpp
/// @brief The ParseErrors of every reader (meshes, recipes): where in the file, then what.
#pragma once

#include <cstdint>
#include <string>

namespace tpmsfill::detail {

/// Throws the ParseError of a text format: the location is a 1-based line ("file:12: reason").
[[noreturn]] void fail_at_line(const std::string& source, std::uint64_t line,
                               const std::string& reason);

/// Throws the ParseError of a binary format: the location is a byte offset
/// ("file: byte 84: reason").
[[noreturn]] void fail_at_byte(const std::string& source, std::uint64_t offset,
                               const std::string& reason);

}  // namespace tpmsfill::detail
