/// @file formats.hpp
/// @brief Internal: the readers behind parse_mesh() and what they share.
///
/// Each reader takes the (already decompressed and transcoded) bytes and fills a MeshFile:
/// points, triangles, faces_in_file, polygons_triangulated and warnings. Format detection, the
/// empty / no-triangles checks and the size limit live in read_mesh.cpp, once for all readers.
#pragma once

#include <cstdint>
#include <span>
#include <string>
#include <string_view>

#include "core/index_limits.hpp"
#include "io/parse_errors.hpp"
#include "tpmsfill/error.hpp"
#include "tpmsfill/io.hpp"

namespace tpmsfill::io {

void read_stl(std::string_view data, const std::string& source, MeshFile& mesh);
void read_obj(std::string_view data, const std::string& source, MeshFile& mesh);
void read_ply(std::string_view data, const std::string& source, MeshFile& mesh);
void read_off(std::string_view data, const std::string& source, MeshFile& mesh);

/// Is this binary STL rather than ASCII? Decided by content as docs/formats.md describes.
bool looks_like_binary_stl(std::string_view data);

/// Adds one face (indices already validated against mesh.soup.points) as triangles, and
/// counts it. The caller has checked polygon.size() >= 3.
void add_face(MeshFile& mesh, std::span<const std::uint32_t> polygon);

/// Is this word an OFF-family keyword (OFF, COFF, NOFF, CNOFF, STOFF, nOFF, 4OFF ...)?
bool is_off_keyword(std::string_view word);

using detail::fail_at_byte;
using detail::fail_at_line;

}  // namespace tpmsfill::io
