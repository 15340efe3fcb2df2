/// @file io.hpp
/// @brief Stage "io": mesh files to triangle soups and back (STL, OBJ, PLY, OFF, 3MF; scenes
/// such as glTF, FBX and COLLADA read through assimp).
///
/// Readers are our own, not CGAL's stock ones: they validate every declared count against the
/// data size before allocating, reject non-finite coordinates and out-of-range indices with
/// the line or byte offset, and triangulate polygons (ear clipping in the polygon's plane, a
/// fan only where that fails). The format is decided by content first and extension second;
/// gzip-compressed data and UTF-16 text (with a byte-order mark) are unwrapped transparently.
/// 3MF goes through lib3mf, the 3MF Consortium's library, in both directions. Scenes (glTF,
/// GLB, FBX, COLLADA, 3DS, ...) are read through assimp where the build has it (libassimp-dev),
/// flattened into one soup; a scene's side files (a glTF's .bin) only from its own folder.
///
/// Writers write a temporary file in the target folder and rename it over the target, so a
/// failed write leaves nothing behind and never a half-written file. MeshWriter writes a mesh
/// too large to hold in memory piece by piece, with the bytes write_mesh would write.
#pragma once

#include <cstdint>
#include <filesystem>
#include <memory>
#include <span>
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
  /// 3MF (a zip package; read: every build item of type model, transforms and components
  /// applied, in mm; written: one object in millimetres, with metadata; see CoordinateRounding)
  ThreeMf,
  /// A scene read through assimp (read only): glTF/GLB, FBX, COLLADA, 3DS and the rest assimp
  /// reads, flattened (every placed mesh transformed), its up axis turned onto +z, in mm from
  /// the unit the format states (glTF and COLLADA metres, FBX its stated unit; others as mm)
  Scene,
};

/// Lower-case name used in reports and messages: "stl-binary", "stl-ascii", "obj", "ply", "off",
/// "3mf", "scene".
std::string_view format_name(MeshFormat format);

/// The format an extension names (case-insensitive), or Auto if it names none we know.
/// ".stl" gives StlBinary; under a last ".gz" the extension before it counts ("x.ply.gz": Ply;
/// "x.3mf.gz" names none: a 3MF package is compressed already).
MeshFormat format_from_extension(const std::filesystem::path& path);

/// Whether the name ends in ".gz" (case-insensitive).
bool is_gzip_name(const std::filesystem::path& path);

/// The one sentence for a name whose extension names no mesh format: "<path>: unknown
/// extension (use .stl, .obj, .ply, .off or .3mf; the first four may end in .gz too)".
std::string unknown_mesh_extension(const std::filesystem::path& path);

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

/// Whether a mesh file is written gzip-compressed.
enum class Compression { Auto, None, Gzip };

// CoordinateRounding (how a format stores coordinates) is in types.hpp.

/// The rounding a format needs (Float for both STLs, ThreeMf for 3MF, None for the others).
CoordinateRounding rounding_for(MeshFormat format);

/// `p` as a file with `rounding` holds it.
Vec3 round_coordinates(CoordinateRounding rounding, Vec3 p);

/// Every point of `soup` as a file with `rounding` holds it.
void round_coordinates(CoordinateRounding rounding, TriangleSoup& soup);

/// What formats that hold metadata (3MF) store beside the mesh; the others ignore it.
struct MeshMetadata {
  std::string title;        ///< 3MF "Title" (empty: the file name's stem)
  std::string description;  ///< 3MF "Description": one paragraph on what the mesh is
  /// Files stored in the package, path inside it (e.g. "Metadata/tpmsfill-report.json") to
  /// bytes; tpmsfill writes its recipe and report there.
  std::vector<std::pair<std::string, std::string>> attachments;
};

struct WriteOptions {
  /// Auto takes the format from the path's extension (".stl" writes binary STL; "x.stl.gz"
  /// too, by the extension under ".gz").
  MeshFormat format = MeshFormat::Auto;
  /// Auto compresses when the path ends in ".gz" (gzip, zlib level 1: fast, for meshes of
  /// gigabytes): the readers inflate such files whatever their name.
  Compression compression = Compression::Auto;
  /// For 3MF: title, description, attachments. "Application" is always "tpmsfill VERSION".
  MeshMetadata metadata = {};
};

/// The options that write `path` as its name says: format by extension (under any ".gz"),
/// gzip when it ends in ".gz", its stem as a 3MF's title. For writing to a staged name that
/// has lost the extension.
WriteOptions write_options_for(const std::filesystem::path& path);

/// Writes a soup, atomically: to a temporary file beside `path`, then renamed over it (a
/// MeshWriter given the whole soup in one piece).
/// Coordinates are written so they read back bit-identical once rounded as the format needs
/// (rounding_for: STL as float, 3MF as lib3mf writes them); round, then validate, then write.
/// @throws IoError     the folder is not writable, the disk is full, ...
/// @throws InputError  no format could be taken from the extension, or the soup has an
///                     index out of range or more points than the format can hold
void write_mesh(const std::filesystem::path& path, const TriangleSoup& soup,
                const WriteOptions& options = {});

/// Writes a mesh piece by piece, for meshes too large to hold whole: the same bytes as
/// write_mesh() of the whole mesh, and as atomic (a temporary beside `path` until commit()).
/// The counts come first (formats with a header need them); then points in id order and
/// triangles in order, in pieces, interleaved as the caller makes them.
///
/// STL stores coordinates per facet, so its points are only counted. OBJ, OFF and PLY store
/// all points before the first face: faces that arrive before the last point go to a second
/// temporary (unlinked at once, so never left behind), copied after the points when the last
/// one is added; faces that arrive after it cost nothing extra (write_mesh's case). 3MF is
/// built whole by lib3mf at commit(): its points and triangles are held until then, as floats
/// and 32-bit ids (24 bytes a triangle for a closed mesh), and lib3mf needs as much again.
///
/// After any exception from add_points(), add_triangles() or commit() the writer is dead: its
/// temporaries are removed at once and every later call throws InputError. Destroying a writer
/// that was not committed removes its temporaries and leaves `path` untouched. Not thread-safe:
/// one thread calls at a time (a piece is formatted in parallel inside).
class MeshWriter {
 public:
  /// Creates the temporary and writes the header.
  /// @param[in] path       the file to write; its extension gives the format unless options do
  /// @param[in] points     how many points add_points() will add, in all
  /// @param[in] triangles  how many triangles add_triangles() will add, in all
  /// @throws InputError  no format could be taken from the extension, or the counts are too many
  ///                     for the format (binary STL's triangles, PLY's points: 32 bits)
  /// @throws IoError     the folder is not writable, the disk is full, ...
  MeshWriter(const std::filesystem::path& path, std::uint64_t points, std::uint64_t triangles,
             const WriteOptions& options = {});
  /// Without commit(): every temporary removed, `path` untouched.
  ~MeshWriter();
  MeshWriter(const MeshWriter&) = delete;
  MeshWriter& operator=(const MeshWriter&) = delete;

  /// The next points (ids continue from those added before). The last of them brings in the
  /// faces that were waiting for them (see above).
  /// @throws InputError  more points than declared, or the writer is dead or committed
  /// @throws IoError     the disk is full, ...
  void add_points(std::span<const Vec3> points);

  /// The next triangles. Their corners are point ids (< the declared point count); `window`
  /// holds the positions of ids [first_id, first_id + window.size()), which must cover every
  /// corner (STL stores coordinates per facet; the check is the same for every format, so a
  /// caller's bug shows whatever it writes). The points need not have been added yet.
  /// @throws InputError  more triangles than declared, a corner not below the declared point
  ///                     count or outside the window, or the writer is dead or committed
  /// @throws IoError     the disk is full, ...
  void add_triangles(std::span<const Triangle> triangles, std::span<const Vec3> window,
                     std::uint64_t first_id);

  /// Replaces the metadata given in the options (for figures known only once the mesh is made);
  /// stored at commit() by formats that hold metadata (3MF), ignored by the others.
  /// @throws InputError  the writer is dead or committed
  void set_metadata(MeshMetadata metadata);

  /// Checks that the declared counts were added, flushes, renames over `path`.
  /// @throws InputError  fewer points or triangles than declared, or the writer is dead or
  ///                     committed already
  /// @throws IoError     the last write, the flush or the rename failed
  void commit();

 private:
  struct State;
  State& open_state();
  std::unique_ptr<State> state_;
};

/// Writes bytes (a report, say) the way write_mesh writes a mesh: to a temporary file beside
/// `path`, flushed, then renamed over it, so `path` is never half-written.
/// @throws IoError  the folder is not writable, the disk is full, ...
void write_file_atomically(const std::filesystem::path& path, const std::string& bytes);

}  // namespace tpmsfill
