// TetGen `.node` + `.ele` (https://wias-berlin.de/software/tetgen/fformats.html): the points,
// the first node attribute as material, the tets (10-node tets keep their 4 corners). One row
// per line; '#' starts a comment. The first node's number (0 or 1) sets the numbering of both
// files. Every count is checked against the bytes left before anything is allocated for it.
#include <string>
#include <string_view>

#include "io/text_scanner.hpp"
#include "solid/internal/tet_formats.hpp"

namespace tpmsfill::io {
namespace {

// A header or row must start on a line of its own: skips blank and comment lines first.
void next_header(TextScanner& in, std::string_view what) {
  if (!in.skip_empty_lines()) in.fail("the file ends where " + std::string(what) + " should be");
}
void next_row(TextScanner& in, std::uint64_t row, std::uint64_t rows, std::string_view what) {
  if (!in.skip_empty_lines())
    in.fail("the file ends after " + std::to_string(row) + " of " + std::to_string(rows) + " " +
            std::string(what));
}

// Refuses `rows` rows of `numbers` numbers (each at least a character and a separator) that
// the bytes left cannot hold; `line` is the header's.
void check_rows(const TextScanner& in, std::uint64_t line, std::uint64_t rows,
                std::uint64_t numbers, std::string_view what) {
  if (rows > (in.remaining() + 1) / (2 * numbers))
    fail_at_line(in.source(), line,
                 "the header declares " + std::to_string(rows) + " " + std::string(what) + " of " +
                     std::to_string(numbers) + " numbers each but only " +
                     std::to_string(in.remaining()) + " bytes follow");
}

// A count from a header that also bounds a row's width: refused past the bytes left.
std::uint64_t row_width_count(TextScanner& in, std::string_view what) {
  const std::uint64_t n = in.non_negative(in.required_token(what), what);
  if (n > in.remaining()) in.fail(std::string(what) + " " + std::to_string(n) + " is too large");
  return n;
}

struct NodeFile {
  std::uint64_t base = 0;  // the first node's number: 0 or 1
};

NodeFile read_nodes(TextScanner& in, TetMesh& mesh) {
  next_header(in, "the .node header");
  const std::uint64_t header_line = in.line();
  const std::uint64_t n = in.non_negative(in.required_token("the node count"), "node count");
  const std::uint64_t dim = in.non_negative(in.required_token("the dimension"), "dimension");
  if (dim != 3)
    in.fail("dimension " + std::to_string(dim) + ": only 3-dimensional nodes hold tetrahedra");
  const std::uint64_t attributes = row_width_count(in, "attribute count");
  const std::uint64_t markers = in.at_line_end() ? 0 : row_width_count(in, "boundary marker count");
  if (markers > 1) in.fail("boundary marker count " + std::to_string(markers) + " is not 0 or 1");
  in.next_line();
  check_rows(in, header_line, n, 4 + attributes + markers, "nodes");
  if (!detail::fits_32bit_ids(n)) throw InputError(in.source() + " has too many nodes");

  NodeFile file;
  mesh.points.reserve(n);
  if (attributes > 0) mesh.material.reserve(n);
  for (std::uint64_t i = 0; i < n; ++i) {
    next_row(in, i, n, "nodes");
    const std::int64_t number = in.integer(in.required_token("the node number"), "node number");
    if (i == 0) {
      if (number != 0 && number != 1)
        in.fail("the first node is numbered " + std::to_string(number) + " (0 or 1 expected)");
      file.base = static_cast<std::uint64_t>(number);
    } else if (number != static_cast<std::int64_t>(i + file.base)) {
      in.fail("node row " + std::to_string(i + 1) + " is numbered " + std::to_string(number) +
              ", expected " + std::to_string(i + file.base) + " (rows must be consecutive)");
    }
    Vec3 p;
    p.x = in.number(in.required_token("the x coordinate"), "x coordinate");
    p.y = in.number(in.required_token("the y coordinate"), "y coordinate");
    p.z = in.number(in.required_token("the z coordinate"), "z coordinate");
    mesh.points.push_back(p);
    for (std::uint64_t a = 0; a < attributes; ++a) {
      const double value = in.number(in.required_token("a node attribute"), "node attribute");
      if (a == 0) mesh.material.push_back(value);
    }
    if (markers > 0) in.integer(in.required_token("the boundary marker"), "boundary marker");
    in.next_line();
  }
  return file;
}

void read_elements(TextScanner& in, const NodeFile& nodes, TetMesh& mesh) {
  next_header(in, "the .ele header");
  const std::uint64_t header_line = in.line();
  const std::uint64_t n =
      in.non_negative(in.required_token("the tetrahedron count"), "tetrahedron count");
  const std::uint64_t per =
      in.non_negative(in.required_token("the nodes per tetrahedron"), "nodes per tetrahedron");
  if (per != 4 && per != 10)
    in.fail(std::to_string(per) + " nodes per tetrahedron (4 or 10 expected)");
  const std::uint64_t attributes = in.at_line_end() ? 0 : row_width_count(in, "attribute count");
  in.next_line();
  check_rows(in, header_line, n, 1 + per + attributes, "tetrahedra");

  mesh.tets.reserve(n);
  const std::uint64_t points = mesh.points.size();
  for (std::uint64_t i = 0; i < n; ++i) {
    next_row(in, i, n, "tetrahedra");
    const std::int64_t number =
        in.integer(in.required_token("the tetrahedron number"), "tetrahedron number");
    Tet t{};
    for (std::uint64_t k = 0; k < per; ++k) {
      const std::int64_t v = in.integer(in.required_token("a corner"), "tetrahedron corner");
      const std::int64_t index = v - static_cast<std::int64_t>(nodes.base);
      if (index < 0 || static_cast<std::uint64_t>(index) >= points)
        in.fail("tetrahedron " + std::to_string(number) + " has node " + std::to_string(v) +
                (points == 0 ? ", but there are no nodes"
                             : ", but the nodes are numbered " + std::to_string(nodes.base) +
                                   " to " + std::to_string(points - 1 + nodes.base)));
      if (k < 4) t[k] = static_cast<std::uint32_t>(index);
    }
    for (std::uint64_t a = 0; a < attributes; ++a)
      in.number(in.required_token("a tetrahedron attribute"), "tetrahedron attribute");
    mesh.tets.push_back(t);
    in.next_line();
  }
}

}  // namespace

void read_tetgen(std::string_view node, const std::string& node_source, std::string_view ele,
                 const std::string& ele_source, TetMesh& mesh) {
  TextScanner nodes_in(node, node_source, {.comment = '#'});
  const NodeFile nodes = read_nodes(nodes_in, mesh);
  TextScanner ele_in(ele, ele_source, {.comment = '#'});
  read_elements(ele_in, nodes, mesh);
}

}  // namespace tpmsfill::io
