// Stage "classify": the inside rule's names, apart from the search so that the recipe reader
// (and its fuzzer) need no CGAL.
#include "core/names.hpp"
#include "tpmsfill/sampling/classify.hpp"

namespace tpmsfill {
namespace {

constexpr detail::Named<std::optional<InsideRule>> kInsideNames[] = {
    {std::nullopt, "auto"}, {InsideRule::Winding, "winding"}, {InsideRule::Parity, "parity"}};

}  // namespace

std::string_view inside_name(std::optional<InsideRule> rule) {
  return detail::name_of(kInsideNames, rule);
}

std::optional<InsideRule> inside_from_name(std::string_view name) {
  return detail::from_name(kInsideNames, name, "inside rule");
}

}  // namespace tpmsfill
