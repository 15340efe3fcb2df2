/// @file text_scanner.hpp
/// @brief Internal: the tokenizer and number parser every text reader uses, so whitespace,
/// comments, line continuations, number syntax and error locations are handled once.
#pragma once

#include <charconv>
#include <cmath>
#include <cstdint>
#include <string>
#include <string_view>
#include <system_error>

#include "io/formats.hpp"

namespace tpmsfill::io {

struct ScannerSyntax {
  char comment = '\0';        ///< starts a comment running to the end of the line ('\0': none)
  bool continuation = false;  ///< a backslash right before a line break joins the lines (OBJ)
};

/// Walks text token by token, keeping the 1-based line number for error messages. Lines end
/// in LF; a CR before it (CRLF files) is whitespace. A UTF-8 byte-order mark is skipped.
class TextScanner {
 public:
  /// @param first_line  number of the text's first line (when it starts inside a file)
  TextScanner(std::string_view text, const std::string& source, ScannerSyntax syntax = {},
              std::uint64_t first_line = 1)
      : p_(text.data()),
        end_(text.data() + text.size()),
        source_(source),
        syntax_(syntax),
        line_(first_line) {
    if (text.starts_with("\xEF\xBB\xBF")) p_ += 3;
  }

  std::uint64_t line() const { return line_; }
  const std::string& source() const { return source_; }
  /// Bytes not yet consumed.
  std::uint64_t remaining() const { return static_cast<std::uint64_t>(end_ - p_); }
  const char* position() const { return p_; }

  /// Skips blanks and comments up to (not past) the end of the line.
  void skip_blanks() {
    while (p_ != end_) {
      const char c = *p_;
      if (c == ' ' || c == '\t' || c == '\r' || c == '\f' || c == '\v') {
        ++p_;
      } else if (c == syntax_.comment && c != '\0') {
        while (p_ != end_ && *p_ != '\n') ++p_;
      } else if (c == '\\' && syntax_.continuation && is_continuation(p_)) {
        while (*p_ != '\n') ++p_;
        ++p_;
        ++line_;
      } else {
        return;
      }
    }
  }

  /// True at the end of the line (after blanks and comments) or of the text.
  bool at_line_end() {
    skip_blanks();
    return p_ == end_ || *p_ == '\n';
  }
  bool at_end() const { return p_ == end_; }

  /// Moves past the rest of the line (whatever it holds) and its line break.
  void next_line() {
    while (p_ != end_ && *p_ != '\n') {
      if (*p_ == '\\' && syntax_.continuation && is_continuation(p_)) {
        while (*p_ != '\n') ++p_;
        ++line_;
      }
      ++p_;
    }
    if (p_ != end_) {
      ++p_;
      ++line_;
    }
  }

  /// Skips blank lines and comment lines; false at the end of the text.
  bool skip_empty_lines() {
    while (at_line_end()) {
      if (p_ == end_) return false;
      next_line();
    }
    return true;
  }

  /// The next token on this line, or an empty view at the end of the line.
  std::string_view token() {
    skip_blanks();
    const char* begin = p_;
    while (p_ != end_ && !is_space(*p_) && *p_ != '\n' &&
           !(*p_ == syntax_.comment && *p_ != '\0') &&
           !(*p_ == '\\' && syntax_.continuation && is_continuation(p_)))
      ++p_;
    return {begin, static_cast<std::size_t>(p_ - begin)};
  }

  /// The next token, on this line or a later one; empty only at the end of the text.
  std::string_view token_any_line() {
    skip_empty_lines();
    return token();
  }

  /// A token on this line that must be there; `what` names it in the error.
  std::string_view required_token(std::string_view what) {
    std::string_view t = token();
    if (t.empty()) fail("expected " + std::string(what) + ", found the end of the line");
    return t;
  }

  /// A finite coordinate. Accepts a leading '+', which from_chars does not.
  double number(std::string_view token, std::string_view what) const {
    std::string_view t = token;
    if (t.size() > 1 && t[0] == '+' && t[1] != '-' && t[1] != '+') t.remove_prefix(1);
    double value = 0;
    const auto [end, ec] = std::from_chars(t.data(), t.data() + t.size(), value);
    if (ec == std::errc::result_out_of_range)
      fail(std::string(what) + " '" + std::string(token) + "' is out of range for a double");
    if (ec != std::errc{} || end != t.data() + t.size())
      fail("malformed number '" + std::string(token) + "' for " + std::string(what));
    if (!std::isfinite(value))
      fail(std::string(what) + " '" + std::string(token) + "' is not a finite number");
    return value;
  }

  /// An integer (for counts and indices). Accepts a leading '+'.
  std::int64_t integer(std::string_view token, std::string_view what) const {
    std::string_view t = token;
    if (t.size() > 1 && t[0] == '+' && t[1] != '-' && t[1] != '+') t.remove_prefix(1);
    std::int64_t value = 0;
    const auto [end, ec] = std::from_chars(t.data(), t.data() + t.size(), value);
    if (ec != std::errc{} || end != t.data() + t.size())
      fail("malformed integer '" + std::string(token) + "' for " + std::string(what));
    return value;
  }

  /// A count or index that must be >= 0.
  std::uint64_t non_negative(std::string_view token, std::string_view what) const {
    const std::int64_t value = integer(token, what);
    if (value < 0) fail(std::string(what) + " " + std::to_string(value) + " is negative");
    return static_cast<std::uint64_t>(value);
  }

  [[noreturn]] void fail(const std::string& reason) const { fail_at_line(source_, line_, reason); }

 private:
  static bool is_space(char c) {
    return c == ' ' || c == '\t' || c == '\r' || c == '\f' || c == '\v';
  }
  // A backslash followed by optional blanks and a line break.
  bool is_continuation(const char* at) const {
    ++at;
    while (at != end_ && (*at == ' ' || *at == '\t' || *at == '\r')) ++at;
    return at != end_ && *at == '\n';
  }

  const char* p_;
  const char* end_;
  const std::string& source_;
  ScannerSyntax syntax_;
  std::uint64_t line_;
};

}  // namespace tpmsfill::io
