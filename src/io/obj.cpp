// Wavefront OBJ: only geometry ("v" and "f") is read; every other statement is skipped.
#include <vector>

#include "io/formats.hpp"
#include "io/text_scanner.hpp"

namespace tpmsfill::io {
namespace {

// "7", "7/1", "7//3", "7/1/3", "-2/..." -> 0-based index into the points read so far. Indices
// must refer to vertices defined above the face, as the OBJ spec requires for negative ones.
std::uint32_t face_index(const TextScanner& in, std::string_view token, std::uint64_t points) {
  const std::string_view v = token.substr(0, token.find('/'));
  const std::int64_t i = in.integer(v, "face vertex index");
  if (i == 0) in.fail("face vertex index 0 (OBJ indices start at 1)");
  const std::int64_t n = static_cast<std::int64_t>(points);
  const std::int64_t zero_based = i > 0 ? i - 1 : n + i;
  if (zero_based < 0 || zero_based >= n)
    in.fail("face vertex index " + std::to_string(i) + " is out of range (" +
            std::to_string(points) + " vertices defined so far)");
  return static_cast<std::uint32_t>(zero_based);
}

}  // namespace

void read_obj(std::string_view data, const std::string& source, MeshFile& mesh) {
  TextScanner in(data, source, {.comment = '#', .continuation = true});
  std::vector<std::uint32_t> face;
  auto& points = mesh.soup.points;
  while (in.skip_empty_lines()) {
    const std::string_view word = in.token();
    if (word == "v") {
      Vec3 p;
      p.x = in.number(in.required_token("x coordinate"), "x coordinate");
      p.y = in.number(in.required_token("y coordinate"), "y coordinate");
      p.z = in.number(in.required_token("z coordinate"), "z coordinate");
      // w or a colour may follow; they are not geometry.
      if (!detail::fits_32bit_ids(points.size() + 1))
        throw InputError(source + " has too many vertices");
      points.push_back(p);
    } else if (word == "f") {
      face.clear();
      for (std::string_view t = in.token(); !t.empty(); t = in.token())
        face.push_back(face_index(in, t, points.size()));
      if (face.size() < 3)
        in.fail("face with " + std::to_string(face.size()) + " vertices (needs at least 3)");
      add_face(mesh, face);
    }
    in.next_line();
  }
  mesh.format = MeshFormat::Obj;
}

}  // namespace tpmsfill::io
