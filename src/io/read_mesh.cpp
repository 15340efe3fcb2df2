// Placeholder until the readers land.
#include "tpmsfill/error.hpp"
#include "tpmsfill/io.hpp"

namespace tpmsfill {
std::string_view format_name(MeshFormat) {
  return "unknown";
}
MeshFormat format_from_extension(const std::filesystem::path&) {
  return MeshFormat::Auto;
}
MeshFile read_mesh_file(const std::filesystem::path& path, const ReadOptions&) {
  throw InputError(path.string() + ": reading is not implemented yet");
}
TriangleSoup read_mesh(const std::filesystem::path& path, const ReadOptions& options) {
  return read_mesh_file(path, options).soup;
}
MeshFile parse_mesh(std::string_view, const std::string& name, const ReadOptions&) {
  throw InputError(name + ": reading is not implemented yet");
}
void write_mesh(const std::filesystem::path& path, const TriangleSoup&, const WriteOptions&) {
  throw InputError(path.string() + ": writing is not implemented yet");
}
}  // namespace tpmsfill
