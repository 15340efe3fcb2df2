// read_tet_mesh() and parse_tet_mesh(): the format from the extension, the file pairs (.node
// and .ele, .mesh and .sol), the size limit, and the checks every format shares, made once
// here; the per-format readers are in tet_medit.cpp, tet_tetgen.cpp and tet_vtk.cpp.
#include <algorithm>
#include <cctype>
#include <cmath>
#include <filesystem>
#include <string>
#include <system_error>

#include "io/file_bytes.hpp"
#include "solid/internal/tet_formats.hpp"

namespace tpmsfill {

namespace io {

std::string lower_ascii(std::string_view word) {
  std::string out(word);
  std::transform(out.begin(), out.end(), out.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return out;
}

}  // namespace io

namespace {

// Nothing but whitespace.
bool is_blank(std::string_view data) {
  return data.find_first_not_of(" \t\r\n\f\v") == std::string_view::npos;
}

void check_size(std::string_view bytes, const std::string& name, std::uint64_t max_bytes) {
  if (bytes.size() > max_bytes)
    throw InputError(name + " is larger than the limit of " + std::to_string(max_bytes) + " bytes");
}

// What the readers promise, checked once for all: tets, corners in range, one material value
// per point or none, ids that fit 32 bits.
void check_tet_mesh_read(const TetMesh& mesh, const std::string& source) {
  if (!detail::fits_32bit_ids(mesh.points.size()))
    throw InputError(source + " has too many points");
  if (mesh.tets.empty()) throw InputError(source + " contains no tetrahedra");
  for (std::size_t i = 0; i < mesh.tets.size(); ++i)
    for (const std::uint32_t v : mesh.tets[i])
      if (v >= mesh.points.size())
        throw ParseError(source, std::nullopt, std::nullopt,
                         "tetrahedron " + std::to_string(i) + " refers to point " +
                             std::to_string(v) + " but there are " +
                             std::to_string(mesh.points.size()) + " points");
  if (!mesh.material.empty() && mesh.material.size() != mesh.points.size())
    throw ParseError(source, std::nullopt, std::nullopt,
                     std::to_string(mesh.material.size()) + " material values for " +
                         std::to_string(mesh.points.size()) + " points");
}

std::string extension_of(const std::filesystem::path& path) {
  return io::lower_ascii(path.extension().string());
}

TetFormat format_of(const std::filesystem::path& path) {
  const TetFormat format = tet_format_from_extension(path);
  if (format != TetFormat::Auto) return format;
  throw InputError(path.string() +
                   ": unknown extension for a tetrahedral mesh (use .mesh, .node, .ele or .vtk)");
}

bool file_exists(const std::filesystem::path& path) {
  std::error_code ec;
  return std::filesystem::exists(path, ec);
}

std::string read_nonblank(const std::filesystem::path& path, std::uint64_t max_bytes) {
  std::string bytes = detail::read_file_bytes(path, max_bytes);
  if (is_blank(bytes)) throw InputError(path.string() + " is empty");
  return bytes;
}

}  // namespace

TetFormat tet_format_from_extension(const std::filesystem::path& path) {
  const std::string ext = extension_of(path);
  if (ext == ".mesh" || ext == ".meshb") return TetFormat::Medit;
  if (ext == ".node" || ext == ".ele") return TetFormat::TetGen;
  if (ext == ".vtk") return TetFormat::Vtk;
  return TetFormat::Auto;
}

std::string_view tet_format_name(TetFormat format) {
  switch (format) {
    case TetFormat::Auto:
      return "auto";
    case TetFormat::Medit:
      return "MEDIT";
    case TetFormat::TetGen:
      return "TetGen";
    case TetFormat::Vtk:
      return "VTK";
  }
  return "auto";
}

TetMesh parse_tet_mesh(TetFormat format, std::string_view first, const std::string& first_name,
                       std::string_view second, const std::string& second_name,
                       const TetReadOptions& options) {
  check_size(first, first_name, options.max_bytes);
  check_size(second, second_name, options.max_bytes);
  if (is_blank(first)) throw InputError(first_name + " is empty");
  TetMesh mesh;
  switch (format) {
    case TetFormat::Auto:
      throw InputError(first_name + ": parse_tet_mesh needs a format (MEDIT, TetGen or VTK)");
    case TetFormat::Medit:
      io::read_medit_mesh(first, first_name, mesh);
      if (!second.empty() && !is_blank(second))
        io::read_medit_sol(second, second_name, mesh.points.size(), mesh.material);
      break;
    case TetFormat::TetGen:
      if (is_blank(second)) throw InputError(second_name + " is empty");
      io::read_tetgen(first, first_name, second, second_name, mesh);
      break;
    case TetFormat::Vtk:
      io::read_vtk_tets(first, first_name, options.material_name, mesh);
      break;
  }
  check_tet_mesh_read(mesh, first_name);
  return mesh;
}

TetMesh read_tet_mesh(const std::filesystem::path& path, const TetReadOptions& options) {
  const TetFormat format = options.format == TetFormat::Auto ? format_of(path) : options.format;
  switch (format) {
    case TetFormat::Auto:
    case TetFormat::Medit: {
      const std::string mesh = read_nonblank(path, options.max_bytes);
      std::filesystem::path sol = options.material_file;
      if (sol.empty() && !io::looks_like_binary_medit(mesh)) {
        sol = std::filesystem::path(path).replace_extension(".sol");
        if (!file_exists(sol)) sol.clear();
      }
      const std::string sol_bytes =
          sol.empty() ? std::string() : read_nonblank(sol, options.max_bytes);
      return parse_tet_mesh(TetFormat::Medit, mesh, path.string(), sol_bytes, sol.string(),
                            options);
    }
    case TetFormat::TetGen: {
      // x.node or x.ele: the pair x.node, x.ele; any other name is a base name, as TetGen's
      // own command line takes it ("cube.1": cube.1.node, cube.1.ele).
      const std::string ext = extension_of(path);
      std::filesystem::path node = path, ele = path;
      if (ext == ".node" || ext == ".ele") {
        node.replace_extension(".node");
        ele.replace_extension(".ele");
      } else {
        node += ".node";
        ele += ".ele";
      }
      const std::string node_bytes = read_nonblank(node, options.max_bytes);
      const std::string ele_bytes = read_nonblank(ele, options.max_bytes);
      return parse_tet_mesh(TetFormat::TetGen, node_bytes, node.string(), ele_bytes, ele.string(),
                            options);
    }
    case TetFormat::Vtk:
      return parse_tet_mesh(TetFormat::Vtk, read_nonblank(path, options.max_bytes), path.string(),
                            {}, {}, options);
  }
  throw InputError(path.string() + ": unknown tetrahedral mesh format");
}

}  // namespace tpmsfill
