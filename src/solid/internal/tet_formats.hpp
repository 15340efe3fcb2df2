/// @file tet_formats.hpp
/// @brief Internal: the tet-mesh readers behind parse_tet_mesh() (tet_read.cpp), one per
/// format. Each takes bytes already in memory and fills a TetMesh, checking every count against
/// the bytes left before allocating for it and every corner index against the points; the
/// checks all formats share (at least one tet, the material count, 32-bit ids) are made once,
/// in tet_read.cpp.
#pragma once

#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "core/index_limits.hpp"
#include "io/parse_errors.hpp"
#include "tpmsfill/error.hpp"
#include "tpmsfill/solid/tet_mesh.hpp"

namespace tpmsfill::io {

/// MEDIT `.mesh` (ASCII): points and tets. Refuses binary `.meshb` with a sentence.
void read_medit_mesh(std::string_view data, const std::string& source, TetMesh& mesh);
/// MEDIT `.sol` (ASCII): the first scalar field of SolAtVertices, one value per point of a mesh
/// of `points` points, into `material`.
void read_medit_sol(std::string_view data, const std::string& source, std::uint64_t points,
                    std::vector<double>& material);
/// TetGen `.node` + `.ele`: points (and the first node attribute as material), tets.
void read_tetgen(std::string_view node, const std::string& node_source, std::string_view ele,
                 const std::string& ele_source, TetMesh& mesh);
/// Legacy VTK UNSTRUCTURED_GRID, ASCII or BINARY: points, tets, the material named
/// `material_name` (or the first single-component point array when empty).
void read_vtk_tets(std::string_view data, const std::string& source,
                   const std::string& material_name, TetMesh& mesh);

/// Whether the bytes start as a binary MEDIT file does: the int32 code 1 in either byte order.
bool looks_like_binary_medit(std::string_view data);

/// Lower-case copy of an ASCII keyword (the formats' keywords are matched in any case).
std::string lower_ascii(std::string_view word);

using detail::fail_at_byte;
using detail::fail_at_line;

}  // namespace tpmsfill::io
