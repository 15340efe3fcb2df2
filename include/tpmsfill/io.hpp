/// @file io.hpp
/// @brief Stage "io": mesh files to triangle soups and back (STL, OBJ, PLY, OFF).
///
/// Readers are our own, not CGAL's stock ones: they validate every declared count against the
/// data size before allocating, reject non-finite coordinates and out-of-range indices with
/// the line or byte offset, and triangulate polygons (ear clipping in the polygon's plane, a
/// fan only where that fails). The format is decided by content first and extension second;
/// gzip-compressed data and UTF-16 text (with a byte-order mark) are unwrapped transparently.
///
/// Writers write a temporary file in the target folder and rename it over the target, so a
/// failed write leaves nothing behind and never a half-written file.
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

#include "tpmsfill/types.hpp"

namespace tpmsfill {

enum class MeshFormat {
  Auto,       ///< reading: detect from content, then extension; writing: from the extension
  StlBinary,  ///< binary STL (written for ".stl")
  StlAscii,   ///< ASCII STL
  Obj,        ///< Wavefront OBJ
  Ply,        ///< PLY (read: ascii and binary of either endianness; written: binary little endian)
  Off,        ///< OFF / COFF / NOFF ... (ASCII)
};

/// Lower-case name used in reports and messages: "stl-binary", "stl-ascii", "obj", "ply", "off".
std::string_view format_name(MeshFormat format);

/// The format an extension names (case-insensitive), or Auto if it names none we know.
/// ".stl" gives StlBinary.
MeshFormat format_from_extension(const std::filesystem::path& path);

struct ReadOptions {
  /// Auto detects; anything else forces that reader (StlAscii and StlBinary both mean "STL,
  /// detect which").
  MeshFormat format = MeshFormat::Auto;
  /// Largest file (or decompressed gzip stream) accepted, in bytes. Guards memory.
  std::uint64_t max_bytes = std::uint64_t{4} << 30;
};

/// What a reader found, beside the soup itself.
struct MeshFile {
  TriangleSoup soup;
  MeshFormat format = MeshFormat::Auto;     ///< the format actually parsed
  bool gzip = false;                        ///< the bytes were gzip-compressed
  std::uint64_t faces_in_file = 0;          ///< faces as stored, before triangulation
  std::uint64_t polygons_triangulated = 0;  ///< of those, faces with more than three corners
  /// Things read around rather than refused, one sentence each (e.g. a binary STL whose
  /// header under-counts its triangles).
  std::vector<std::string> warnings;
};

/// Reads a mesh file.
/// @param[in] path     file to read; its extension only breaks ties the content leaves open
/// @param[in] options  forced format and size limit
/// @return the triangles (polygons triangulated) and what was found on the way
/// @throws IoError     the file cannot be opened or read
/// @throws ParseError  the bytes are malformed (message names the line or byte offset)
/// @throws InputError  the file is empty, holds no triangles, or is over options.max_bytes
MeshFile read_mesh_file(const std::filesystem::path& path, const ReadOptions& options = {});

/// read_mesh_file(path, options).soup.
TriangleSoup read_mesh(const std::filesystem::path& path, const ReadOptions& options = {});

/// Parses mesh bytes already in memory; the same rules and errors as read_mesh_file().
/// @param[in] bytes        the file's content
/// @param[in] source_name  used in error messages, and its extension as a format hint
MeshFile parse_mesh(std::string_view bytes, const std::string& source_name,
                    const ReadOptions& options = {});

struct WriteOptions {
  /// Auto takes the format from the path's extension (".stl" writes binary STL).
  MeshFormat format = MeshFormat::Auto;
};

/// Writes a soup, atomically: to a temporary file beside `path`, then renamed over it.
/// Coordinates are written so they read back bit-identical (binary STL: as float, its format).
/// @throws IoError     the folder is not writable, the disk is full, ...
/// @throws InputError  no format could be taken from the extension, or the soup has an
///                     index out of range or more points than the format can hold
void write_mesh(const std::filesystem::path& path, const TriangleSoup& soup,
                const WriteOptions& options = {});

/// Writes bytes (a report, say) the way write_mesh writes a mesh: to a temporary file beside
/// `path`, flushed, then renamed over it, so `path` is never half-written.
/// @throws IoError  the folder is not writable, the disk is full, ...
void write_file_atomically(const std::filesystem::path& path, const std::string& bytes);

}  // namespace tpmsfill
