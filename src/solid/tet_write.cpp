// write_tet_mesh(): MEDIT `.mesh` (with a `.sol` beside it when the mesh has material) or
// legacy VTK `.vtk`, ASCII, numbers as their shortest round-trip text, each file written
// atomically.
#include <array>
#include <charconv>
#include <cmath>
#include <filesystem>
#include <string>

#include "io/number_text.hpp"
#include "solid/internal/tet_formats.hpp"
#include "tpmsfill/io.hpp"

namespace tpmsfill {
namespace {

using io::append_number;

// Refuses what the readers would refuse, before anything is written.
void check_writable(const std::filesystem::path& path, const TetMesh& mesh) {
  const auto refuse = [&](const std::string& why) {
    throw InputError("cannot write " + path.string() + ": " + why);
  };
  if (!detail::fits_32bit_ids(mesh.points.size())) refuse("too many points");
  for (std::size_t i = 0; i < mesh.points.size(); ++i) {
    const Vec3& p = mesh.points[i];
    if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z))
      refuse("point " + std::to_string(i) + " has a non-finite coordinate");
  }
  for (std::size_t i = 0; i < mesh.tets.size(); ++i)
    for (const std::uint32_t v : mesh.tets[i])
      if (v >= mesh.points.size())
        refuse("tetrahedron " + std::to_string(i) + " refers to point " + std::to_string(v) +
               ", but there are only " + std::to_string(mesh.points.size()) + " points");
  if (!mesh.material.empty() && mesh.material.size() != mesh.points.size())
    refuse(std::to_string(mesh.material.size()) + " material values for " +
           std::to_string(mesh.points.size()) + " points");
  for (std::size_t i = 0; i < mesh.material.size(); ++i)
    if (!std::isfinite(mesh.material[i]))
      refuse("the material of point " + std::to_string(i) + " is not a finite number");
}

std::string medit_mesh(const TetMesh& mesh) {
  std::string out = "MeshVersionFormatted 2\nDimension 3\n\nVertices\n";
  append_number(out, mesh.points.size());
  out += '\n';
  for (const Vec3& p : mesh.points) {
    for (const double c : {p.x, p.y, p.z}) {
      append_number(out, c);
      out += ' ';
    }
    out += "0\n";
  }
  out += "\nTetrahedra\n";
  append_number(out, mesh.tets.size());
  out += '\n';
  for (const Tet& t : mesh.tets) {
    for (const std::uint32_t v : t) {
      append_number(out, std::uint64_t{v} + 1);
      out += ' ';
    }
    out += "0\n";
  }
  out += "\nEnd\n";
  return out;
}

std::string medit_sol(const TetMesh& mesh) {
  std::string out = "MeshVersionFormatted 2\nDimension 3\n\nSolAtVertices\n";
  append_number(out, mesh.material.size());
  out += "\n1 1\n";
  for (const double m : mesh.material) {
    append_number(out, m);
    out += '\n';
  }
  out += "\nEnd\n";
  return out;
}

std::string vtk(const TetMesh& mesh) {
  std::string out =
      "# vtk DataFile Version 4.2\ntpmsfill tetrahedral mesh\nASCII\nDATASET "
      "UNSTRUCTURED_GRID\nPOINTS ";
  append_number(out, mesh.points.size());
  out += " double\n";
  for (const Vec3& p : mesh.points) io::append_xyz(out, p);
  out += "CELLS ";
  append_number(out, mesh.tets.size());
  out += ' ';
  append_number(out, mesh.tets.size() * 5);
  out += '\n';
  for (const Tet& t : mesh.tets) {
    out += '4';
    for (const std::uint32_t v : t) {
      out += ' ';
      append_number(out, v);
    }
    out += '\n';
  }
  out += "CELL_TYPES ";
  append_number(out, mesh.tets.size());
  out += '\n';
  for (std::size_t i = 0; i < mesh.tets.size(); ++i) out += "10\n";
  if (!mesh.material.empty()) {
    out += "POINT_DATA ";
    append_number(out, mesh.points.size());
    out += "\nSCALARS material double 1\nLOOKUP_TABLE default\n";
    for (const double m : mesh.material) {
      append_number(out, m);
      out += '\n';
    }
  }
  return out;
}

}  // namespace

void write_tet_mesh(const std::filesystem::path& path, const TetMesh& mesh) {
  const std::string ext = io::lower_ascii(path.extension().string());
  if (ext != ".mesh" && ext != ".vtk")
    throw InputError("cannot write " + path.string() +
                     ": unknown extension for a tetrahedral mesh (use .mesh or .vtk)");
  check_writable(path, mesh);
  if (ext == ".vtk") {
    write_file_atomically(path, vtk(mesh));
    return;
  }
  // The material first: a reader never finds the new mesh beside the old material. Without
  // material, an old .sol beside the mesh would be read as its material: it goes.
  const auto sol = std::filesystem::path(path).replace_extension(".sol");
  if (!mesh.material.empty()) write_file_atomically(sol, medit_sol(mesh));
  write_file_atomically(path, medit_mesh(mesh));
  std::error_code ignored;
  if (mesh.material.empty()) std::filesystem::remove(sol, ignored);
}

}  // namespace tpmsfill
