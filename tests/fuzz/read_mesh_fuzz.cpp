// libFuzzer target for parse_mesh. Any tpmsfill::Error is an accepted answer to bad bytes;
// any other exception, crash, sanitizer report, timeout or runaway allocation is a finding.
//
// The reader is chosen by TPMSFILL_FUZZ_FORMAT (auto, stl, obj, ply, off, 3mf) when it is set,
// so
// scripts/fuzz.sh can spend its time on one reader at a time; otherwise by the input's first
// byte, which is then not part of the mesh.
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <string>
#include <string_view>
#include <tpmsfill/error.hpp>
#include <tpmsfill/io.hpp>

namespace {

constexpr tpmsfill::MeshFormat kFormats[] = {
    tpmsfill::MeshFormat::Auto, tpmsfill::MeshFormat::StlBinary, tpmsfill::MeshFormat::Obj,
    tpmsfill::MeshFormat::Ply,  tpmsfill::MeshFormat::Off,       tpmsfill::MeshFormat::ThreeMf};

int forced_format() {
  static const int index = [] {
    const char* env = std::getenv("TPMSFILL_FUZZ_FORMAT");
    if (!env) return -1;
    const std::string_view name(env);
    if (name == "stl") return 1;
    if (name == "obj") return 2;
    if (name == "ply") return 3;
    if (name == "off") return 4;
    if (name == "3mf") return 5;
    return 0;
  }();
  return index;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  std::string_view bytes(reinterpret_cast<const char*>(data), size);
  int index = forced_format();
  if (index < 0) {
    if (bytes.empty()) return 0;
    index = static_cast<unsigned char>(bytes[0]) % std::size(kFormats);
    bytes.remove_prefix(1);
  }
  tpmsfill::ReadOptions options;
  options.format = kFormats[index];
  options.max_bytes = std::uint64_t{64} << 20;  // a gzip bomb stops here, within rss_limit
  try {
    const tpmsfill::MeshFile mesh = tpmsfill::parse_mesh(bytes, "fuzz", options);
    // The promise every consumer relies on: indices are in range.
    for (const tpmsfill::Triangle& t : mesh.soup.triangles)
      for (std::uint32_t v : t)
        if (v >= mesh.soup.points.size()) __builtin_trap();
  } catch (const tpmsfill::Error&) {
  }
  return 0;
}
