// libFuzzer target for read_recipe: any tpmsfill::Error is an accepted answer to bad bytes; any
// other exception, crash, sanitizer report, timeout or runaway allocation is a finding. A recipe
// that reads must also write back (recipe_json) and read again to the same options.
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <string_view>
#include <tpmsfill/error.hpp>
#include <tpmsfill/recipe.hpp>
#include <tpmsfill/solid/material_volume.hpp>

// A volume ramp names a file (a .tsm model or a volume). The fuzz build does not open files a
// fuzzed recipe names (read_volume_fuzz and read_solid_model_fuzz fuzz those readers), nor link
// the spline stages: here the volume is refused as the library refuses a missing one.
namespace tpmsfill {
ScalarVolume read_grading_volume(const std::filesystem::path& path, const MaterialVolumeOptions&) {
  throw IoError("cannot open " + path.string() + " (the fuzz build reads no named files)");
}
}  // namespace tpmsfill

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
