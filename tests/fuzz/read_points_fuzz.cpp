// libFuzzer target for parse_points (point clouds: PLY vertices or XYZ text, gzip allowed).
// Any tpmsfill::Error is an accepted answer to bad bytes; any other exception, crash,
// sanitizer report, timeout or runaway allocation is a finding. What reads is finite.
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <string_view>
#include <tpmsfill/error.hpp>
#include <tpmsfill/scan/scanned_field.hpp>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view bytes(reinterpret_cast<const char*>(data), size);
  try {
    for (const tpmsfill::Vec3& p : tpmsfill::parse_points(bytes, "fuzz.xyz"))
      if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z)) __builtin_trap();
  } catch (const tpmsfill::Error&) {
  }
  return 0;
}
