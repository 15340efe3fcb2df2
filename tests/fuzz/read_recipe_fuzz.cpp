// libFuzzer target for read_recipe: any tpmsfill::Error is an accepted answer to bad bytes; any
// other exception, crash, sanitizer report, timeout or runaway allocation is a finding. A recipe
// that reads must also write back (recipe_json) and read again to the same options.
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <string_view>
#include <tpmsfill/error.hpp>
#include <tpmsfill/recipe.hpp>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  try {
    const tpmsfill::FillOptions o = tpmsfill::read_recipe(text, "fuzz.json");
    const std::string once = tpmsfill::recipe_json(o);
    if (tpmsfill::recipe_json(tpmsfill::read_recipe(once, "echo")) != once) std::abort();
  } catch (const tpmsfill::Error&) {
  }
  return 0;
}
