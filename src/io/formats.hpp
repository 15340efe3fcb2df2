/// @file formats.hpp
/// @brief Internal: the readers behind parse_mesh() and what they share.
///
/// Each reader takes the (already decompressed and transcoded) bytes and fills a MeshFile:
/// points, triangles, faces_in_file, polygons_triangulated and warnings. Format detection, the
/// empty / no-triangles checks and the size limit live in read_mesh.cpp, once for all readers.
#pragma once

#include <cstdint>
#include <filesystem>
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

/// The most meshes a scene may place (nodes times the meshes each names), as for 3MF's
/// instances: assemblies of thousands of parts pass, a small file multiplying out does not.
inline constexpr std::uint64_t kMaxSceneInstances = 100000;

/// Reads a scene (glTF, GLB, FBX, COLLADA, 3DS and the rest assimp reads, src/io/scene.cpp):
/// every placed mesh with its node's transform, the scene's up axis turned onto +z and its unit
/// (glTF and COLLADA metres, FBX's stated centimetres per unit) to millimetres. `file` is the
/// file `data` holds as it is on disk, or null (bytes from memory, or unwrapped from gzip):
/// files the scene names (a glTF's .bin buffers) are read only from its folder or below it,
/// and without a file, none.
/// @throws ParseError  assimp cannot read it (its reason), or a placed point is not finite
/// @throws InputError  this build has no assimp, or the flattened scene passes the limits
void read_scene(std::string_view data, const std::string& source, const std::filesystem::path* file,
                std::uint64_t max_bytes, MeshFile& mesh);

/// Whether a name's extension is a scene's that assimp reads (never STL, OBJ, PLY, OFF, 3MF).
bool is_scene_extension(const std::filesystem::path& path);

/// Whether the bytes say they are a scene: GLB's magic, binary or text FBX, glTF's JSON, a
/// COLLADA document.
bool looks_like_scene(std::string_view data);

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
