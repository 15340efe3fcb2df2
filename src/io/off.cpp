// OFF and its variants (COFF, NOFF, CNOFF, STOFF ...), ASCII only. Vertex lines may carry
// colours, normals or texture coordinates after x y z; face lines may carry a colour.
#include <string_view>
#include <utility>
#include <vector>

#include "io/formats.hpp"
#include "io/text_scanner.hpp"

namespace tpmsfill::io {

namespace {

// The keyword and what is glued to it: "OFF8" (seen in real files, "OFF8 6 12" being a cube's
// header with the space lost) is read as Geomview's and CGAL's stream readers read it, the
// keyword OFF followed by the vertex count 8. Only digits may be glued on.
std::pair<std::string_view, std::string_view> split_off_keyword(std::string_view word) {
  const std::size_t at = word.find("OFF");
  if (at == std::string_view::npos) return {};
  const std::string_view prefix = word.substr(0, at), rest = word.substr(at + 3);
  if (prefix.find_first_not_of("STCNn4") != std::string_view::npos ||
      rest.find_first_not_of("0123456789") != std::string_view::npos)
    return {};
  return {word.substr(0, at + 3), rest};
}

}  // namespace

bool is_off_keyword(std::string_view word) {
  return !split_off_keyword(word).first.empty();
}

void read_off(std::string_view data, const std::string& source, MeshFile& mesh) {
  TextScanner in(data, source, {.comment = '#'});
  in.skip_empty_lines();
  const std::string_view word = in.token();
  const auto [keyword, glued] = split_off_keyword(word);
  if (keyword.empty()) in.fail("expected an OFF keyword, found '" + std::string(word) + "'");
  // The header's next token: what was glued to the keyword first, if anything.
  std::string_view pending = glued;
  auto next_token = [&] {
    const std::string_view t = pending.empty() ? in.token_any_line() : pending;
    pending = {};
    return t;
  };
  if (keyword.find('4') != std::string_view::npos)
    in.fail("4-dimensional OFF ('" + std::string(keyword) + "') is not supported");
  if (keyword.find('n') != std::string_view::npos) {
    const std::uint64_t dimension = in.non_negative(next_token(), "nOFF dimension");
    if (dimension != 3)
      in.fail("nOFF with dimension " + std::to_string(dimension) + " is not supported");
  }
  std::string_view token = next_token();
  if (token == "BINARY") in.fail("binary OFF is not supported");
  const std::uint64_t nv = in.non_negative(token, "vertex count");
  const std::uint64_t nf = in.non_negative(in.token_any_line(), "face count");
  if (!in.at_line_end()) in.non_negative(in.token(), "edge count");  // optional, unused
  const std::uint64_t counts_line = in.line();
  in.next_line();

  // "x y z\n" is at least 6 bytes and "3 a b c\n" at least 8 (the last line may lack its line
  // break): counts the rest of the file cannot hold are refused before reserving anything.
  const std::uint64_t left = in.remaining() + 1;
  if (nv > left / 6 || nf > left / 8 || nv * 6 + nf * 8 > left + 1)
    fail_at_line(source, counts_line,
                 "OFF header declares " + std::to_string(nv) + " vertices and " +
                     std::to_string(nf) + " faces but only " + std::to_string(in.remaining()) +
                     " bytes follow");
  if (!detail::fits_32bit_ids(nv)) throw InputError(source + " has too many vertices");

  auto& points = mesh.soup.points;
  points.reserve(nv);
  for (std::uint64_t i = 0; i < nv; ++i) {
    if (!in.skip_empty_lines())
      in.fail("file ends after " + std::to_string(i) + " of " + std::to_string(nv) + " vertices");
    Vec3 p;
    p.x = in.number(in.required_token("x coordinate"), "x coordinate");
    p.y = in.number(in.required_token("y coordinate"), "y coordinate");
    p.z = in.number(in.required_token("z coordinate"), "z coordinate");
    points.push_back(p);  // whatever follows on the line (colour, normal) is not geometry
    in.next_line();
  }

  std::vector<std::uint32_t> face;
  for (std::uint64_t i = 0; i < nf; ++i) {
    if (!in.skip_empty_lines())
      in.fail("file ends after " + std::to_string(i) + " of " + std::to_string(nf) + " faces");
    const std::uint64_t n = in.non_negative(in.token(), "face vertex count");
    if (n < 3) in.fail("face with " + std::to_string(n) + " vertices (needs at least 3)");
    if (n > in.remaining() / 2)
      in.fail("face with " + std::to_string(n) + " vertices runs past the end of the file");
    face.clear();
    for (std::uint64_t k = 0; k < n; ++k) {
      const std::uint64_t index =
          in.non_negative(in.required_token("face vertex index"), "face vertex index");
      if (index >= nv)
        in.fail("face vertex index " + std::to_string(index) + " is out of range (" +
                std::to_string(nv) + " vertices)");
      face.push_back(static_cast<std::uint32_t>(index));
    }
    add_face(mesh, face);  // a colour may follow
    in.next_line();
  }
  mesh.format = MeshFormat::Off;
}

}  // namespace tpmsfill::io
