// MEDIT (INRIA) ASCII meshes, `.mesh`, and their solutions, `.sol`: the points and tets of the
// mesh, the first scalar field at the vertices of the solution. Other sections are skipped by
// their declared row counts; every count is checked against the bytes left before anything is
// allocated for it. Keywords are matched in any case; '#' starts a comment.
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "io/text_scanner.hpp"
#include "solid/internal/tet_formats.hpp"

namespace tpmsfill::io {
namespace {

// Sections we skip: their keyword (lower case) and the numbers in each row (references
// included). Normals and tangents are 3-dimensional since the mesh must be.
struct Skipped {
  std::string_view name;
  std::uint64_t numbers;
};
constexpr Skipped kSkipped[] = {
    {"edges", 3},
    {"triangles", 4},
    {"quadrilaterals", 5},
    {"hexahedra", 9},
    {"prisms", 7},
    {"pentahedra", 7},
    {"pyramids", 6},
    {"edgesp2", 4},
    {"trianglesp2", 7},
    {"quadrilateralsq2", 10},
    {"hexahedraq2", 28},
    {"corners", 1},
    {"requiredvertices", 1},
    {"ridges", 1},
    {"requirededges", 1},
    {"requiredtriangles", 1},
    {"requiredquadrilaterals", 1},
    {"normals", 3},
    {"normalatvertices", 2},
    {"normalattrianglevertices", 3},
    {"normalatquadrilateralvertices", 3},
    {"tangents", 3},
    {"tangentatvertices", 2},
    {"tangentatedges", 3},
    {"vertexongeometricvertex", 2},
    {"vertexongeometricedge", 3},
    {"vertexongeometrictriangle", 4},
    {"edgeongeometricedge", 2},
    {"triangleongeometrictriangle", 2},
    {"subdomainfrommesh", 4},
    {"subdomainfromgeom", 4},
};

std::optional<std::uint64_t> skipped_row_numbers(std::string_view key) {
  for (const Skipped& s : kSkipped)
    if (s.name == key) return s.numbers;
  return std::nullopt;
}

// The next token wherever it is; the end of the file where one is needed is an error.
std::string_view need(TextScanner& in, std::string_view what) {
  const std::string_view t = in.token_any_line();
  if (t.empty()) in.fail("the file ends where " + std::string(what) + " should be");
  return t;
}

// The row count after a section keyword, refused when the bytes left cannot hold that many
// rows of `numbers` numbers (each at least one character and a separator).
std::uint64_t row_count(TextScanner& in, std::string_view section, std::uint64_t numbers) {
  const std::string what = std::string(section) + " count";
  const std::uint64_t count = in.non_negative(need(in, what), what);
  if (numbers > 0 && count > (in.remaining() + 1) / (2 * numbers))
    in.fail(std::string(section) + " declares " + std::to_string(count) + " rows of " +
            std::to_string(numbers) + " numbers but only " + std::to_string(in.remaining()) +
            " bytes follow");
  return count;
}

void skip_rows(TextScanner& in, std::string_view section, std::uint64_t numbers) {
  const std::uint64_t count = row_count(in, section, numbers);
  const std::string what = std::string(section) + " values";
  for (std::uint64_t i = 0; i < count * numbers; ++i) need(in, what);
}

std::uint64_t dimension(TextScanner& in) {
  const std::uint64_t d = in.non_negative(need(in, "the dimension"), "Dimension");
  if (d != 3)
    in.fail("Dimension " + std::to_string(d) + ": only 3-dimensional meshes hold tetrahedra");
  return d;
}

void version(TextScanner& in) {
  const std::int64_t v = in.integer(need(in, "the version"), "MeshVersionFormatted");
  if (v < 1 || v > 4)
    in.fail("MeshVersionFormatted " + std::to_string(v) + " is not a MEDIT version (1 to 4)");
}

void read_vertices(TextScanner& in, TetMesh& mesh) {
  const std::uint64_t n = row_count(in, "Vertices", 4);
  if (!detail::fits_32bit_ids(n)) throw InputError(in.source() + " has too many vertices");
  mesh.points.reserve(n);
  for (std::uint64_t i = 0; i < n; ++i) {
    Vec3 p;
    p.x = in.number(need(in, "an x coordinate"), "x coordinate");
    p.y = in.number(need(in, "a y coordinate"), "y coordinate");
    p.z = in.number(need(in, "a z coordinate"), "z coordinate");
    in.number(need(in, "a vertex reference"), "vertex reference");
    mesh.points.push_back(p);
  }
}

// Tetrahedra (4 corners and a reference) or TetrahedraP2 (10 nodes, the corners first, and a
// reference). Corners are 1-based; checked against the points when the Vertices came first,
// otherwise afterwards by check_deferred().
void read_tets(TextScanner& in, std::string_view section, std::uint64_t nodes, TetMesh& mesh,
               bool have_vertices) {
  const std::uint64_t n = row_count(in, section, nodes + 1);
  mesh.tets.reserve(n);
  for (std::uint64_t i = 0; i < n; ++i) {
    Tet t{};
    for (std::uint64_t k = 0; k < nodes + 1; ++k) {
      const std::string_view token = need(in, "a tetrahedron's vertex");
      if (k >= nodes) {
        in.number(token, "tetrahedron reference");
        continue;
      }
      const std::int64_t v = in.integer(token, "tetrahedron vertex");
      if (v < 1)
        in.fail("tetrahedron " + std::to_string(i + 1) + " has vertex " + std::to_string(v) +
                " (MEDIT numbers vertices from 1)");
      const auto index = static_cast<std::uint64_t>(v - 1);
      if (index >= (have_vertices ? mesh.points.size() : detail::kNoIndex))
        in.fail("tetrahedron " + std::to_string(i + 1) + " has vertex " + std::to_string(v) +
                " but there are " + std::to_string(mesh.points.size()) + " vertices");
      if (k < 4) t[k] = static_cast<std::uint32_t>(index);
    }
    mesh.tets.push_back(t);
  }
}

// Tets read before their Vertices: checked now, the error at the Tetrahedra keyword.
void check_deferred(const TetMesh& mesh, const std::string& source, std::uint64_t line) {
  for (std::size_t i = 0; i < mesh.tets.size(); ++i)
    for (const std::uint32_t v : mesh.tets[i])
      if (v >= mesh.points.size())
        fail_at_line(source, line,
                     "tetrahedron " + std::to_string(i + 1) + " has vertex " +
                         std::to_string(std::uint64_t{v} + 1) + " but there are " +
                         std::to_string(mesh.points.size()) + " vertices");
}

}  // namespace

bool looks_like_binary_medit(std::string_view data) {
  using namespace std::string_view_literals;
  return data.starts_with("\x01\0\0\0"sv) || data.starts_with("\0\0\0\x01"sv);
}

void read_medit_mesh(std::string_view data, const std::string& source, TetMesh& mesh) {
  if (looks_like_binary_medit(data))
    fail_at_byte(source, 0, "binary MEDIT (.meshb) is not supported; write ASCII .mesh");
  TextScanner in(data, source, {.comment = '#'});
  bool have_vertices = false, have_tets = false;
  std::optional<std::uint64_t> deferred_line;
  while (true) {
    const std::string_view word = in.token_any_line();
    if (word.empty()) break;
    const std::string key = lower_ascii(word);
    if (key == "end") break;
    if (key == "meshversionformatted") {
      version(in);
    } else if (key == "dimension") {
      dimension(in);
    } else if (key == "vertices") {
      if (have_vertices) in.fail("a second Vertices section");
      read_vertices(in, mesh);
      have_vertices = true;
    } else if (key == "tetrahedra" || key == "tetrahedrap2") {
      if (have_tets) in.fail("a second tetrahedra section ('" + std::string(word) + "')");
      if (!have_vertices) deferred_line = in.line();
      read_tets(in, word, key == "tetrahedra" ? 4 : 10, mesh, have_vertices);
      have_tets = true;
    } else if (const auto numbers = skipped_row_numbers(key)) {
      skip_rows(in, word, *numbers);
    } else if (key == "geometry" || key == "identifier") {
      need(in, "the " + std::string(word));  // a name, perhaps quoted: the rest of its line
      in.next_line();
    } else {
      in.fail("unknown MEDIT keyword '" + std::string(word) + "'");
    }
  }
  if (deferred_line) check_deferred(mesh, source, *deferred_line);
}

namespace {

// The values in a row of each solution type: 1 scalar, 2 vector, 3 symmetric tensor,
// 4 full matrix.
std::uint64_t type_width(TextScanner& in, std::uint64_t type, std::uint64_t dim) {
  switch (type) {
    case 1:
      return 1;
    case 2:
      return dim;
    case 3:
      return dim * (dim + 1) / 2;
    case 4:
      return dim * dim;
    default:
      in.fail("solution type " + std::to_string(type) +
              " is not 1 (scalar), 2 (vector), 3 (symmetric tensor) or 4 (matrix)");
  }
}

struct SolLayout {
  std::uint64_t width = 0;                 // values per row, all fields
  std::optional<std::uint64_t> scalar_at;  // the first scalar field's place in a row
};

// "nfields type1 type2 ...".
SolLayout sol_layout(TextScanner& in, std::uint64_t dim) {
  SolLayout layout;
  const std::uint64_t fields = in.non_negative(need(in, "the field count"), "field count");
  if (fields == 0) in.fail("a solution with no fields");
  if (fields > in.remaining() / 2) in.fail("the field count runs past the end of the file");
  for (std::uint64_t f = 0; f < fields; ++f) {
    const std::uint64_t type = in.non_negative(need(in, "a solution type"), "solution type");
    if (type == 1 && !layout.scalar_at) layout.scalar_at = layout.width;
    layout.width += type_width(in, type, dim);
  }
  return layout;
}

// One SolAt... section: the count, the field types, the rows. Reads the first scalar field
// into `material` when given one, skips the rest.
void sol_section(TextScanner& in, std::string_view section, std::uint64_t dim,
                 std::optional<std::uint64_t> points, std::vector<double>* material,
                 std::optional<std::uint64_t>& no_scalar_line) {
  const std::string what = std::string(section) + " count";
  const std::uint64_t n = in.non_negative(need(in, what), what);
  const std::uint64_t count_line = in.line();
  if (points && n != *points)
    in.fail(std::string(section) + " holds " + std::to_string(n) + " values but the mesh has " +
            std::to_string(*points) + " vertices");
  const SolLayout layout = sol_layout(in, dim);
  if (n > (in.remaining() + 1) / (2 * layout.width))
    fail_at_line(in.source(), count_line,
                 std::string(section) + " declares " + std::to_string(n) + " rows of " +
                     std::to_string(layout.width) + " values but only " +
                     std::to_string(in.remaining()) + " bytes follow");
  const bool read = material && layout.scalar_at;
  if (material && !layout.scalar_at && !no_scalar_line) no_scalar_line = count_line;
  if (read) material->reserve(n);
  for (std::uint64_t i = 0; i < n; ++i)
    for (std::uint64_t k = 0; k < layout.width; ++k) {
      const std::string_view t = need(in, "a solution value");
      if (read && k == *layout.scalar_at) material->push_back(in.number(t, "material value"));
    }
}

bool is_skipped_solution(std::string_view key) {
  return key == "solatedges" || key == "solattriangles" || key == "solatquadrilaterals" ||
         key == "solattetrahedra" || key == "solatprisms" || key == "solatpentahedra" ||
         key == "solathexahedra" || key == "solatpyramids";
}

}  // namespace

void read_medit_sol(std::string_view data, const std::string& source, std::uint64_t points,
                    std::vector<double>& material) {
  if (looks_like_binary_medit(data))
    fail_at_byte(source, 0, "binary MEDIT solution (.solb) is not supported; write ASCII .sol");
  TextScanner in(data, source, {.comment = '#'});
  std::uint64_t dim = 3;
  std::optional<std::uint64_t> no_scalar_line;
  bool have_vertex_solution = false;
  while (true) {
    const std::string_view word = in.token_any_line();
    if (word.empty()) break;
    const std::string key = lower_ascii(word);
    if (key == "end") break;
    if (key == "meshversionformatted") {
      version(in);
    } else if (key == "dimension") {
      dim = dimension(in);
    } else if (key == "solatvertices") {
      sol_section(in, word, dim, points, material.empty() ? &material : nullptr, no_scalar_line);
      have_vertex_solution = true;
    } else if (is_skipped_solution(key)) {
      sol_section(in, word, dim, std::nullopt, nullptr, no_scalar_line);
    } else if (key == "time") {
      in.number(need(in, "the time"), "Time");
    } else if (key == "iterations") {
      in.integer(need(in, "the iteration count"), "Iterations");
    } else {
      in.fail("unknown MEDIT solution keyword '" + std::string(word) + "'");
    }
  }
  if (!have_vertex_solution) in.fail("no SolAtVertices section: no material at the vertices");
  if (material.empty() && points > 0)
    fail_at_line(source, no_scalar_line.value_or(in.line()),
                 "SolAtVertices holds no scalar field (type 1): no material");
}

}  // namespace tpmsfill::io
