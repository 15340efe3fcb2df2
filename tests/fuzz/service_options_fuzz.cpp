// libFuzzer target for the service's options (job_options): the JSON a stranger posts with a
// job, for every kind (the first byte picks it). Any tpmsfill::Error is the 400 the request
// gets; any other exception, crash, sanitizer report (a stack overflow on nesting included),
// timeout or runaway allocation is a finding. Options that are accepted make a command line.
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <string>
#include <tpmsfill/error.hpp>
#include <tpmsfill/solid/material_volume.hpp>

#include "service/job_spec.hpp"

// As in read_recipe_fuzz: a recipe naming a volume file gets the refusal a missing one gets.
namespace tpmsfill {
ScalarVolume read_grading_volume(const std::filesystem::path& path, const MaterialVolumeOptions&) {
  throw IoError("cannot open " + path.string() + " (the fuzz build reads no named files)");
}
}  // namespace tpmsfill

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace tpmsfill::service;
  if (size == 0) return 0;
  const auto& kinds = job_kinds();
  const JobKind kind = kinds[data[0] % kinds.size()];
  const std::string text(reinterpret_cast<const char*>(data) + 1, size - 1);
  try {
    const JobOptions options = job_options(kind, text);
    const auto command =
        job_command(kind, options, {"input.stl", "out", "recipe.json", "report.json"}, 1 << 30);
    if (command.empty()) __builtin_trap();
  } catch (const tpmsfill::Error&) {
  }
  return 0;
}
