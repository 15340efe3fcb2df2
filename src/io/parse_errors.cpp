// Out of line, so that every reader shares one place where ParseError's message is composed:
// GCC 12 reports a false -Wrestrict in std::string's concatenation there (GCC bug 105651),
// which is silenced here and nowhere else.
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC diagnostic ignored "-Wrestrict"
#endif

#include "io/parse_errors.hpp"

#include <optional>

#include "tpmsfill/error.hpp"

namespace tpmsfill::detail {

void fail_at_byte(const std::string& source, std::uint64_t offset, const std::string& reason) {
  throw ParseError(source, std::nullopt, offset, reason);
}

void fail_at_line(const std::string& source, std::uint64_t line, const std::string& reason) {
  throw ParseError(source, line, std::nullopt, reason);
}

}  // namespace tpmsfill::detail
