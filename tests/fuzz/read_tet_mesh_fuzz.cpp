// libFuzzer target for parse_tet_mesh. Any tpmsfill::Error is an accepted answer to bad bytes;
// any other exception, crash, sanitizer report, timeout or runaway allocation is a finding.
//
// Input: byte 0 selects the format (byte % 3: MEDIT, TetGen, VTK) unless TPMSFILL_FUZZ_FORMAT
// (medit, tetgen, vtk) forces one, so scripts/fuzz.sh can spend its time on one reader at a
// time; bytes 1 and 2 (little-endian) are the length of the first file (clamped), the rest is
// the second file (the .sol or the .ele; for VTK, a non-empty rest asks for the point array
// named "material" rather than the first one).
#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <string>
#include <string_view>
#include <tpmsfill/error.hpp>
#include <tpmsfill/solid/tet_mesh.hpp>

namespace {

constexpr tpmsfill::TetFormat kFormats[] = {tpmsfill::TetFormat::Medit, tpmsfill::TetFormat::TetGen,
                                            tpmsfill::TetFormat::Vtk};

int forced_format() {
  static const int index = [] {
    const char* env = std::getenv("TPMSFILL_FUZZ_FORMAT");
    if (!env) return -1;
    const std::string_view name(env);
    if (name == "medit") return 0;
    if (name == "tetgen") return 1;
    if (name == "vtk") return 2;
    return -1;
  }();
  return index;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size < 3) return 0;
  std::string_view bytes(reinterpret_cast<const char*>(data), size);
  int index = forced_format();
  if (index < 0) index = data[0] % 3;
  const std::size_t first_size = std::min<std::size_t>(data[1] | data[2] << 8, size - 3);
  const std::string_view first = bytes.substr(3, first_size), second = bytes.substr(3 + first_size);
  tpmsfill::TetReadOptions options;
  options.format = kFormats[index];
  options.max_bytes = std::uint64_t{64} << 20;
  if (options.format == tpmsfill::TetFormat::Vtk && !second.empty())
    options.material_name = "material";
  try {
    const tpmsfill::TetMesh mesh =
        tpmsfill::parse_tet_mesh(options.format, first, "fuzz", second, "fuzz2", options);
    // The promises every consumer relies on: tets, corners in range, one material per point.
    if (mesh.tets.empty()) __builtin_trap();
    for (const tpmsfill::Tet& t : mesh.tets)
      for (std::uint32_t v : t)
        if (v >= mesh.points.size()) __builtin_trap();
    if (!mesh.material.empty() && mesh.material.size() != mesh.points.size()) __builtin_trap();
  } catch (const tpmsfill::Error&) {
  }
  return 0;
}
