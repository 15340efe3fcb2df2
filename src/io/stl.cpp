// STL, ASCII and binary. Which of the two is decided by content (looks_like_binary_stl), never
// by the header's first word alone: many binary files start their header with "solid".
#include <algorithm>
#include <array>
#include <bit>
#include <cctype>
#include <cmath>
#include <cstring>
#include <vector>

#include "io/formats.hpp"
#include "io/text_scanner.hpp"

namespace tpmsfill::io {
namespace {

constexpr std::uint64_t kHeaderBytes = 84;
constexpr std::uint64_t kFacetBytes = 50;

bool iequals(std::string_view a, std::string_view b) {
  return a.size() == b.size() && std::equal(a.begin(), a.end(), b.begin(), [](char x, char y) {
           return std::tolower(static_cast<unsigned char>(x)) ==
                  std::tolower(static_cast<unsigned char>(y));
         });
}

std::uint32_t load_u32_le(const char* p) {
  std::array<unsigned char, 4> b;
  std::memcpy(b.data(), p, 4);
  return std::uint32_t{b[0]} | std::uint32_t{b[1]} << 8 | std::uint32_t{b[2]} << 16 |
         std::uint32_t{b[3]} << 24;
}

float load_f32_le(const char* p) {
  return std::bit_cast<float>(load_u32_le(p));
}

// "solid" (any case) then a blank, a line break or the end, after an optional UTF-8 BOM and
// leading whitespace.
bool starts_with_solid(std::string_view data) {
  if (data.starts_with("\xEF\xBB\xBF")) data.remove_prefix(3);
  const std::size_t first = data.find_first_not_of(" \t\r\n");
  if (first == std::string_view::npos) return false;
  data.remove_prefix(first);
  if (data.size() < 5 || !iequals(data.substr(0, 5), "solid")) return false;
  return data.size() == 5 || std::string_view(" \t\r\n").find(data[5]) != std::string_view::npos;
}

// Text: no control bytes but whitespace, no NUL. Float data almost never passes this.
bool is_text(std::string_view data) {
  return std::none_of(data.begin(), data.end(), [](char c) {
    const auto u = static_cast<unsigned char>(c);
    return (u < 0x20 && c != '\t' && c != '\n' && c != '\r' && c != '\f' && c != '\v') || u == 0x7F;
  });
}

void read_binary(std::string_view data, const std::string& source, MeshFile& mesh) {
  const std::uint64_t size = data.size();
  if (size < kHeaderBytes)
    fail_at_byte(source, size,
                 "binary STL is truncated: " + std::to_string(size) +
                     " bytes, less than the 84-byte header and triangle count");
  const std::uint64_t declared = load_u32_le(data.data() + 80);
  const std::uint64_t needed = kHeaderBytes + kFacetBytes * declared;
  std::uint64_t count = declared;
  if (size < needed) {
    fail_at_byte(source, size,
                 "binary STL is truncated: header declares " + std::to_string(declared) +
                     " triangles (" + std::to_string(needed) + " bytes), the file has " +
                     std::to_string(size) + " bytes");
  } else if (size > needed) {
    const std::uint64_t excess = size - needed;
    if (excess % kFacetBytes == 0) {
      // The count under-states the data: read what the size implies rather than silently
      // dropping triangles (as CGAL's stock reader does).
      count = (size - kHeaderBytes) / kFacetBytes;
      mesh.warnings.push_back("binary STL header declares " + std::to_string(declared) +
                              " triangles but the file holds " + std::to_string(count) +
                              "; read all " + std::to_string(count));
    } else if (excess < kFacetBytes) {
      mesh.warnings.push_back("binary STL has " + std::to_string(excess) +
                              " trailing bytes after its " + std::to_string(declared) +
                              " triangles; ignored them");
    } else {
      fail_at_byte(source, needed,
                   "binary STL size " + std::to_string(size) + " does not match its " +
                       std::to_string(declared) + " declared triangles (" + std::to_string(needed) +
                       " bytes) nor any whole number of triangles");
    }
  }
  if (!detail::fits_32bit_ids(count * 3)) throw InputError(source + " has too many triangles");
  mesh.soup.points.reserve(count * 3);
  mesh.soup.triangles.reserve(count);
  for (std::uint64_t t = 0; t < count; ++t) {
    const std::uint64_t facet = kHeaderBytes + t * kFacetBytes;
    for (std::uint64_t corner = 0; corner < 3; ++corner) {
      const std::uint64_t at = facet + 12 + corner * 12;
      const char* p = data.data() + at;
      const Vec3 v{load_f32_le(p), load_f32_le(p + 4), load_f32_le(p + 8)};
      if (!std::isfinite(v.x) || !std::isfinite(v.y) || !std::isfinite(v.z))
        fail_at_byte(source, at, "triangle " + std::to_string(t) + " has a non-finite coordinate");
      mesh.soup.points.push_back(v);
    }
    const auto first = static_cast<std::uint32_t>(t * 3);
    mesh.soup.triangles.push_back({first, first + 1, first + 2});
  }
  mesh.faces_in_file = count;
  mesh.format = MeshFormat::StlBinary;
}

void read_ascii(std::string_view data, const std::string& source, MeshFile& mesh) {
  TextScanner in(data, source);
  std::vector<std::uint32_t> facet;
  bool in_solid = false, in_facet = false;
  while (in.skip_empty_lines()) {
    const std::string_view word = in.token();
    if (iequals(word, "solid")) {
      if (in_solid) in.fail("'solid' inside a solid (missing 'endsolid')");
      in_solid = true;  // the name is the rest of the line, spaces and all
    } else if (iequals(word, "endsolid")) {
      if (!in_solid) in.fail("'endsolid' without 'solid'");
      if (in_facet) in.fail("'endsolid' inside a facet (missing 'endfacet')");
      in_solid = false;
    } else if (!in_solid) {
      in.fail("expected 'solid', found '" + std::string(word) + "'");
    } else if (iequals(word, "facet")) {
      if (in_facet) in.fail("'facet' inside a facet (missing 'endfacet')");
      in_facet = true;  // the normal is recomputed by whoever needs it
      facet.clear();
    } else if (iequals(word, "outer") || iequals(word, "endloop")) {
      if (!in_facet) in.fail("'" + std::string(word) + "' outside a facet");
    } else if (iequals(word, "vertex")) {
      if (!in_facet) in.fail("'vertex' outside a facet");
      Vec3 v;
      v.x = in.number(in.required_token("x coordinate"), "x coordinate");
      v.y = in.number(in.required_token("y coordinate"), "y coordinate");
      v.z = in.number(in.required_token("z coordinate"), "z coordinate");
      if (!in.at_line_end()) in.fail("unexpected text after the vertex coordinates");
      if (!detail::fits_32bit_ids(mesh.soup.points.size() + 1))
        throw InputError(source + " is too big");
      facet.push_back(static_cast<std::uint32_t>(mesh.soup.points.size()));
      mesh.soup.points.push_back(v);
    } else if (iequals(word, "endfacet")) {
      if (!in_facet) in.fail("'endfacet' without 'facet'");
      if (facet.size() < 3)
        in.fail("facet with " + std::to_string(facet.size()) + " vertices (needs at least 3)");
      add_face(mesh, facet);
      in_facet = false;
    } else {
      in.fail("unexpected '" + std::string(word) + "' in ASCII STL");
    }
    in.next_line();
  }
  if (in_facet) in.fail("file ends inside a facet");
  if (in_solid) mesh.warnings.push_back("ASCII STL ends without 'endsolid'");
  mesh.format = MeshFormat::StlAscii;
}

}  // namespace

bool looks_like_binary_stl(std::string_view data) {
  // Only text that opens with "solid" is ASCII. A binary file whose header opens with "solid"
  // has float data with control or NUL bytes, whether or not its triangle count matches its
  // size (84 + 50 n), and the binary reader then checks that count.
  return !(starts_with_solid(data) && is_text(data));
}

void read_stl(std::string_view data, const std::string& source, MeshFile& mesh) {
  if (looks_like_binary_stl(data))
    read_binary(data, source, mesh);
  else
    read_ascii(data, source, mesh);
}

}  // namespace tpmsfill::io
