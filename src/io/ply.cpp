// PLY: ascii, binary_little_endian and binary_big_endian; any element order, any extra
// elements and properties. Every count is checked against the bytes left before anything is
// allocated for it.
#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstring>
#include <optional>
#include <vector>

#include "io/formats.hpp"
#include "io/text_scanner.hpp"

namespace tpmsfill::io {
namespace {

enum class Scalar { Int8, UInt8, Int16, UInt16, Int32, UInt32, Float32, Float64 };

std::optional<Scalar> scalar_from_name(std::string_view name) {
  struct Entry {
    std::string_view name;
    Scalar type;
  };
  static constexpr std::array<Entry, 16> kNames{{
      {"char", Scalar::Int8},
      {"int8", Scalar::Int8},
      {"uchar", Scalar::UInt8},
      {"uint8", Scalar::UInt8},
      {"short", Scalar::Int16},
      {"int16", Scalar::Int16},
      {"ushort", Scalar::UInt16},
      {"uint16", Scalar::UInt16},
      {"int", Scalar::Int32},
      {"int32", Scalar::Int32},
      {"uint", Scalar::UInt32},
      {"uint32", Scalar::UInt32},
      {"float", Scalar::Float32},
      {"float32", Scalar::Float32},
      {"double", Scalar::Float64},
      {"float64", Scalar::Float64},
  }};
  for (const Entry& e : kNames)
    if (e.name == name) return e.type;
  return std::nullopt;
}

std::uint64_t size_of(Scalar s) {
  switch (s) {
    case Scalar::Int8:
    case Scalar::UInt8:
      return 1;
    case Scalar::Int16:
    case Scalar::UInt16:
      return 2;
    case Scalar::Int32:
    case Scalar::UInt32:
    case Scalar::Float32:
      return 4;
    case Scalar::Float64:
      return 8;
  }
  return 8;
}

bool is_float(Scalar s) {
  return s == Scalar::Float32 || s == Scalar::Float64;
}

struct Property {
  std::string name;
  bool list = false;
  Scalar count_type = Scalar::UInt8;  // lists only
  Scalar type = Scalar::Float32;      // the value, or a list's items
};

struct Element {
  std::string name;
  std::uint64_t count = 0;
  std::uint64_t line = 0;  // of its "element" header line, for errors about the count
  std::vector<Property> properties;
};

enum class Encoding { Ascii, BinaryLittle, BinaryBig };

struct Header {
  Encoding encoding = Encoding::Ascii;
  std::vector<Element> elements;
  std::uint64_t data_offset = 0;  // first byte after the end_header line
  std::uint64_t end_line = 0;     // line number of end_header
};

Header read_header(std::string_view data, const std::string& source, MeshFile& mesh) {
  TextScanner in(data, source);
  Header header;
  if (in.token() != "ply") in.fail("PLY file does not start with 'ply'");
  in.next_line();
  bool have_format = false;
  while (true) {
    if (in.at_end()) in.fail("PLY header has no 'end_header'");
    const std::string_view word = in.token();
    if (word == "format") {
      const std::string_view enc = in.required_token("format");
      if (enc == "ascii")
        header.encoding = Encoding::Ascii;
      else if (enc == "binary_little_endian")
        header.encoding = Encoding::BinaryLittle;
      else if (enc == "binary_big_endian")
        header.encoding = Encoding::BinaryBig;
      else
        in.fail("unknown PLY format '" + std::string(enc) + "'");
      have_format = true;
    } else if (word == "element") {
      Element e;
      e.name = in.required_token("element name");
      e.count = in.non_negative(in.required_token("element count"), "element count");
      e.line = in.line();
      header.elements.push_back(std::move(e));
    } else if (word == "property") {
      if (header.elements.empty()) in.fail("'property' before any 'element'");
      Property p;
      std::string_view type = in.required_token("property type");
      if (type == "list") {
        p.list = true;
        const std::string_view count_type = in.required_token("list count type");
        const auto ct = scalar_from_name(count_type);
        if (!ct || is_float(*ct))
          in.fail("list count type '" + std::string(count_type) + "' is not an integer type");
        p.count_type = *ct;
        type = in.required_token("list item type");
      }
      const auto t = scalar_from_name(type);
      if (!t) in.fail("unknown property type '" + std::string(type) + "'");
      p.type = *t;
      p.name = in.required_token("property name");
      header.elements.back().properties.push_back(std::move(p));
    } else if (word == "end_header") {
      header.end_line = in.line();
      in.next_line();
      break;
    } else if (word != "comment" && word != "obj_info" && !word.empty()) {
      // Some exporters (old Blender) write free text into the header; it carries no layout.
      mesh.warnings.push_back("PLY header line " + std::to_string(in.line()) +
                              " is not a PLY keyword; ignored it");
    }
    in.next_line();
  }
  if (!have_format) in.fail("PLY header has no 'format' line");
  header.data_offset = static_cast<std::uint64_t>(in.position() - data.data());
  return header;
}

// The parts of the header the soup needs: where x, y, z and the face indices are.
struct Layout {
  std::optional<std::size_t> vertex, face;  // element indices
  std::array<std::size_t, 3> xyz{};         // property indices in the vertex element
  std::size_t indices = 0;                  // property index in the face element
};

Layout find_layout(const Header& header, const std::string& source) {
  Layout layout;
  for (std::size_t e = 0; e < header.elements.size(); ++e) {
    const Element& element = header.elements[e];
    if (element.name == "vertex" && !layout.vertex) {
      layout.vertex = e;
      for (std::size_t axis = 0; axis < 3; ++axis) {
        const std::string_view name = std::array{"x", "y", "z"}[axis];
        std::size_t p = 0;
        while (p < element.properties.size() &&
               (element.properties[p].name != name || element.properties[p].list))
          ++p;
        if (p == element.properties.size())
          fail_at_line(source, element.line,
                       "PLY vertex element has no scalar '" + std::string(name) + "' property");
        layout.xyz[axis] = p;
      }
    } else if (element.name == "face" && !layout.face) {
      std::size_t p = 0;
      while (p < element.properties.size() &&
             !(element.properties[p].list && (element.properties[p].name == "vertex_indices" ||
                                              element.properties[p].name == "vertex_index")))
        ++p;
      if (p == element.properties.size())
        fail_at_line(source, element.line,
                     "PLY face element has no list property 'vertex_indices'");
      layout.face = e;
      layout.indices = p;
    }
  }
  return layout;
}

// Refuses counts the bytes after the header cannot hold, before anything is allocated: binary
// elements need at least their fixed-size part each, ascii ones at least one character and one
// separator per property.
void check_counts(const Header& header, std::uint64_t available, const std::string& source) {
  std::uint64_t needed = 0;
  for (const Element& e : header.elements) {
    std::uint64_t per = 0;
    for (const Property& p : e.properties)
      per += header.encoding == Encoding::Ascii ? 2 : size_of(p.list ? p.count_type : p.type);
    if (per == 0) continue;
    if (e.count > (available + 1) / per || needed + e.count * per > available + 1)
      fail_at_line(source, e.line,
                   "PLY header declares " + std::to_string(e.count) + " '" + e.name +
                       "' elements but only " + std::to_string(available) +
                       " bytes of data follow the header");
    needed += e.count * per;
  }
}

// Where values come from: a cursor over binary data of one endianness, or ascii tokens.
class ValueReader {
 public:
  ValueReader(std::string_view data, const Header& header, const std::string& source)
      : data_(data),
        pos_(header.data_offset),
        encoding_(header.encoding),
        text_(data.substr(header.data_offset), source, {}, header.end_line + 1),
        source_(source) {}

  // A value of the given type; `what` names it in errors.
  double value(Scalar type, std::string_view what) {
    if (encoding_ == Encoding::Ascii) {
      const std::string_view t = text_.token_any_line();
      if (t.empty()) fail("data ends early, expected " + std::string(what));
      if (is_float(type)) return text_.number(t, what);
      return static_cast<double>(text_.integer(t, what));
    }
    const std::uint64_t n = size_of(type);
    if (data_.size() - pos_ < n) fail("data ends early, expected " + std::string(what));
    std::array<unsigned char, 8> b{};
    std::memcpy(b.data(), data_.data() + pos_, n);
    if ((encoding_ == Encoding::BinaryBig) != (std::endian::native == std::endian::big))
      std::reverse(b.begin(), b.begin() + static_cast<std::ptrdiff_t>(n));
    last_ = pos_;
    pos_ += n;
    switch (type) {
      case Scalar::Int8:
        return std::bit_cast<std::int8_t>(b[0]);
      case Scalar::UInt8:
        return b[0];
      case Scalar::Int16:
        return load<std::int16_t>(b);
      case Scalar::UInt16:
        return load<std::uint16_t>(b);
      case Scalar::Int32:
        return load<std::int32_t>(b);
      case Scalar::UInt32:
        return load<std::uint32_t>(b);
      case Scalar::Float32:
        return load<float>(b);
      case Scalar::Float64:
        return load<double>(b);
    }
    return 0;
  }

  // A value we do not use: binary skips its bytes, ascii its token.
  void skip(Scalar type, std::string_view what) {
    if (encoding_ != Encoding::Ascii) {
      if (data_.size() - pos_ < size_of(type))
        fail("data ends early, expected " + std::string(what));
      pos_ += size_of(type);
    } else if (text_.token_any_line().empty()) {
      fail("data ends early, expected " + std::string(what));
    }
  }

  // A list's length, checked against what is left so a bad one cannot make us loop for long.
  std::uint64_t list_count(const Property& p) {
    const double c = value(p.count_type, "list length of '" + p.name + "'");
    if (c < 0) fail("list '" + p.name + "' has negative length");
    const auto n = static_cast<std::uint64_t>(c);
    const std::uint64_t item = encoding_ == Encoding::Ascii ? 2 : size_of(p.type);
    if (n > (remaining() + 1) / item)
      fail("list '" + p.name + "' of length " + std::to_string(n) +
           " runs past the end of the data");
    return n;
  }

  [[noreturn]] void fail(const std::string& reason) const {
    if (encoding_ == Encoding::Ascii) text_.fail(reason);
    fail_at_byte(source_, last_, reason);
  }

 private:
  template <typename T>
  static double load(const std::array<unsigned char, 8>& b) {
    T v;
    std::memcpy(&v, b.data(), sizeof v);
    return static_cast<double>(v);
  }
  std::uint64_t remaining() const {
    return encoding_ == Encoding::Ascii ? text_.remaining() : data_.size() - pos_;
  }

  std::string_view data_;
  std::uint64_t pos_;
  std::uint64_t last_ = 0;  // offset of the last binary value read, for errors
  Encoding encoding_;
  TextScanner text_;
  const std::string& source_;
};

}  // namespace

void read_ply(std::string_view data, const std::string& source, MeshFile& mesh) {
  const Header header = read_header(data, source, mesh);
  check_counts(header, data.size() - header.data_offset, source);
  const Layout layout = find_layout(header, source);
  const std::uint64_t vertex_count = layout.vertex ? header.elements[*layout.vertex].count : 0;
  if (!detail::fits_32bit_ids(vertex_count)) throw InputError(source + " has too many vertices");
  mesh.soup.points.resize(vertex_count);

  // Faces may come before the vertices: keep their indices and triangulate at the end.
  std::vector<std::uint32_t> corners, sizes;
  ValueReader in(data, header, source);
  for (std::size_t e = 0; e < header.elements.size(); ++e) {
    const Element& element = header.elements[e];
    if (element.properties.empty()) continue;
    const bool is_vertex = layout.vertex == e, is_face = layout.face == e;
    for (std::uint64_t i = 0; i < element.count; ++i) {
      for (std::size_t p = 0; p < element.properties.size(); ++p) {
        const Property& prop = element.properties[p];
        if (prop.list) {
          const std::uint64_t n = in.list_count(prop);
          if (is_face && p == layout.indices) {
            if (n < 3)
              in.fail("face " + std::to_string(i) + " has " + std::to_string(n) +
                      " vertices (needs at least 3)");
            for (std::uint64_t k = 0; k < n; ++k) {
              const double v = in.value(prop.type, "face vertex index");
              if (!(v >= 0 && v < static_cast<double>(vertex_count)) || v != std::floor(v))
                in.fail("face " + std::to_string(i) + " has vertex index " + std::to_string(v) +
                        " out of range (" + std::to_string(vertex_count) + " vertices)");
              corners.push_back(static_cast<std::uint32_t>(v));
            }
            sizes.push_back(static_cast<std::uint32_t>(n));
          } else {
            for (std::uint64_t k = 0; k < n; ++k) in.skip(prop.type, prop.name);
          }
        } else if (is_vertex && (p == layout.xyz[0] || p == layout.xyz[1] || p == layout.xyz[2])) {
          const double v = in.value(prop.type, prop.name + " coordinate");
          if (!std::isfinite(v))
            in.fail("vertex " + std::to_string(i) + " has a non-finite " + prop.name);
          Vec3& point = mesh.soup.points[i];
          (p == layout.xyz[0] ? point.x : p == layout.xyz[1] ? point.y : point.z) = v;
        } else {
          in.skip(prop.type, prop.name);
        }
      }
    }
  }

  std::size_t at = 0;
  for (const std::uint32_t n : sizes) {
    add_face(mesh, std::span(corners).subspan(at, n));
    at += n;
  }
  mesh.format = MeshFormat::Ply;
}

}  // namespace tpmsfill::io
