/// @file tet_mesh.hpp
/// @brief Input of the heterogeneous-material pipeline (Li & Fu 2021): a tetrahedral mesh
/// with a material value per vertex, its readers and writer, its boundary, and the checks the
/// volumetric parameterization (cube_map.hpp) needs: positive tets, a closed 2-manifold
/// boundary, one piece, genus 0.
///
/// Formats (docs/formats.md, "Tetrahedral meshes"):
///  - MEDIT `.mesh` (ASCII; Vertices and Tetrahedra, other sections skipped), material from a
///    `.sol` beside it (SolAtVertices, the first scalar field);
///  - TetGen `.node` + `.ele` (either name given; 0- or 1-based), material from the first node
///    attribute; 10-node tets keep their 4 corners;
///  - legacy VTK `.vtk` UNSTRUCTURED_GRID (ASCII or BINARY, versions 2 to 5.1), tets of cell
///    type 10 (24, the quadratic tetra, keeps its 4 corners; other cells skipped), material
///    from POINT_DATA SCALARS or FIELD arrays (by name, or the first with one component).
#pragma once

#include <array>
#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "tpmsfill/types.hpp"

namespace tpmsfill {

/// Corners of a tet, indices into TetMesh::points. Positive when
/// (b − a) · ((c − a) × (d − a)) > 0: d sees a, b, c counter-clockwise.
using Tet = std::array<std::uint32_t, 4>;

/// A tetrahedral mesh with an optional scalar material per point. Lengths in mm.
struct TetMesh {
  std::vector<Vec3> points;
  std::vector<Tet> tets;
  /// One value per point, or empty when the mesh carries no material.
  std::vector<double> material;
};

enum class TetFormat { Auto, Medit, TetGen, Vtk };

/// "MEDIT", "TetGen", "VTK" ("auto" for Auto).
std::string_view tet_format_name(TetFormat format);

/// The format a tet-mesh file's extension names (any case): .mesh (.meshb) MEDIT, .node and
/// .ele TetGen, .vtk VTK; Auto for any other extension.
TetFormat tet_format_from_extension(const std::filesystem::path& path);

struct TetReadOptions {
  TetFormat format = TetFormat::Auto;  ///< Auto: by extension (.mesh, .node/.ele, .vtk; any case)
  /// MEDIT: the .sol file holding the material (must exist). Empty: the mesh's path with
  /// ".sol" when that file exists (no material otherwise).
  std::filesystem::path material_file = {};
  /// VTK: the POINT_DATA SCALARS (or FIELD array, or other point attribute) to read as
  /// material; absent is a ParseError listing the arrays present. Empty: the first
  /// single-component SCALARS or FIELD array of POINT_DATA, or none.
  std::string material_name = {};
  /// Largest file accepted, in bytes (each file of a pair). Guards memory.
  std::uint64_t max_bytes = std::uint64_t{4} << 30;
};

/// Reads a tet mesh; the material when the files hold one. Every declared count is checked
/// against the bytes present before memory is reserved for it (docs/formats.md).
/// @param[in] path  the .mesh, .node, .ele or .vtk file
/// @throws IoError     a file cannot be opened or read (e.g. the .ele beside a .node, a named
///                     material_file)
/// @throws ParseError  malformed bytes (message names the file and line or byte offset), an
///                     index out of range, a material count that is not one per point, a
///                     non-finite coordinate or material value, binary MEDIT (.meshb)
/// @throws InputError  no tets (a VTK file's message lists the cell types it has), an unknown
///                     extension, an empty file, a file over options.max_bytes, more than
///                     2^32 − 1 points
TetMesh read_tet_mesh(const std::filesystem::path& path, const TetReadOptions& options = {});

/// Parses a tet mesh already in memory: `first` is the .mesh, .node or .vtk bytes, `second`
/// the .sol (optional, may be empty) or the .ele (required); the names label errors.
/// The same rules and errors as read_tet_mesh(); format must not be Auto (InputError).
TetMesh parse_tet_mesh(TetFormat format, std::string_view first, const std::string& first_name,
                       std::string_view second = {}, const std::string& second_name = {},
                       const TetReadOptions& options = {});

/// Writes a tet mesh atomically: `.mesh` (MEDIT, with a `.sol` beside it when the mesh has
/// material; without material, a `.sol` of that name is removed, since readers would take it
/// for this mesh's material) or
/// `.vtk` (legacy ASCII 4.2, material as POINT_DATA SCALARS "material"). Coordinates and
/// material as shortest round-trip text, so they read back bit-identical.
/// @throws InputError  another extension, an index out of range, a material count that is not
///                     one per point, a non-finite coordinate or material value
/// @throws IoError     the folder is not writable, the disk is full, ...
void write_tet_mesh(const std::filesystem::path& path, const TetMesh& mesh);

/// What check_tet_mesh() found. Counts, and the first offender of each kind (for messages).
struct TetMeshReport {
  std::uint64_t points = 0, tets = 0;
  std::uint64_t unused_points = 0;  ///< in no tet (ignored by the pipeline)
  std::uint64_t repeated_corner_tets = 0;
  std::uint64_t negative_tets = 0;  ///< exact orientation < 0
  std::uint64_t flat_tets = 0;      ///< exact orientation = 0 (no volume)
  std::optional<std::uint64_t> first_negative_tet, first_flat_tet;
  std::uint64_t overfull_faces = 0;  ///< faces in more than two tets
  std::uint64_t boundary_faces = 0;  ///< faces in one tet
  std::uint64_t boundary_edges = 0;
  std::uint64_t open_edges = 0;        ///< boundary edges not in exactly two boundary faces
  std::uint64_t pinched_vertices = 0;  ///< boundary vertices whose boundary faces form several fans
  std::uint64_t boundary_vertices = 0;
  std::uint64_t components = 0;       ///< pieces of tets joined by shared faces
  std::uint64_t boundary_shells = 0;  ///< pieces of the boundary joined by shared edges
  /// Of the boundary surface: V − E + F, and (when the surface is a closed 2-manifold in one
  /// piece) its genus (2 − χ) / 2.
  std::int64_t euler_characteristic = 0;
  std::optional<std::int64_t> genus;
  double volume = 0;  ///< Σ signed tet volumes, mm³
  Box3 bounds;
  bool has_material = false;
  double material_min = 0, material_max = 0;
  std::uint64_t non_finite_material = 0;
};

/// Checks a tet mesh; never throws. Orientation uses exact predicates (CGAL Epick).
/// @pre every corner index < points.size() (read_tet_mesh guarantees it)
TetMeshReport check_tet_mesh(const TetMesh& mesh);

/// The first reason a checked mesh cannot be mapped onto the unit cube, as one sentence
/// ("3 tets have no volume, the first is tet 17"), or nothing when it can: every tet positive,
/// no face in more than two tets, a closed 2-manifold boundary, one piece with one boundary
/// shell (no cavity), genus 0, material finite. A mesh whose tets are *all* negative (the other
/// orientation convention) passes: with_positive_tets() turns it.
std::optional<std::string> ball_problem(const TetMeshReport& report);

/// The mesh with every tet's last two corners swapped when all its tets are negative (files
/// from tools with the other orientation convention); otherwise unchanged.
TetMesh with_positive_tets(TetMesh mesh, const TetMeshReport& report);

/// The mesh with every chord (an edge inside the solid whose two ends lie on the boundary)
/// split at its midpoint, each tet around it halved (the midpoint's material the ends' mean).
/// A map onto the cube that keeps the boundary on the cube's faces cannot be fold-free with
/// a chord whose ends land on one face: its tets, which wind all the way round it, would have
/// to lie on both sides of that face. Mesh_3 leaves hundreds (libcgal-demo's bear, bunny00 and
/// fandisk at diagonal / 30: 250, 401 and 1,046). Then every face inside whose three corners
/// lie on the boundary (a thin part's tip) gets a point at its centroid, its two tets cut in
/// three there, for the same reason.
/// Points are appended; tets keep their order, each split tet's halves in its place.
/// @pre tets positive
TetMesh with_chords_split(TetMesh mesh);

/// The boundary faces (those in one tet), oriented outward, over all of mesh.points (unused
/// points stay, so indices are the mesh's). Face order: by tet, then by opposite corner.
/// @pre tets positive
TriangleSoup tet_boundary(const TetMesh& mesh);

}  // namespace tpmsfill
