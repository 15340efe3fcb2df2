/// @file error.hpp
/// @brief The exceptions every tpmsfill function may throw, all derived from tpmsfill::Error.
///
/// The library throws; it never prints and never exits. The CLI catches these and turns them
/// into one line on stderr and an exit code (see docs/cli.md).
#pragma once

#include <cstdint>
#include <optional>
#include <stdexcept>
#include <string>

namespace tpmsfill {

/// Base of every exception tpmsfill throws on purpose. what() is one sentence, no newline.
class Error : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// A file could not be opened, read, written or renamed (the operating system said no).
class IoError : public Error {
 public:
  using Error::Error;
};

/// A file's bytes are not a valid mesh in the format they claim (or any format we read).
/// Carries where: a 1-based line for text formats, a byte offset for binary ones.
class ParseError : public Error {
 public:
  /// @param source   file name (or a caller's label for in-memory data)
  /// @param line     1-based line number, for text formats
  /// @param offset   byte offset from the start of the (decompressed) data, for binary formats
  /// @param reason   what is wrong, one sentence without the location
  ParseError(std::string source, std::optional<std::uint64_t> line,
             std::optional<std::uint64_t> offset, std::string reason)
      : Error(compose(source, line, offset, reason)),
        source_(std::move(source)),
        line_(line),
        offset_(offset),
        reason_(std::move(reason)) {}

  const std::string& source() const { return source_; }
  std::optional<std::uint64_t> line() const { return line_; }
  std::optional<std::uint64_t> byte_offset() const { return offset_; }
  const std::string& reason() const { return reason_; }

 private:
  // "file:12: reason" (the compiler convention editors can jump to) or "file: byte 84: reason".
  static std::string compose(const std::string& source, std::optional<std::uint64_t> line,
                             std::optional<std::uint64_t> offset, const std::string& reason) {
    std::string s = source;
    if (line) s += ":" + std::to_string(*line);
    if (offset) s += ": byte " + std::to_string(*offset);
    return s + ": " + reason;
  }

  std::string source_;
  std::optional<std::uint64_t> line_;
  std::optional<std::uint64_t> offset_;
  std::string reason_;
};

/// The input is well formed but cannot be used: an empty file, a file with no triangles,
/// or data larger than the limits in the options.
class InputError : public Error {
 public:
  using Error::Error;
};

/// A job would need more memory than its budget allows. The message names the budget, the
/// estimate and, where one exists, a setting that would fit (e.g. the largest voxel size).
class ResourceError : public Error {
 public:
  using Error::Error;
};

/// fill() produced a mesh that failed validation (it is not written). The message says which
/// check failed; this is a bug in tpmsfill, please report it with the input and options.
class ValidationError : public Error {
 public:
  using Error::Error;
};

/// The job was cancelled through a Progress callback.
class Cancelled : public Error {
 public:
  using Error::Error;
};

}  // namespace tpmsfill
