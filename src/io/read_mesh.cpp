// Loading, unwrapping (gzip, UTF-16), format detection and dispatch: everything the readers
// share, so each reader only parses its own syntax.
// GCC 12 at -O3 warns falsely (-Wrestrict, GCC bug 105651) inside <string> on `"literal" +
// std::string` once inlined. The warning is located in the library header, so it can only be
// silenced before the first include.
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC diagnostic ignored "-Wrestrict"
#endif

#include <algorithm>
#include <cctype>
#include <cstdio>
#include <cstring>

#include "io/file_bytes.hpp"
#include "io/formats.hpp"
#include "io/inflate.hpp"
#include "io/internal/triangulate_polygon.hpp"
#include "io/three_mf.hpp"

namespace tpmsfill {
namespace io {

void add_face(MeshFile& mesh, std::span<const std::uint32_t> polygon) {
  ++mesh.faces_in_file;
  if (polygon.size() > 3) ++mesh.polygons_triangulated;
  detail::triangulate_polygon(mesh.soup.points, polygon, mesh.soup.triangles);
}

}  // namespace io

namespace {

using namespace io;

bool is_exact_binary_stl(std::string_view data) {
  if (data.size() < 84) return false;
  std::uint32_t n = 0;
  for (int i = 3; i >= 0; --i) n = n << 8 | static_cast<unsigned char>(data[80 + i]);
  return data.size() == 84 + 50 * std::uint64_t{n};
}

// What a gzipped STL's first 84 bytes declare: a binary STL holds 84 + 50 n bytes, n its
// count. Text ("solid ...") declares nothing, and neither does another format's name.
detail::DeclaredSize binary_stl_size(const std::string& source, MeshFormat format) {
  const bool stl = format == MeshFormat::StlBinary || format == MeshFormat::StlAscii ||
                   (format == MeshFormat::Auto &&
                    detail::lower_extension(std::filesystem::path(source).stem()) == ".stl");
  if (!stl) return {};
  return {84, [](std::string_view head) -> std::uint64_t {
            std::size_t i = 0;
            while (i < head.size() && std::isspace(static_cast<unsigned char>(head[i]))) ++i;
            if (head.substr(i).starts_with("solid") || head.starts_with("\xFE\xFF") ||
                head.starts_with("\xFF\xFE"))
              return 0;  // text, or text in UTF-16
            std::uint32_t n = 0;
            for (int k = 3; k >= 0; --k) n = n << 8 | static_cast<unsigned char>(head[80 + k]);
            return 84 + 50 * std::uint64_t{n};
          }};
}

// UTF-16 with a byte-order mark -> bytes. Mesh files are ASCII, so anything else is refused
// rather than guessed at.
std::string from_utf16(std::string_view data, const std::string& source) {
  const bool big = static_cast<unsigned char>(data[0]) == 0xFE;
  if (data.size() % 2 != 0)
    fail_at_byte(source, data.size() - 1, "UTF-16 text has an odd number of bytes");
  std::string out;
  out.reserve(data.size() / 2);
  std::uint64_t line = 1;
  for (std::size_t i = 2; i < data.size(); i += 2) {
    const auto hi = static_cast<unsigned char>(data[big ? i : i + 1]);
    const auto lo = static_cast<unsigned char>(data[big ? i + 1 : i]);
    const unsigned unit = hi << 8 | lo;
    if (unit >= 0x80) {
      char hex[8];
      std::snprintf(hex, sizeof hex, "%04X", unit);
      fail_at_line(source, line, std::string("non-ASCII character U+") + hex + " in UTF-16 text");
    }
    if (unit == '\n') ++line;
    out.push_back(static_cast<char>(unit));
  }
  return out;
}

// Nothing but whitespace and '#' comment lines.
bool is_blank(std::string_view data) {
  if (data.starts_with("\xEF\xBB\xBF")) data.remove_prefix(3);
  bool comment = false;
  for (const char c : data) {
    if (c == '\n') {
      comment = false;
    } else if (!comment) {
      if (c == '#') {
        comment = true;
      } else if (c != ' ' && c != '\t' && c != '\r' && c != '\f' && c != '\v') {
        return false;
      }
    }
  }
  return true;
}

// The first word of the text after blank and '#' comment lines (and a UTF-8 BOM).
std::string_view first_word(std::string_view data) {
  if (data.starts_with("\xEF\xBB\xBF")) data.remove_prefix(3);
  constexpr std::string_view kBlank = " \t\r\n\f\v";
  while (true) {
    const std::size_t start = data.find_first_not_of(kBlank);
    if (start == std::string_view::npos) return {};
    data.remove_prefix(start);
    if (data[0] != '#') break;
    const std::size_t eol = data.find('\n');
    if (eol == std::string_view::npos) return {};
    data.remove_prefix(eol);
  }
  return data.substr(0, std::min(data.find_first_of(kBlank), std::size_t{64}));
}

bool is_obj_keyword(std::string_view word) {
  static constexpr std::string_view kWords[] = {"v", "vt", "vn",     "vp",     "f", "g",
                                                "o", "s",  "usemtl", "mtllib", "l", "p"};
  return std::find(std::begin(kWords), std::end(kWords), word) != std::end(kWords);
}

bool has_control_bytes(std::string_view data) {
  return std::any_of(data.begin(), data.end(), [](char c) {
    const auto u = static_cast<unsigned char>(c);
    return u < 0x20 && c != '\t' && c != '\n' && c != '\r' && c != '\f' && c != '\v';
  });
}

// What a file that is not a mesh most likely is, by its magic bytes ("" when none is known):
// a PNG saved as .stl is better told as a PNG than as an STL whose count is absurd.
std::string_view other_file_kind(std::string_view data) {
  static constexpr std::pair<std::string_view, std::string_view> kMagic[] = {
      {"\x89PNG\r\n\x1a\n", "a PNG image"},
      {"\xFF\xD8\xFF", "a JPEG image"},
      {"GIF87a", "a GIF image"},
      {"GIF89a", "a GIF image"},
      {"%PDF-", "a PDF document"},
      {"\x7F"
       "ELF",
       "a program (ELF)"},
      {std::string_view("II*\0", 4), "a TIFF image"},
      {std::string_view("MM\0*", 4), "a TIFF image"},
      {"BZh", "a bzip2 archive"},
      {"\xFD"
       "7zXZ",
       "an xz archive"},
      {"7z\xBC\xAF\x27\x1C", "a 7-Zip archive"},
      {"Rar!", "a RAR archive"},
      {"RIFF", "a RIFF file (WAV, AVI or WebP)"},
      {"{\"", "a JSON document"},
      {"<?xml", "an XML document"},
      {"<!DOCTYPE", "an HTML page"},
      {"<html", "an HTML page"},
  };
  for (const auto& [magic, kind] : kMagic)
    if (data.starts_with(magic)) return kind;
  return {};
}

// Content first; the extension only where the content leaves it open.
MeshFormat detect(std::string_view data, const std::string& source) {
  std::string_view text = data;
  if (text.starts_with("\xEF\xBB\xBF")) text.remove_prefix(3);
  if (text.starts_with("ply\n") || text.starts_with("ply\r")) return MeshFormat::Ply;
  // A zip's local file header: the only zip mesh format is 3MF (lib3mf explains a wrong one).
  // A zipped COLLADA (.zae) is a zip too; its name tells.
  if (data.starts_with("PK\x03\x04") && !is_exact_binary_stl(data))
    return is_scene_extension(source) ? MeshFormat::Scene : MeshFormat::ThreeMf;
  const std::string_view word = first_word(data);
  if (is_off_keyword(word)) return MeshFormat::Off;
  if (is_exact_binary_stl(data)) return MeshFormat::StlBinary;  // read_stl tells "solid" text
  if (looks_like_scene(data)) return MeshFormat::Scene;
  if (const std::string_view kind = other_file_kind(data); !kind.empty())
    detail::fail_at_byte(source, 0,
                         "this is " + std::string(kind) +
                             ", not a mesh (tpmsfill reads STL, OBJ, PLY, OFF, 3MF and the scenes "
                             "assimp reads: glTF, FBX, COLLADA, 3DS, ...)");
  std::string lower(word);
  std::transform(lower.begin(), lower.end(), lower.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  if (lower == "solid") return MeshFormat::StlAscii;
  if (is_obj_keyword(word)) return MeshFormat::Obj;
  if (const MeshFormat hint = format_from_extension(source); hint != MeshFormat::Auto) return hint;
  if (is_scene_extension(source)) return MeshFormat::Scene;  // 3DS and others without a magic
  // Binary data in no other format: the STL reader explains what is wrong with its count.
  if (data.size() >= 84 && has_control_bytes(data)) return MeshFormat::StlBinary;
  fail_at_line(source, 1,
               "not a mesh file: no STL, OBJ, PLY, OFF, 3MF or scene (glTF, FBX, COLLADA, ...) "
               "content recognised");
}

}  // namespace

std::string_view format_name(MeshFormat format) {
  switch (format) {
    case MeshFormat::Auto:
      return "auto";
    case MeshFormat::StlBinary:
      return "stl-binary";
    case MeshFormat::StlAscii:
      return "stl-ascii";
    case MeshFormat::Obj:
      return "obj";
    case MeshFormat::Ply:
      return "ply";
    case MeshFormat::Off:
      return "off";
    case MeshFormat::ThreeMf:
      return "3mf";
    case MeshFormat::Scene:
      return "scene";
  }
  return "auto";
}

using detail::lower_extension;

bool is_gzip_name(const std::filesystem::path& path) {
  return lower_extension(path) == ".gz";
}

std::string unknown_mesh_extension(const std::filesystem::path& path) {
  return path.string() +
         ": unknown extension (use .stl, .obj, .ply, .off or .3mf; the first four may end in .gz "
         "too)";
}

MeshFormat format_from_extension(const std::filesystem::path& path) {
  // "x.stl.gz": the format of "x.stl", compressed.
  const bool gzip = is_gzip_name(path);
  const std::string ext = lower_extension(gzip ? path.stem() : path);
  if (ext == ".3mf") return gzip ? MeshFormat::Auto : MeshFormat::ThreeMf;
  if (ext == ".stl") return MeshFormat::StlBinary;
  if (ext == ".obj") return MeshFormat::Obj;
  if (ext == ".ply") return MeshFormat::Ply;
  if (ext == ".off") return MeshFormat::Off;
  return MeshFormat::Auto;
}

namespace {

// parse_mesh(), and the file the bytes came from (null for bytes from memory), which a scene
// reads by name along with the files it names beside it.
MeshFile parse(std::string_view bytes, const std::string& source_name, const ReadOptions& options,
               const std::filesystem::path* file) {
  if (bytes.size() > options.max_bytes)
    throw InputError(source_name + " is larger than the limit of " +
                     std::to_string(options.max_bytes) + " bytes");
  MeshFile mesh;
  std::string_view data = bytes;
  std::string inflated, transcoded;
  // A binary STL header may start with any bytes, the gzip magic or a BOM included: a file whose
  // size matches its triangle count is never unwrapped.
  if (data.size() >= 2 && static_cast<unsigned char>(data[0]) == 0x1f &&
      static_cast<unsigned char>(data[1]) == 0x8b && !is_exact_binary_stl(data)) {
    inflated = detail::inflate_bytes(data, source_name, options.max_bytes,
                                     binary_stl_size(source_name, options.format));
    data = inflated;
    mesh.gzip = true;
  }
  if (data.size() >= 2 && !is_exact_binary_stl(data) &&
      (data.starts_with("\xFE\xFF") || data.starts_with("\xFF\xFE"))) {
    transcoded = from_utf16(data, source_name);
    data = transcoded;
  }
  if (is_blank(data)) throw InputError(source_name + " is empty");

  const MeshFormat format =
      options.format == MeshFormat::Auto ? detect(data, source_name) : options.format;
  switch (format) {
    case MeshFormat::Auto:
    case MeshFormat::StlBinary:
    case MeshFormat::StlAscii:
      read_stl(data, source_name, mesh);
      break;
    case MeshFormat::Obj:
      read_obj(data, source_name, mesh);
      break;
    case MeshFormat::Ply:
      read_ply(data, source_name, mesh);
      break;
    case MeshFormat::Off:
      read_off(data, source_name, mesh);
      break;
    case MeshFormat::ThreeMf:
      read_3mf(data, source_name, mesh);
      break;
    case MeshFormat::Scene:
      read_scene(data, source_name, data.data() == bytes.data() ? file : nullptr, options.max_bytes,
                 mesh);
      break;
  }
  if (mesh.soup.triangles.empty()) throw InputError(source_name + " contains no triangles");
  return mesh;
}

}  // namespace

MeshFile parse_mesh(std::string_view bytes, const std::string& source_name,
                    const ReadOptions& options) {
  return parse(bytes, source_name, options, nullptr);
}

MeshFile read_mesh_file(const std::filesystem::path& path, const ReadOptions& options) {
  return parse(detail::read_file_bytes(path, options.max_bytes), path.string(), options, &path);
}

TriangleSoup read_mesh(const std::filesystem::path& path, const ReadOptions& options) {
  return read_mesh_file(path, options).soup;
}

}  // namespace tpmsfill
