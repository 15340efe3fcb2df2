/// @file names.hpp
/// @brief Enum ⇄ name tables: one table per enum serves its *_name and *_from_name, the
/// CLI and the recipes. A value may have aliases: entries after its first, which name it
/// wins and from_name accepts.
#pragma once

#include <cstddef>
#include <string>
#include <string_view>

#include "tpmsfill/error.hpp"

namespace tpmsfill::detail {

template <class E>
struct Named {
  E value;
  std::string_view name;
};

template <class E, std::size_t N>
constexpr std::string_view name_of(const Named<E> (&table)[N], E value) {
  for (const Named<E>& n : table)
    if (n.value == value) return n.name;
  return "unknown";
}

/// @throws InputError  "unknown WHAT 'NAME' (known: ...)", listing each value's first name
template <class E, std::size_t N>
E from_name(const Named<E> (&table)[N], std::string_view name, std::string_view what) {
  std::string known;
  for (const Named<E>& n : table) {
    if (n.name == name) return n.value;
    if (name_of(table, n.value) == n.name)
      known += (known.empty() ? "" : ", ") + std::string(n.name);
  }
  throw InputError("unknown " + std::string(what) + " '" + std::string(name) +
                   "' (known: " + known + ")");
}

}  // namespace tpmsfill::detail
