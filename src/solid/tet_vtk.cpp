// Legacy VTK (https://vtk.org/wp-content/uploads/2015/04/file-formats.pdf), versions 2 to 5.1,
// ASCII or BINARY (big-endian values right after their keyword line), DATASET
// UNSTRUCTURED_GRID: the points, the cells of type 10 (tetra; 24, the quadratic tetra, keeps its
// 4 corners), one point array as material. Every other block is skipped by its declared
// counts, each checked against the bytes left before anything is allocated for it. Errors name
// the line (keywords, ASCII values; newlines inside binary blocks count) or, inside a binary
// block, the byte offset of the value.
#include <algorithm>
#include <bit>
#include <cmath>
#include <map>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "io/text_scanner.hpp"
#include "solid/internal/tet_formats.hpp"

namespace tpmsfill::io {
namespace {

enum class Kind { Bit, Signed, Unsigned, Real, String };

struct VtkType {
  std::string_view name;
  Kind kind;
  std::uint64_t size;  // bytes per binary value (bits: 0, packed)
};

constexpr VtkType kTypes[] = {
    {"bit", Kind::Bit, 0},
    {"unsigned_char", Kind::Unsigned, 1},
    {"char", Kind::Signed, 1},
    {"signed_char", Kind::Signed, 1},
    {"unsigned_short", Kind::Unsigned, 2},
    {"short", Kind::Signed, 2},
    {"unsigned_int", Kind::Unsigned, 4},
    {"int", Kind::Signed, 4},
    {"unsigned_long", Kind::Unsigned, 8},
    {"long", Kind::Signed, 8},
    {"unsigned_long_long", Kind::Unsigned, 8},
    {"long_long", Kind::Signed, 8},
    {"vtkidtype", Kind::Signed, 4},  // the legacy writer writes ids as int
    {"vtktypeint8", Kind::Signed, 1},
    {"vtktypeuint8", Kind::Unsigned, 1},
    {"vtktypeint16", Kind::Signed, 2},
    {"vtktypeuint16", Kind::Unsigned, 2},
    {"vtktypeint32", Kind::Signed, 4},
    {"vtktypeuint32", Kind::Unsigned, 4},
    {"vtktypeint64", Kind::Signed, 8},
    {"vtktypeuint64", Kind::Unsigned, 8},
    {"float", Kind::Real, 4},
    {"double", Kind::Real, 8},
    {"string", Kind::String, 0},
    {"utf8_string", Kind::String, 0},
    {"variant", Kind::String, 0},
};

constexpr VtkType kInt32 = {"int", Kind::Signed, 4};
constexpr VtkType kUChar = {"unsigned_char", Kind::Unsigned, 1};
constexpr VtkType kFloat = {"float", Kind::Real, 4};

constexpr std::int64_t kTetra = 10, kQuadraticTetra = 24;

std::string cell_type_name(std::int64_t type) {
  switch (type) {
    case 1:
      return "vertex";
    case 2:
      return "poly-vertex";
    case 3:
      return "line";
    case 4:
      return "poly-line";
    case 5:
      return "triangle";
    case 6:
      return "triangle strip";
    case 7:
      return "polygon";
    case 8:
      return "pixel";
    case 9:
      return "quad";
    case 11:
      return "voxel";
    case 12:
      return "hexahedron";
    case 13:
      return "wedge";
    case 14:
      return "pyramid";
    case 22:
      return "quadratic triangle";
    case 25:
      return "quadratic hexahedron";
    case 42:
      return "polyhedron";
    default:
      return "cell";
  }
}

// A value as read: reals as double, integers as int64 (uint64 past its range saturates, which
// no index or count can reach).
struct Value {
  double real = 0;
  std::int64_t integer = 0;
};

// The cells as read, before CELL_TYPES says which are tets.
struct Cells {
  std::uint64_t line = 0;              // of the CELLS keyword, for errors about a cell
  std::vector<std::uint64_t> offsets;  // cell i is connectivity[offsets[i], offsets[i + 1])
  std::vector<std::int64_t> connectivity;
  std::optional<std::vector<std::int64_t>> types;
};

// Where the reader stands: the scanner over the rest of the text.
struct Mark {
  std::uint64_t offset = 0, line = 1;
};

class VtkReader {
 public:
  VtkReader(std::string_view data, const std::string& source, const std::string& material_name)
      : data_(data), source_(source), material_name_(material_name) {
    text_.emplace(data_, source_);
  }

  void read(TetMesh& mesh);

 private:
  TextScanner& in() { return *text_; }
  std::uint64_t offset() const {
    return static_cast<std::uint64_t>(text_->position() - data_.data());
  }
  Mark mark() const { return {offset(), text_->line()}; }
  void restore(Mark m) { text_.emplace(data_.substr(m.offset), source_, ScannerSyntax{}, m.line); }
  // Moves forward to `to`, counting the line breaks on the way (binary blocks hold some).
  void seek(std::uint64_t to) {
    const std::uint64_t from = offset();
    const auto breaks = std::count(data_.begin() + static_cast<std::ptrdiff_t>(from),
                                   data_.begin() + static_cast<std::ptrdiff_t>(to), '\n');
    restore({to, text_->line() + static_cast<std::uint64_t>(breaks)});
  }

  std::string_view need(std::string_view what) {
    const std::string_view t = in().token_any_line();
    if (t.empty()) in().fail("the file ends where " + std::string(what) + " should be");
    return t;
  }
  std::uint64_t count_arg(std::string_view what) {
    return in().non_negative(in().required_token(what), what);
  }
  const VtkType& type_arg();

  void header();
  void points(TetMesh& mesh);
  void cells();
  void cell_types();
  void cells_classic(std::uint64_t n, std::uint64_t size);
  void cells_offsets(std::uint64_t offsets, std::uint64_t size);
  void array_values(bool material, std::uint64_t count, const VtkType& type,
                    const std::string& what, TetMesh& mesh);
  void data_section(bool point, TetMesh& mesh);
  void attribute(std::string_view word, const std::string& key, TetMesh& mesh);
  void scalars(TetMesh& mesh);
  void field(TetMesh& mesh);
  void skip_metadata();
  void skip_metadata_if_next();
  bool wants_material(const std::string& name, std::uint64_t components, std::uint64_t tuples,
                      bool first_may_be_it = true);
  void finish(TetMesh& mesh);

  // Reads `count` values of `type` (ASCII: the next tokens; BINARY: the bytes after the current
  // line), handing each to `sink(i, value)`; a null sink skips them.
  template <typename Sink>
  void values(std::uint64_t count, const VtkType& type, std::string_view what, Sink* sink);
  void skip_values(std::uint64_t count, const VtkType& type, std::string_view what) {
    values<void(std::uint64_t, Value)>(count, type, what, nullptr);
  }
  [[noreturn]] void fail_value(const std::string& reason) const {
    if (binary_) fail_at_byte(source_, value_offset_, reason);
    text_->fail(reason);
  }

  std::string_view data_;
  const std::string& source_;
  const std::string& material_name_;
  std::optional<TextScanner> text_;
  bool binary_ = false;
  std::int64_t major_ = 0;
  std::uint64_t value_offset_ = 0;  // of the binary value being read, for errors

  bool have_points_ = false;
  std::optional<Cells> cells_;
  std::uint64_t cell_count_ = 0;
  // The attribute section we are in: POINT_DATA (true) or CELL_DATA (false), its tuple count.
  std::optional<bool> point_data_;
  std::uint64_t tuples_ = 0;
  std::uint64_t point_data_line_ = 0;
  std::vector<std::string> point_arrays_;  // names seen, for the error when the named one is not
  bool have_material_ = false;
};

const VtkType& VtkReader::type_arg() {
  const std::string_view word = in().required_token("a data type");
  const std::string key = lower_ascii(word);
  for (const VtkType& t : kTypes)
    if (t.name == key) return t;
  in().fail("unknown VTK data type '" + std::string(word) + "'");
}

Value decode(const VtkType& type, const char* p) {
  std::uint64_t bits = 0;
  for (std::uint64_t i = 0; i < type.size; ++i) bits = bits << 8 | static_cast<unsigned char>(p[i]);
  Value v;
  if (type.kind == Kind::Real) {
    v.real = type.size == 4
                 ? static_cast<double>(std::bit_cast<float>(static_cast<std::uint32_t>(bits)))
                 : std::bit_cast<double>(bits);
    return v;
  }
  if (type.kind == Kind::Signed && type.size < 8) {
    const std::uint64_t sign = std::uint64_t{1} << (8 * type.size - 1);
    v.integer = static_cast<std::int64_t>(bits ^ sign) - static_cast<std::int64_t>(sign);
  } else if (type.kind == Kind::Unsigned && bits > static_cast<std::uint64_t>(INT64_MAX)) {
    v.integer = INT64_MAX;
  } else {
    v.integer = static_cast<std::int64_t>(bits);
  }
  v.real = static_cast<double>(v.integer);
  return v;
}

template <typename Sink>
void VtkReader::values(std::uint64_t count, const VtkType& type, std::string_view what,
                       Sink* sink) {
  const std::string label(what);
  if (type.kind == Kind::String)
    in().fail(label + " is a " + std::string(type.name) + " array, which is not supported");
  if (sink && type.kind == Kind::Bit) in().fail(label + " is a bit array, not numbers");
  if (!binary_) {
    if (count > (in().remaining() + 1) / 2)
      in().fail(label + ": " + std::to_string(count) + " values declared but only " +
                std::to_string(in().remaining()) + " bytes follow");
    for (std::uint64_t i = 0; i < count; ++i) {
      const std::string_view t = need(label);
      if (!sink) continue;
      Value v;
      if (type.kind == Kind::Real) {
        v.real = in().number(t, label);
      } else {
        v.integer = in().integer(t, label);
        v.real = static_cast<double>(v.integer);
      }
      (*sink)(i, v);
    }
    return;
  }
  in().next_line();  // binary values start after their keyword line
  const std::uint64_t start = offset(), left = data_.size() - start;
  const std::uint64_t bytes = type.kind == Kind::Bit     ? count / 8 + (count % 8 != 0)
                              : count > left / type.size ? left + 1
                                                         : count * type.size;
  if (bytes > left)
    fail_at_byte(source_, start,
                 label + ": " + std::to_string(count) + " " + std::string(type.name) +
                     " values declared but only " + std::to_string(left) + " bytes follow");
  if (sink)
    for (std::uint64_t i = 0; i < count; ++i) {
      value_offset_ = start + i * type.size;
      (*sink)(i, decode(type, data_.data() + value_offset_));
    }
  seek(start + bytes);
}

void VtkReader::header() {
  const std::string_view words[] = {in().token(), in().token(), in().token(), in().token()};
  if (words[0] != "#" || lower_ascii(words[1]) != "vtk" || lower_ascii(words[2]) != "datafile" ||
      lower_ascii(words[3]) != "version")
    in().fail("a legacy VTK file starts with '# vtk DataFile Version'");
  const std::string_view version = in().required_token("the version");
  const std::string_view major = version.substr(0, version.find('.'));
  major_ = in().integer(major, "VTK version");
  if (major_ < 1) in().fail("VTK version '" + std::string(version) + "' is not a version");
  in().next_line();
  if (in().at_end()) in().fail("the file ends before its title line");
  in().next_line();  // the title: any text
  const std::string_view encoding = in().token();
  const std::string key = lower_ascii(encoding);
  if (key != "ascii" && key != "binary")
    in().fail("line 3 must say ASCII or BINARY, not '" + std::string(encoding) + "'");
  binary_ = key == "binary";
  in().next_line();
}

void VtkReader::points(TetMesh& mesh) {
  if (have_points_) in().fail("a second POINTS section");
  const std::uint64_t n = count_arg("the point count");
  const VtkType& type = type_arg();
  if (n > data_.size())
    in().fail("POINTS declares " + std::to_string(n) + " points, more than the file can hold");
  if (!detail::fits_32bit_ids(n)) throw InputError(source_ + " has too many points");
  std::vector<double> xyz;
  auto sink = [&](std::uint64_t i, Value v) {
    if (!std::isfinite(v.real))
      fail_value("point " + std::to_string(i / 3) + " has a non-finite coordinate");
    if (i == 0) xyz.reserve(3 * n);  // values() has checked 3n against the bytes left
    xyz.push_back(v.real);
  };
  values(3 * n, type, "POINTS", &sink);
  mesh.points.resize(n);
  for (std::uint64_t i = 0; i < n; ++i)
    mesh.points[i] = {xyz[3 * i], xyz[3 * i + 1], xyz[3 * i + 2]};
  have_points_ = true;
}

// Version 5 and later: CELLS nOffsets nConnectivity, then OFFSETS and CONNECTIVITY arrays.
void VtkReader::cells_offsets(std::uint64_t n_offsets, std::uint64_t size) {
  Cells& cells = *cells_;
  for (const std::string_view keyword : {"OFFSETS", "CONNECTIVITY"}) {
    skip_metadata_if_next();
    const std::string_view word = need(keyword);
    if (lower_ascii(word) != lower_ascii(keyword))
      in().fail("expected " + std::string(keyword) + " after CELLS, found '" + std::string(word) +
                "'");
    const VtkType& type = type_arg();
    if (type.kind != Kind::Signed && type.kind != Kind::Unsigned)
      in().fail(std::string(keyword) + " must have an integer type, not " + std::string(type.name));
    const bool offsets = keyword == "OFFSETS";
    const std::uint64_t count = offsets ? n_offsets : size;
    auto sink = [&](std::uint64_t i, Value v) {
      if (offsets) {
        if (i == 0) cells.offsets.reserve(count);
        const std::int64_t previous = i == 0 ? 0 : static_cast<std::int64_t>(cells.offsets.back());
        if (v.integer < previous || (i == 0 && v.integer != 0) ||
            static_cast<std::uint64_t>(v.integer) > size)
          fail_value("offset " + std::to_string(i) + " is " + std::to_string(v.integer) +
                     " (offsets start at 0, never decrease, end at " + std::to_string(size) + ")");
        cells.offsets.push_back(static_cast<std::uint64_t>(v.integer));
      } else {
        if (i == 0) cells.connectivity.reserve(count);
        if (v.integer < 0) fail_value("connectivity entry " + std::to_string(i) + " is negative");
        cells.connectivity.push_back(v.integer);
      }
    };
    values(count, type, keyword, &sink);
    if (offsets && n_offsets > 0 && cells.offsets.back() != size)
      in().fail("the last offset is " + std::to_string(cells.offsets.back()) +
                " but CELLS declares " + std::to_string(size) + " connectivity entries");
  }
  if (cells.offsets.empty()) cells.offsets.push_back(0);
  cell_count_ = cells.offsets.size() - 1;
}

// Before version 5: CELLS n size, then per cell its point count and its points.
void VtkReader::cells_classic(std::uint64_t n, std::uint64_t size) {
  Cells& cells = *cells_;
  if (n > size)
    in().fail("CELLS declares " + std::to_string(n) + " cells in " + std::to_string(size) +
              " numbers (each cell takes at least one)");
  std::uint64_t left_in_cell = 0;  // points still to come in the current cell
  auto sink = [&](std::uint64_t i, Value v) {
    if (i == 0) {
      cells.offsets.reserve(n + 1);
      cells.connectivity.reserve(size - n);
      cells.offsets.push_back(0);
    }
    if (left_in_cell > 0) {
      if (v.integer < 0)
        fail_value("cell " + std::to_string(cells.offsets.size() - 1) +
                   " has a negative point index");
      cells.connectivity.push_back(v.integer);
      if (--left_in_cell == 0) cells.offsets.push_back(cells.connectivity.size());
      return;
    }
    const std::uint64_t cell = cells.offsets.size() - 1;
    if (cell >= n)
      fail_value("CELLS declares " + std::to_string(n) + " cells but its " + std::to_string(size) +
                 " numbers hold more");
    if (v.integer < 0 || static_cast<std::uint64_t>(v.integer) >= size - i)
      fail_value("cell " + std::to_string(cell) + " has " + std::to_string(v.integer) +
                 " points, more than the numbers left in CELLS");
    left_in_cell = static_cast<std::uint64_t>(v.integer);
    if (left_in_cell == 0) cells.offsets.push_back(cells.connectivity.size());
  };
  values(size, kInt32, "CELLS", &sink);
  if (cells.offsets.empty()) cells.offsets.push_back(0);
  if (cells.offsets.size() - 1 != n)
    fail_at_line(source_, cells.line,
                 "CELLS declares " + std::to_string(n) + " cells but its numbers hold " +
                     std::to_string(cells.offsets.size() - 1));
  cell_count_ = n;
}

void VtkReader::cells() {
  if (cells_) in().fail("a second CELLS section");
  cells_.emplace();
  cells_->line = in().line();
  const std::uint64_t a = count_arg("the cell count");
  const std::uint64_t b = count_arg("the size");
  if (major_ >= 5)
    cells_offsets(a, b);
  else
    cells_classic(a, b);
}

void VtkReader::cell_types() {
  if (!cells_) in().fail("CELL_TYPES before CELLS");
  if (cells_->types) in().fail("a second CELL_TYPES section");
  const std::uint64_t n = count_arg("the cell count");
  if (n != cell_count_)
    in().fail("CELL_TYPES declares " + std::to_string(n) + " cells but CELLS holds " +
              std::to_string(cell_count_));
  std::vector<std::int64_t>& types = cells_->types.emplace();
  auto sink = [&](std::uint64_t i, Value v) {
    if (i == 0) types.reserve(n);
    types.push_back(v.integer);
  };
  values(n, kInt32, "CELL_TYPES", &sink);
}

// METADATA: text lines up to an empty one (VTK 5.1 writes it after some arrays).
void VtkReader::skip_metadata() {
  in().next_line();
  while (!in().at_end()) {
    const bool empty = in().at_line_end();
    in().next_line();
    if (empty) break;
  }
}

void VtkReader::skip_metadata_if_next() {
  const Mark before = mark();
  if (lower_ascii(in().token_any_line()) == "metadata")
    skip_metadata();
  else
    restore(before);
}

// Whether this point array is the material: the one named so, or (no name given, and
// `first_may_be_it`: SCALARS and FIELD arrays) the first with one component.
bool VtkReader::wants_material(const std::string& name, std::uint64_t components,
                               std::uint64_t tuples, bool first_may_be_it) {
  if (!point_data_.value_or(false)) return false;
  point_arrays_.push_back(name);
  if (have_material_) return false;
  if (material_name_.empty()) return first_may_be_it && components == 1 && tuples == tuples_;
  if (name != material_name_) return false;
  if (components != 1)
    in().fail("point array '" + name + "' has " + std::to_string(components) +
              " components; a material needs 1");
  if (tuples != tuples_)
    in().fail("point array '" + name + "' has " + std::to_string(tuples) + " values for " +
              std::to_string(tuples_) + " points");
  return true;
}

// Reads the values of an array into the material when it is the one wanted, else skips them.
void VtkReader::array_values(bool material, std::uint64_t count, const VtkType& type,
                             const std::string& what, TetMesh& mesh) {
  if (!material) {
    skip_values(count, type, what);
    return;
  }
  auto sink = [&](std::uint64_t i, Value v) {
    if (i == 0) mesh.material.reserve(count);
    if (!std::isfinite(v.real))
      fail_value("material value " + std::to_string(i) + " is not a finite number");
    mesh.material.push_back(v.real);
  };
  values(count, type, what, &sink);
  have_material_ = true;
}

// a × b, or the largest count when it overflows (which no file can hold, so the count checks
// refuse it).
std::uint64_t times(std::uint64_t a, std::uint64_t b) {
  return b != 0 && a > UINT64_MAX / b ? UINT64_MAX : a * b;
}

// SCALARS name type [components], an optional LOOKUP_TABLE name, the values.
void VtkReader::scalars(TetMesh& mesh) {
  const std::string name(in().required_token("the array name"));
  const VtkType& type = type_arg();
  const std::uint64_t components = in().at_line_end() ? 1 : count_arg("the component count");
  if (components == 0) in().fail("SCALARS '" + name + "' has 0 components");
  const bool material = wants_material(name, components, tuples_);
  const Mark after_line = mark();
  if (lower_ascii(in().token_any_line()) == "lookup_table")
    in().required_token("the lookup table name");
  else
    restore(after_line);
  array_values(material, times(tuples_, components), type, "SCALARS '" + name + "'", mesh);
}

// FIELD name arrays, then per array: name components tuples type, the values.
void VtkReader::field(TetMesh& mesh) {
  in().required_token("the field name");
  const std::uint64_t arrays = count_arg("the array count");
  if (arrays > in().remaining()) in().fail("FIELD declares more arrays than the file can hold");
  for (std::uint64_t a = 0; a < arrays; ++a) {
    skip_metadata_if_next();
    const std::string name(need("a FIELD array"));
    if (name == "NULL_ARRAY") continue;
    const std::uint64_t components = count_arg("the component count");
    const std::uint64_t tuples = count_arg("the tuple count");
    const VtkType& type = type_arg();
    const bool material = wants_material(name, components, tuples);
    array_values(material, times(components, tuples), type, "FIELD array '" + name + "'", mesh);
  }
}

void VtkReader::attribute(std::string_view word, const std::string& key, TetMesh& mesh) {
  if (key == "field") {
    field(mesh);
    return;
  }
  if (!point_data_) in().fail(std::string(word) + " before POINT_DATA or CELL_DATA");
  if (key == "scalars") {
    scalars(mesh);
    return;
  }
  const std::string name(in().required_token("the array name"));
  const std::string what = std::string(word) + " '" + name + "'";
  if (key == "color_scalars" || key == "lookup_table") {
    const std::uint64_t per = key == "color_scalars" ? count_arg("the value count") : 4;
    const std::uint64_t rows = key == "color_scalars" ? tuples_ : count_arg("the table size");
    skip_values(times(rows, per), binary_ ? kUChar : kFloat, what);
    return;
  }
  std::uint64_t components = 1;
  if (key == "vectors" || key == "normals") components = 3;
  if (key == "tensors") components = 9;
  if (key == "tensors6") components = 6;
  if (key == "texture_coordinates") {
    components = count_arg("the dimension");
    if (components == 0) in().fail(what + " has dimension 0");
  }
  const VtkType& type = type_arg();
  // VECTORS, NORMALS, ids ...: the material only when named.
  const bool material = wants_material(name, components, tuples_, false);
  array_values(material, times(tuples_, components), type, what, mesh);
}

bool is_attribute(const std::string& key) {
  static constexpr std::string_view kKeys[] = {
      "scalars",  "color_scalars",       "lookup_table", "vectors",      "normals", "tensors",
      "tensors6", "texture_coordinates", "global_ids",   "pedigree_ids", "field"};
  return std::find(std::begin(kKeys), std::end(kKeys), key) != std::end(kKeys);
}

// POINT_DATA n or CELL_DATA n: the attributes that follow have n tuples.
void VtkReader::data_section(bool point, TetMesh& mesh) {
  const std::uint64_t n = count_arg("the tuple count");
  if (point) {
    if (!have_points_) in().fail("POINT_DATA before POINTS");
    if (point_data_line_ != 0) in().fail("a second POINT_DATA section");
    if (n != mesh.points.size())
      in().fail("POINT_DATA declares " + std::to_string(n) + " values per array but there are " +
                std::to_string(mesh.points.size()) + " points");
    point_data_line_ = in().line();
  } else {
    if (!cells_) in().fail("CELL_DATA before CELLS");
    if (n != cell_count_)
      in().fail("CELL_DATA declares " + std::to_string(n) + " values per array but there are " +
                std::to_string(cell_count_) + " cells");
  }
  point_data_ = point;
  tuples_ = n;
}

void VtkReader::finish(TetMesh& mesh) {
  if (!have_points_) in().fail("no POINTS section");
  if (cells_ && !cells_->types) fail_at_line(source_, cells_->line, "CELLS without CELL_TYPES");
  if (!material_name_.empty() && !have_material_) {
    std::string names;
    for (const std::string& n : point_arrays_) names += (names.empty() ? "'" : ", '") + n + "'";
    fail_at_line(source_, point_data_line_ != 0 ? point_data_line_ : in().line(),
                 "no point array named '" + material_name_ + "' (" +
                     (names.empty() ? "the file has no point arrays" : "point arrays: " + names) +
                     ")");
  }
  if (!cells_) return;  // no tets: parse_tet_mesh says so
  const Cells& cells = *cells_;
  std::map<std::int64_t, std::uint64_t> others;
  for (std::uint64_t i = 0; i < cell_count_; ++i) {
    const std::int64_t type = (*cells.types)[i];
    const std::uint64_t begin = cells.offsets[i], size = cells.offsets[i + 1] - begin;
    if (type != kTetra && type != kQuadraticTetra) {
      ++others[type];
      continue;
    }
    const std::uint64_t expected = type == kTetra ? 4 : 10;
    if (size != expected)
      fail_at_line(source_, cells.line,
                   "cell " + std::to_string(i) + " is of type " + std::to_string(type) +
                       " but has " + std::to_string(size) + " points, not " +
                       std::to_string(expected));
    Tet t{};
    for (std::size_t k = 0; k < 4; ++k) {
      const std::int64_t v = cells.connectivity[begin + k];
      if (static_cast<std::uint64_t>(v) >= mesh.points.size())
        fail_at_line(source_, cells.line,
                     "cell " + std::to_string(i) + " refers to point " + std::to_string(v) +
                         " but there are " + std::to_string(mesh.points.size()) + " points");
      t[k] = static_cast<std::uint32_t>(v);
    }
    mesh.tets.push_back(t);
  }
  if (mesh.tets.empty() && !others.empty()) {
    std::string list;
    for (const auto& [type, count] : others)
      list += (list.empty() ? "" : ", ") + std::to_string(count) + " of type " +
              std::to_string(type) + " (" + cell_type_name(type) + ")";
    throw InputError(source_ + " has no tetrahedra (VTK cell type 10); its cells are " + list);
  }
}

void VtkReader::read(TetMesh& mesh) {
  header();
  const std::string_view first = need("DATASET");
  if (lower_ascii(first) != "dataset")
    in().fail("expected DATASET, found '" + std::string(first) + "'");
  const std::string_view kind = in().required_token("the dataset type");
  if (lower_ascii(kind) != "unstructured_grid")
    in().fail("DATASET " + std::string(kind) +
              " is not supported: tetrahedra come in an UNSTRUCTURED_GRID");
  while (true) {
    const std::string_view word = in().token_any_line();
    if (word.empty()) break;
    const std::string key = lower_ascii(word);
    if (key == "points") {
      points(mesh);
    } else if (key == "cells") {
      cells();
    } else if (key == "cell_types") {
      cell_types();
    } else if (key == "point_data" || key == "cell_data") {
      data_section(key == "point_data", mesh);
    } else if (key == "metadata") {
      skip_metadata();
    } else if (is_attribute(key)) {
      attribute(word, key, mesh);
    } else {
      in().fail("unknown VTK keyword '" + std::string(word) + "'");
    }
  }
  finish(mesh);
}

}  // namespace

void read_vtk_tets(std::string_view data, const std::string& source,
                   const std::string& material_name, TetMesh& mesh) {
  VtkReader(data, source, material_name).read(mesh);
}

}  // namespace tpmsfill::io
