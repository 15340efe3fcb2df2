// libFuzzer target for parse_volume (the seed's text and binary forms, NRRD, MetaImage, INR)
// and parse_itdf. Any tpmsfill::Error is an accepted answer to bad bytes; any other exception,
// crash, sanitizer report, timeout or runaway allocation is a finding. The first byte picks
// the reader (even: volumes, odd: ITDF) and is not part of the file.
#include <cstddef>
#include <cstdint>
#include <string_view>
#include <tpmsfill/error.hpp>
#include <tpmsfill/io/volume.hpp>
#include <tpmsfill/scan/itdf.hpp>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size == 0) return 0;
  const std::string_view bytes(reinterpret_cast<const char*>(data) + 1, size - 1);
  try {
    if (data[0] % 2 == 0) {
      tpmsfill::VolumeReadOptions options;
      options.max_bytes = std::uint64_t{64} << 20;  // a gzip bomb stops here
      const tpmsfill::VolumeFile f = tpmsfill::parse_volume(bytes, "fuzz", options);
      if (f.volume.values.size() != f.volume.count()) __builtin_trap();
    } else {
      const tpmsfill::ItdfFile f = tpmsfill::parse_itdf(bytes, "fuzz.itdf");
      // What was read writes back to the same bytes.
      if (tpmsfill::itdf_bytes(f) != bytes) __builtin_trap();
    }
  } catch (const tpmsfill::Error&) {
  }
  return 0;
}
