// libFuzzer target for parse_solid_model (the .tsm model of seed 001). Any tpmsfill::Error is an
// accepted answer to bad bytes; any other exception, crash, sanitizer report, timeout or runaway
// allocation is a finding. What is read must write back to the same bytes.
#include <cstddef>
#include <cstdint>
#include <string_view>
#include <tpmsfill/error.hpp>
#include <tpmsfill/solid/solid_model.hpp>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view bytes(reinterpret_cast<const char*>(data), size);
  try {
    const tpmsfill::SolidModel m = tpmsfill::parse_solid_model(bytes, "fuzz.tsm");
    if (m.fit.spline.geometry.size() != m.fit.spline.basis.functions.size()) __builtin_trap();
    if (tpmsfill::solid_model_bytes(m) != bytes) __builtin_trap();
  } catch (const tpmsfill::Error&) {
  }
  return 0;
}
