// Volume files: the seed's text and binary forms, NRRD, MetaImage and INR (docs/formats.md,
// "Field files"). Headers are parsed line by line; data is decoded by one function for all
// formats, after its size was checked against the bytes present.
// GCC 12 at -O3 warns falsely (-Wrestrict, GCC bug 105651) on `"literal" + std::string`.
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC diagnostic ignored "-Wrestrict"
#endif
#include "tpmsfill/io/volume.hpp"

#include <algorithm>
#include <bit>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <map>
#include <optional>
#include <sstream>

#include "core/names.hpp"
#include "io/file_bytes.hpp"
#include "io/inflate.hpp"
#include "io/parse_errors.hpp"
#include "io/vdb.hpp"
#include "tpmsfill/error.hpp"
#include "tpmsfill/io.hpp"

namespace tpmsfill {
namespace {

using detail::fail_at_byte;
using detail::fail_at_line;

constexpr std::string_view kBinaryMagic = "TDFB";
constexpr std::string_view kTextMagic = "tpmsfill-field";
constexpr int kMaxDim = 1 << 20;

// An element type as stored: size in bytes, integer or not, signed or not.
struct Element {
  std::string name;  // "uint8", "int16", "float32", ...
  int size = 0;
  bool is_float = false, is_signed = false;
};

std::optional<Element> element_named(std::string_view n) {
  static const std::map<std::string, Element, std::less<>> table = {
      {"uint8", {"uint8", 1, false, false}},   {"int8", {"int8", 1, false, true}},
      {"uint16", {"uint16", 2, false, false}}, {"int16", {"int16", 2, false, true}},
      {"uint32", {"uint32", 4, false, false}}, {"int32", {"int32", 4, false, true}},
      {"uint64", {"uint64", 8, false, false}}, {"int64", {"int64", 8, false, true}},
      {"float32", {"float32", 4, true, true}}, {"float64", {"float64", 8, true, true}}};
  const auto it = table.find(n);
  return it == table.end() ? std::nullopt : std::optional<Element>(it->second);
}

// Decodes count values at `data` (checked to hold exactly or at least that many bytes).
std::vector<double> decode(std::string_view data, std::uint64_t count, const Element& e,
                           bool big_endian, const std::string& source, std::uint64_t base) {
  const std::uint64_t need = count * std::uint64_t(e.size);
  if (data.size() < need)
    fail_at_byte(source, base + data.size(),
                 "the data ends after " + std::to_string(data.size()) + " of " +
                     std::to_string(need) + " bytes (" + std::to_string(count) + " " + e.name +
                     " values)");
  std::vector<double> out(count);
  const bool swap = big_endian != (std::endian::native == std::endian::big);
  for (std::uint64_t n = 0; n < count; ++n) {
    unsigned char b[8];
    std::memcpy(b, data.data() + n * e.size, e.size);
    if (swap) std::reverse(b, b + e.size);
    double v = 0;
    if (e.is_float) {
      if (e.size == 4) {
        float f;
        std::memcpy(&f, b, 4);
        v = f;
      } else {
        std::memcpy(&v, b, 8);
      }
      if (!std::isfinite(v))
        fail_at_byte(source, base + n * e.size, "value " + std::to_string(n) + " is not finite");
    } else {
      std::uint64_t u = 0;
      std::memcpy(&u, b, e.size);  // little-endian host
      if (e.is_signed && e.size < 8 && (u >> (8 * e.size - 1)) & 1) u |= ~0ull << (8 * e.size);
      v = e.is_signed ? static_cast<double>(static_cast<std::int64_t>(u)) : static_cast<double>(u);
    }
    out[n] = v;
  }
  return out;
}

// Dimensions from text, each 1 .. kMaxDim, with the product checked against what a file of
// `available` bytes (or text) can hold before anything is allocated.
std::uint64_t checked_count(const std::array<int, 3>& d) {
  return std::uint64_t(d[0]) * std::uint64_t(d[1]) * std::uint64_t(d[2]);
}

int parse_dim(std::string_view word, const std::string& source, std::uint64_t line) {
  int v = 0;
  const auto [end, ec] = std::from_chars(word.data(), word.data() + word.size(), v);
  if (ec != std::errc() || end != word.data() + word.size() || v < 1 || v > kMaxDim)
    fail_at_line(source, line,
                 "'" + std::string(word) + "' is not a dimension (a whole number 1 to " +
                     std::to_string(kMaxDim) + ")");
  return v;
}

// A finite decimal number (from_chars: no hex, no locale; a leading '+' is accepted).
double parse_number(std::string_view word, const std::string& source, std::uint64_t line) {
  std::string_view t = word;
  if (t.size() > 1 && t[0] == '+' && t[1] != '-' && t[1] != '+') t.remove_prefix(1);
  double v = 0;
  const auto [end, ec] = std::from_chars(t.data(), t.data() + t.size(), v);
  if (ec == std::errc::result_out_of_range)
    fail_at_line(source, line, "'" + std::string(word) + "' is out of range for a double");
  if (t.empty() || ec != std::errc() || end != t.data() + t.size())
    fail_at_line(source, line, "'" + std::string(word) + "' is not a number");
  if (!std::isfinite(v))
    fail_at_line(source, line, "'" + std::string(word) + "' is not a finite number");
  return v;
}

std::vector<std::string_view> words(std::string_view line) {
  std::vector<std::string_view> out;
  std::size_t i = 0;
  while (i < line.size()) {
    while (i < line.size() && std::isspace(static_cast<unsigned char>(line[i]))) ++i;
    const std::size_t start = i;
    while (i < line.size() && !std::isspace(static_cast<unsigned char>(line[i]))) ++i;
    if (i > start) out.push_back(line.substr(start, i - start));
  }
  return out;
}

// Lines of a header: the text before the data, each with its number and end offset.
struct Line {
  std::string_view text;
  std::uint64_t number = 0, end = 0;  // end: offset just past its newline
};

std::optional<Line> next_line(std::string_view data, std::uint64_t& at, std::uint64_t& number) {
  if (at >= data.size()) return std::nullopt;
  const std::size_t eol = data.find('\n', at);
  Line l;
  l.number = ++number;
  l.end = eol == std::string_view::npos ? data.size() : eol + 1;
  l.text = data.substr(at, l.end - at);
  while (!l.text.empty() && (l.text.back() == '\n' || l.text.back() == '\r'))
    l.text.remove_suffix(1);
  at = l.end;
  return l;
}

ScalarVolume unit_volume(std::array<int, 3> dims) {
  ScalarVolume v;
  v.dims = dims;
  return v;
}

// The seed's forms place the box at the origin: the first cell's centre half a cell in.
Vec3 default_origin(const std::array<double, 3>& spacing) {
  return {0.5 * spacing[0], 0.5 * spacing[1], 0.5 * spacing[2]};
}

void set_size(ScalarVolume& v, const std::array<double, 3>& size) {
  for (int a = 0; a < 3; ++a) v.spacing[a] = size[a] / v.dims[a];
  v.origin = default_origin(v.spacing);
}

// Whether the seed's forms need an "origin" to say where `v` sits (a field from a CT or a mesh
// keeps its place; one the seed's way sits at the origin).
bool placed(const ScalarVolume& v) {
  return v.has_physical_size() && !(v.origin == default_origin(v.spacing));
}

// ---- the seed's forms ---------------------------------------------------------------------

VolumeFile parse_field_text(std::string_view data, const std::string& source) {
  VolumeFile f;
  f.format = VolumeFormat::FieldText;
  f.element_type = "text";
  std::uint64_t at = 0, number = 0;
  std::optional<std::array<int, 3>> dims;
  std::optional<std::array<double, 3>> size;
  std::optional<Vec3> origin;
  std::uint64_t origin_line = 0;
  std::vector<double>& values = f.volume.values;
  std::uint64_t expected = 0, last_line = 0;
  while (const std::optional<Line> line = next_line(data, at, number)) {
    last_line = line->number;
    std::string_view text = line->text;
    if (const std::size_t hash = text.find('#'); hash != std::string_view::npos)
      text = text.substr(0, hash);
    const std::vector<std::string_view> w = words(text);
    if (w.empty()) continue;
    std::size_t from = 0;  // the first word that is a value
    if (!dims) {
      from = w.size();
      if (w[0] == kTextMagic) {
        if (w.size() != 2 || w[1] != "1")
          fail_at_line(source, line->number, "this tpmsfill reads tpmsfill-field version 1");
      } else if (w[0] == "size") {
        if (w.size() != 4) fail_at_line(source, line->number, "'size' takes three lengths in mm");
        size = std::array<double, 3>{};
        for (int a = 0; a < 3; ++a) {
          (*size)[a] = parse_number(w[a + 1], source, line->number);
          if (!((*size)[a] > 0) || !std::isfinite((*size)[a]))
            fail_at_line(source, line->number, "a size must be a positive length in mm");
        }
      } else if (w[0] == "origin") {
        if (w.size() != 4)
          fail_at_line(source, line->number, "'origin' takes the first cell's centre, x y z in mm");
        double o[3];
        for (int a = 0; a < 3; ++a) {
          o[a] = parse_number(w[a + 1], source, line->number);
          if (!std::isfinite(o[a])) fail_at_line(source, line->number, "an origin must be finite");
        }
        origin = Vec3{o[0], o[1], o[2]};
        origin_line = line->number;
      } else if (w[0] == "sign") {
        if (w.size() != 2) fail_at_line(source, line->number, "'sign' takes one word");
        try {
          f.volume.sign = field_sign_from_name(w[1]);
        } catch (const InputError& e) {
          fail_at_line(source, line->number, e.what());
        }
      } else {
        if (w.size() < 3)
          fail_at_line(source, line->number, "expected the counts 'w h d' (or size/sign lines)");
        dims = std::array<int, 3>{parse_dim(w[0], source, line->number),
                                  parse_dim(w[1], source, line->number),
                                  parse_dim(w[2], source, line->number)};
        expected = checked_count(*dims);
        // Each value needs at least two characters ("0 "): refuse counts the text cannot hold
        // (values may follow the counts on their line).
        const auto rest =
            static_cast<std::uint64_t>(data.data() + data.size() - (w[2].data() + w[2].size()));
        if (expected > rest / 2 + 1)
          fail_at_line(source, line->number,
                       std::to_string(expected) + " values declared, more than the file holds");
        values.reserve(expected);
        from = 3;
      }
    }
    for (std::size_t i = from; dims && i < w.size(); ++i) {
      if (values.size() == expected)
        fail_at_line(source, line->number,
                     "more values than the " + std::to_string(expected) + " the counts declare");
      values.push_back(parse_number(w[i], source, line->number));
    }
  }
  if (!dims) fail_at_line(source, std::max<std::uint64_t>(last_line, 1), "no counts 'w h d' found");
  if (values.size() != expected)
    fail_at_line(source, std::max<std::uint64_t>(last_line, 1),
                 "the file ends after " + std::to_string(values.size()) + " of " +
                     std::to_string(expected) + " values");
  const FieldSign sign = f.volume.sign;
  std::vector<double> v = std::move(values);
  f.volume = unit_volume(*dims);
  f.volume.values = std::move(v);
  f.volume.sign = sign;
  if (size) set_size(f.volume, *size);
  if (origin) {
    if (!size)
      fail_at_line(source, origin_line, "'origin' needs a 'size' (a unitless field has none)");
    f.volume.origin = *origin;
  }
  return f;
}

// The binary form's header. Version 1: magic, version, type, sign, counts, size; version 2
// adds the origin.
constexpr std::size_t kHeader1 = 4 + 2 + 1 + 1 + 12 + 24;
constexpr std::size_t kHeader2 = kHeader1 + 24;

VolumeFile parse_field_binary(std::string_view data, const std::string& source) {
  if (data.size() < kHeader1) fail_at_byte(source, data.size(), "the header is cut short");
  auto u16 = [&](std::size_t at) {
    std::uint16_t x;
    std::memcpy(&x, data.data() + at, 2);
    return x;
  };
  auto u32 = [&](std::size_t at) {
    std::uint32_t x;
    std::memcpy(&x, data.data() + at, 4);
    return x;
  };
  const std::uint16_t version = u16(4);
  if (version != 1 && version != 2)
    fail_at_byte(source, 4, "this tpmsfill reads TDFB versions 1 and 2");
  const std::size_t kHeader = version == 2 ? kHeader2 : kHeader1;
  if (data.size() < kHeader) fail_at_byte(source, data.size(), "the header is cut short");
  const auto type = static_cast<unsigned char>(data[6]), sign = static_cast<unsigned char>(data[7]);
  if (type > 1) fail_at_byte(source, 6, "unknown value type " + std::to_string(type));
  if (sign > 2) fail_at_byte(source, 7, "unknown sign " + std::to_string(sign));
  std::array<int, 3> dims{};
  for (int a = 0; a < 3; ++a) {
    const std::uint32_t d = u32(8 + 4 * a);
    if (d < 1 || d > kMaxDim)
      fail_at_byte(source, 8 + 4 * a, "dimension " + std::to_string(d) + " is out of range");
    dims[a] = static_cast<int>(d);
  }
  std::array<double, 3> size{};
  std::memcpy(size.data(), data.data() + 20, 24);
  for (int a = 0; a < 3; ++a)
    if (!(size[a] >= 0) || !std::isfinite(size[a]))
      fail_at_byte(source, 20 + 8 * a, "a size must be >= 0 and finite");
  const Element e = *element_named(type == 0 ? "float32" : "float64");
  const std::uint64_t count = checked_count(dims);
  if (count * e.size != data.size() - kHeader)
    fail_at_byte(source, kHeader,
                 std::to_string(data.size() - kHeader) + " bytes of values where the counts need " +
                     std::to_string(count * e.size));
  VolumeFile f;
  f.format = VolumeFormat::FieldBinary;
  f.element_type = e.name;
  f.volume = unit_volume(dims);
  f.volume.values = decode(data.substr(kHeader), count, e, false, source, kHeader);
  f.volume.sign = sign == 0   ? FieldSign::Unknown
                  : sign == 1 ? FieldSign::Signed
                              : FieldSign::Unsigned;
  if (size[0] > 0 || size[1] > 0 || size[2] > 0) {
    if (!(size[0] > 0 && size[1] > 0 && size[2] > 0))
      fail_at_byte(source, 20, "the size must be given on all three axes or none");
    set_size(f.volume, size);
  }
  if (version == 2) {
    if (!f.volume.has_physical_size())
      fail_at_byte(source, kHeader1, "an origin needs a size (a unitless field has none)");
    double o[3];
    std::memcpy(o, data.data() + kHeader1, 24);
    for (int a = 0; a < 3; ++a)
      if (!std::isfinite(o[a])) fail_at_byte(source, kHeader1 + 8 * a, "an origin must be finite");
    f.volume.origin = {o[0], o[1], o[2]};
  }
  return f;
}

// ---- NRRD and MetaImage: "key: value" / "key = value" headers ----------------------------

struct Header {
  std::map<std::string, std::pair<std::string, std::uint64_t>> fields;  // value, line
  std::uint64_t data_offset = 0;
  std::uint64_t data_line = 1;  // the line the data starts on (for ascii data)
  const std::string* source = nullptr;

  const std::string* get(const std::string& key) const {
    const auto it = fields.find(key);
    return it == fields.end() ? nullptr : &it->second.first;
  }
  std::uint64_t line(const std::string& key) const {
    const auto it = fields.find(key);
    return it == fields.end() ? 1 : it->second.second;
  }
  [[noreturn]] void fail(const std::string& key, const std::string& why) const {
    fail_at_line(*source, line(key), why);
  }
  std::vector<double> numbers(const std::string& key, std::size_t n) const {
    std::vector<double> out;
    std::string text = *get(key);
    for (char& c : text)
      if (c == '(' || c == ')' || c == ',') c = ' ';
    for (std::string_view w : words(text)) out.push_back(parse_number(w, *source, line(key)));
    if (out.size() != n)
      fail(key, "'" + key + "' needs " + std::to_string(n) + " numbers, not " +
                    std::to_string(out.size()));
    for (double x : out)
      if (!std::isfinite(x)) fail(key, "'" + key + "' holds a value that is not finite");
    return out;
  }
};

std::string lower(std::string s) {
  for (char& c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return s;
}

std::string trim(std::string_view s) {
  while (!s.empty() && std::isspace(static_cast<unsigned char>(s.front()))) s.remove_prefix(1);
  while (!s.empty() && std::isspace(static_cast<unsigned char>(s.back()))) s.remove_suffix(1);
  return std::string(s);
}

std::array<int, 3> header_dims(const Header& h, const std::string& key) {
  if (!h.get(key)) h.fail(key, "the header has no '" + key + "'");
  const std::vector<std::string_view> w = words(*h.get(key));
  if (w.size() != 3)
    h.fail(key, "'" + key + "' gives " + std::to_string(w.size()) +
                    " sizes; a field is a 3D grid (3 sizes)");
  return {parse_dim(w[0], *h.source, h.line(key)), parse_dim(w[1], *h.source, h.line(key)),
          parse_dim(w[2], *h.source, h.line(key))};
}

// Where a header's data is: the bytes, and what errors in them name (the file, the byte
// offset of bytes[0] in it, the line bytes[0] is on).
struct DataRef {
  std::string_view bytes;
  std::string source;
  std::uint64_t base = 0, first_line = 1;
};

// The data of a header: attached after it, or in a file beside it (read into `storage`).
DataRef header_data(std::string_view data, const Header& h, const std::string& file_key,
                    const std::filesystem::path* folder, std::string& storage,
                    std::uint64_t max_bytes) {
  const std::string* file = h.get(file_key);
  if (!file || lower(*file) == "local")
    return {data.substr(h.data_offset), *h.source, h.data_offset, h.data_line};
  if (!folder)
    h.fail(file_key,
           "the data is in another file ('" + *file + "'), which cannot be followed here");
  if (file->find('%') != std::string::npos || lower(*file) == "list" || file->rfind("LIST", 0) == 0)
    h.fail(file_key, "lists of data files are not supported; join them into one file");
  const std::filesystem::path path = *folder / *file;
  storage = detail::read_file_bytes(path, max_bytes);
  return {storage, path.string(), 0, 1};
}

// NRRD "line skip" / MetaImage-style skips: drops whole lines from the data's start.
void skip_lines(DataRef& d, std::uint64_t lines, const Header& h, const std::string& key) {
  for (std::uint64_t n = 0; n < lines; ++n) {
    const std::size_t eol = d.bytes.find('\n');
    if (eol == std::string_view::npos)
      h.fail(key, "'" + key + "' skips " + std::to_string(lines) + " lines; the data has " +
                      std::to_string(n));
    d.bytes.remove_prefix(eol + 1);
    d.base += eol + 1;
    ++d.first_line;
  }
}

// Drops `skip` bytes from the data's start; -1 (where allowed): all but the last `need` bytes.
void skip_bytes(DataRef& d, std::int64_t skip, std::uint64_t need, const Header& h,
                const std::string& key) {
  if (skip == -1) {
    if (need > d.bytes.size())
      fail_at_byte(d.source, d.base + d.bytes.size(),
                   "the data holds " + std::to_string(d.bytes.size()) + " bytes where " +
                       std::to_string(need) + " are needed");
    skip = static_cast<std::int64_t>(d.bytes.size() - need);
  }
  if (skip < 0 || static_cast<std::uint64_t>(skip) > d.bytes.size())
    h.fail(key, "'" + key + "' " + std::to_string(skip) + " is not 0 to the data's size (" +
                    std::to_string(d.bytes.size()) + " bytes)");
  for (std::int64_t n = 0; n < skip; ++n)
    if (d.bytes[static_cast<std::size_t>(n)] == '\n') ++d.first_line;
  d.bytes.remove_prefix(static_cast<std::size_t>(skip));
  d.base += static_cast<std::uint64_t>(skip);
}

// A whole number in a header (a skip, a count).
std::int64_t header_integer(const Header& h, const std::string& key) {
  const std::string text = trim(*h.get(key));
  std::int64_t v = 0;
  const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), v);
  if (text.empty() || ec != std::errc() || end != text.data() + text.size())
    h.fail(key, "'" + key + "' must be a whole number, not '" + text + "'");
  return v;
}

Header parse_header(std::string_view data, const std::string& source, char separator,
                    bool ends_at_blank, const std::string& data_key) {
  Header h;
  h.source = &source;
  std::uint64_t at = 0, number = 0;
  bool first = true;
  while (const std::optional<Line> line = next_line(data, at, number)) {
    if (first && separator == ':') {  // NRRD's magic line
      first = false;
      continue;
    }
    first = false;
    if (line->text.empty() || trim(line->text).empty()) {
      if (ends_at_blank) {
        h.data_offset = line->end;
        h.data_line = line->number + 1;
        return h;
      }
      continue;
    }
    if (line->text[0] == '#') continue;
    std::size_t sep = separator == ':' ? line->text.find(":=") : std::string_view::npos;
    if (sep != std::string_view::npos) {  // an NRRD key/value pair: kept as "key:="
      h.fields[trim(line->text.substr(0, sep)) + ":="] = {trim(line->text.substr(sep + 2)),
                                                          line->number};
      continue;
    }
    sep = line->text.find(separator == ':' ? ": " : "=");
    if (sep == std::string_view::npos)
      fail_at_line(source, line->number,
                   "expected 'key" + std::string(separator == ':' ? ": " : " = ") + "value'");
    const std::string key =
        separator == ':' ? lower(trim(line->text.substr(0, sep))) : trim(line->text.substr(0, sep));
    const std::string value = trim(line->text.substr(sep + (separator == ':' ? 2 : 1)));
    h.fields[key] = {value, line->number};
    if (!ends_at_blank && key == data_key) {  // MetaImage: the data file line ends the header
      h.data_offset = line->end;
      h.data_line = line->number + 1;
      return h;
    }
  }
  h.data_offset = data.size();
  h.data_line = number + 1;
  return h;
}

Element nrrd_element(const Header& h) {
  if (!h.get("type")) h.fail("type", "the header has no 'type'");
  const std::string t = lower(*h.get("type"));
  static const std::map<std::string, std::string> names = {{"signed char", "int8"},
                                                           {"int8", "int8"},
                                                           {"int8_t", "int8"},
                                                           {"uchar", "uint8"},
                                                           {"unsigned char", "uint8"},
                                                           {"uint8", "uint8"},
                                                           {"uint8_t", "uint8"},
                                                           {"short", "int16"},
                                                           {"short int", "int16"},
                                                           {"signed short", "int16"},
                                                           {"signed short int", "int16"},
                                                           {"int16", "int16"},
                                                           {"int16_t", "int16"},
                                                           {"ushort", "uint16"},
                                                           {"unsigned short", "uint16"},
                                                           {"unsigned short int", "uint16"},
                                                           {"uint16", "uint16"},
                                                           {"uint16_t", "uint16"},
                                                           {"int", "int32"},
                                                           {"signed int", "int32"},
                                                           {"int32", "int32"},
                                                           {"int32_t", "int32"},
                                                           {"uint", "uint32"},
                                                           {"unsigned int", "uint32"},
                                                           {"uint32", "uint32"},
                                                           {"uint32_t", "uint32"},
                                                           {"longlong", "int64"},
                                                           {"long long", "int64"},
                                                           {"int64", "int64"},
                                                           {"int64_t", "int64"},
                                                           {"ulonglong", "uint64"},
                                                           {"unsigned long long", "uint64"},
                                                           {"uint64", "uint64"},
                                                           {"uint64_t", "uint64"},
                                                           {"float", "float32"},
                                                           {"double", "float64"}};
  const auto it = names.find(t);
  if (it == names.end()) h.fail("type", "unsupported NRRD type '" + t + "'");
  return *element_named(it->second);
}

// Inflates a header's data in place; errors name the data's file and offset within it.
// `declared`: the bytes the header's sizes need (0: none known); more is refused while
// inflating, so a small file cannot swell to gigabytes of data nobody reads.
void inflate_data(DataRef& d, std::string& storage, std::uint64_t max_bytes,
                  std::uint64_t declared) {
  try {
    storage = detail::inflate_bytes(d.bytes, d.source, max_bytes,
                                    {0, [declared](std::string_view) { return declared; }});
  } catch (const ParseError& e) {
    fail_at_byte(d.source, d.base + e.byte_offset().value_or(0), e.reason());
  }
  d.bytes = storage;
  d.base = 0;
  d.first_line = 1;
}

// `count` whitespace-separated numbers (NRRD's ascii encoding); errors name the data's line.
std::vector<double> decode_text(const DataRef& d, std::uint64_t count, const Header& h) {
  if (count > d.bytes.size() / 2 + 1)
    h.fail("sizes", std::to_string(count) + " values declared, more than the " +
                        std::to_string(d.bytes.size()) + " bytes of text can hold");
  std::vector<double> out;
  out.reserve(count);
  std::uint64_t at = 0, number = d.first_line - 1, last = d.first_line;
  while (const std::optional<Line> line = next_line(d.bytes, at, number)) {
    last = line->number;
    for (std::string_view w : words(line->text)) {
      if (out.size() == count)
        fail_at_line(d.source, line->number,
                     "more values than the " + std::to_string(count) + " 'sizes' declares");
      out.push_back(parse_number(w, d.source, line->number));
    }
  }
  if (out.size() != count)
    fail_at_line(d.source, last,
                 "the data ends after " + std::to_string(out.size()) + " of " +
                     std::to_string(count) + " values");
  return out;
}

// NRRD's data: attached or detached, line skip, then byte skip (after decompressing, as teem
// does), then decoded by its encoding.
std::vector<double> nrrd_values(std::string_view data, const Header& h, const Element& e,
                                std::uint64_t count, const std::filesystem::path* folder,
                                std::uint64_t max_bytes, VolumeFile& f) {
  const std::string encoding = h.get("encoding") ? lower(*h.get("encoding")) : "raw";
  const bool gzip = encoding == "gzip" || encoding == "gz";
  const bool text = encoding == "ascii" || encoding == "text" || encoding == "txt";
  if (!gzip && !text && encoding != "raw")
    h.fail("encoding",
           "unsupported NRRD encoding '" + encoding + "' (raw, gzip and ascii are read)");
  const bool big = h.get("endian") && lower(*h.get("endian")) == "big";
  std::string storage, inflated;
  DataRef d = header_data(data, h, h.get("datafile") ? "datafile" : "data file", folder, storage,
                          max_bytes);
  for (const char* key : {"line skip", "lineskip"})
    if (h.get(key)) {
      const std::int64_t n = header_integer(h, key);
      if (n < 0) h.fail(key, "'line skip' must be 0 or more");
      skip_lines(d, static_cast<std::uint64_t>(n), h, key);
    }
  const char* skip_key = h.get("byteskip") ? "byteskip" : "byte skip";
  const std::int64_t skip = h.get(skip_key) ? header_integer(h, skip_key) : 0;
  if (skip == -1 && (gzip || text)) h.fail(skip_key, "'byte skip: -1' is only read with raw data");
  if (gzip) {
    inflate_data(d, inflated, max_bytes,
                 count * std::uint64_t(e.size) +
                     static_cast<std::uint64_t>(std::max<std::int64_t>(skip, 0)));
    f.compressed = true;
  }
  skip_bytes(d, skip, count * std::uint64_t(e.size), h, skip_key);
  if (text) return decode_text(d, count, h);
  return decode(d.bytes, count, e, big, d.source, d.base);
}

// An axis stored backwards (a negative NRRD step): its values reversed and the origin moved
// to the cell that is now first, so every axis increases and the geometry is unchanged.
void reverse_axis(ScalarVolume& v, int axis) {
  const std::size_t n = std::size_t(v.dims[axis]);
  const std::size_t stride = axis == 0   ? 1
                             : axis == 1 ? std::size_t(v.dims[0])
                                         : std::size_t(v.dims[0]) * v.dims[1];
  for (std::size_t at = 0; at < v.values.size(); ++at) {
    const std::size_t i = at / stride % n;
    if (i < n - 1 - i) std::swap(v.values[at], v.values[at + (n - 1 - 2 * i) * stride]);
  }
  const double shift = -v.spacing[axis] * double(n - 1);
  (axis == 0 ? v.origin.x : axis == 1 ? v.origin.y : v.origin.z) += shift;
}

VolumeFile parse_nrrd(std::string_view data, const std::string& source,
                      const std::filesystem::path* folder, std::uint64_t max_bytes) {
  const Header h = parse_header(data, source, ':', true, "");
  if (!h.get("dimension")) h.fail("dimension", "the header has no 'dimension'");
  if (trim(*h.get("dimension")) != "3")
    h.fail("dimension", "a field is 3-dimensional, not dimension " + *h.get("dimension"));
  VolumeFile f;
  f.format = VolumeFormat::Nrrd;
  const Element e = nrrd_element(h);
  f.element_type = e.name;
  f.volume = unit_volume(header_dims(h, "sizes"));
  f.volume.values = nrrd_values(data, h, e, f.volume.count(), folder, max_bytes, f);
  std::array<double, 3> step{};  // signed: a negative step runs the axis backwards
  if (h.get("space directions")) {
    std::vector<double> m = h.numbers("space directions", 9);
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 3; ++c)
        if (r != c && m[3 * r + c] != 0)
          h.fail("space directions",
                 "rotated axes are not supported (the directions must be along x, y, z)");
    step = {m[0], m[4], m[8]};
  } else if (h.get("spacings")) {
    const std::vector<double> s = h.numbers("spacings", 3);
    step = {s[0], s[1], s[2]};
  }
  if (const std::string* sign = h.get("tpmsfill_sign:=")) {  // what write_volume records
    try {
      f.volume.sign = field_sign_from_name(*sign);
    } catch (const InputError& e) {
      h.fail("tpmsfill_sign:=", e.what());
    }
  }
  if (h.get("space origin")) {
    const std::vector<double> o = h.numbers("space origin", 3);
    f.volume.origin = {o[0], o[1], o[2]};
  }
  for (int a = 0; a < 3; ++a) {
    f.volume.spacing[a] = std::fabs(step[a]);
    if (step[a] < 0) reverse_axis(f.volume, a);
  }
  return f;
}

VolumeFile parse_metaimage(std::string_view data, const std::string& source,
                           const std::filesystem::path* folder, std::uint64_t max_bytes) {
  const Header h = parse_header(data, source, '=', false, "ElementDataFile");
  if (!h.get("NDims") || trim(*h.get("NDims")) != "3")
    h.fail("NDims", "a field is 3-dimensional: NDims must be 3");
  if (h.get("ElementNumberOfChannels") && trim(*h.get("ElementNumberOfChannels")) != "1")
    h.fail("ElementNumberOfChannels", "only one channel per element is supported");
  for (const char* key : {"TransformMatrix", "Rotation", "Orientation"})  // synonyms
    if (h.get(key) && h.numbers(key, 9) != std::vector<double>{1, 0, 0, 0, 1, 0, 0, 0, 1})
      h.fail(key,
             std::string("rotated volumes are not supported (") + key + " must be the identity)");
  if (!h.get("ElementDataFile")) h.fail("ElementDataFile", "the header has no 'ElementDataFile'");
  if (!h.get("ElementType")) h.fail("ElementType", "the header has no 'ElementType'");
  static const std::map<std::string, std::string> types = {
      {"MET_UCHAR", "uint8"},       {"MET_CHAR", "int8"},       {"MET_USHORT", "uint16"},
      {"MET_SHORT", "int16"},       {"MET_UINT", "uint32"},     {"MET_INT", "int32"},
      {"MET_ULONG_LONG", "uint64"}, {"MET_LONG_LONG", "int64"}, {"MET_FLOAT", "float32"},
      {"MET_DOUBLE", "float64"}};
  const auto type = types.find(*h.get("ElementType"));
  if (type == types.end())
    h.fail("ElementType", "unsupported ElementType '" + *h.get("ElementType") + "'");
  const Element e = *element_named(type->second);
  VolumeFile f;
  f.format = VolumeFormat::MetaImage;
  f.element_type = e.name;
  f.volume = unit_volume(header_dims(h, "DimSize"));
  auto flag = [&](const char* key) { return h.get(key) && lower(*h.get(key)) == "true"; };
  const bool big = flag("BinaryDataByteOrderMSB") || flag("ElementByteOrderMSB");
  if (h.get("BinaryData") && lower(*h.get("BinaryData")) != "true")
    h.fail("BinaryData", "text MetaImage data is not supported (BinaryData = False)");
  std::string storage, inflated;
  DataRef d = header_data(data, h, "ElementDataFile", folder, storage, max_bytes);
  const std::uint64_t need = f.volume.count() * std::uint64_t(e.size);
  if (h.get("HeaderSize")) {  // bytes before the data; -1: the data is the file's end
    const std::int64_t skip = header_integer(h, "HeaderSize");
    if (skip == -1 && flag("CompressedData"))
      h.fail("HeaderSize", "'HeaderSize = -1' is not read with compressed data");
    skip_bytes(d, skip, need, h, "HeaderSize");
  }
  if (flag("CompressedData")) {
    inflate_data(d, inflated, max_bytes, need);
    f.compressed = true;
  }
  f.volume.values = decode(d.bytes, f.volume.count(), e, big, d.source, d.base);
  for (const char* key : {"ElementSpacing", "ElementSize"})
    if (h.get(key)) {
      const std::vector<double> s = h.numbers(key, 3);
      f.volume.spacing = {s[0], s[1], s[2]};
      break;
    }
  for (const char* key : {"Offset", "Origin", "Position"})
    if (h.get(key)) {
      const std::vector<double> o = h.numbers(key, 3);
      f.volume.origin = {o[0], o[1], o[2]};
      break;
    }
  return f;
}

// ---- INR ----------------------------------------------------------------------------------

VolumeFile parse_inr(std::string_view data, const std::string& source) {
  // The header ends at a line "##}". INRIA's format pads it to a multiple of 256 bytes, but
  // CGAL reads up to that line whatever its length (libcgal-demo's small-scalar.inr has 240).
  const std::size_t end = data.substr(0, std::size_t{1} << 20).find("\n##}");
  if (end == std::string_view::npos)
    fail_at_byte(source, 0, "the INR header has no end (a line '##}' in its first MiB)");
  std::size_t header = end + 4;
  if (header < data.size() && data[header] == '\n') ++header;
  Header h;
  h.source = &source;
  std::uint64_t at = 0, number = 0;
  while (const std::optional<Line> line = next_line(data.substr(0, end), at, number)) {
    const std::size_t eq = line->text.find('=');
    if (eq == std::string_view::npos) continue;  // the magic line, blank padding
    h.fields[trim(line->text.substr(0, eq))] = {trim(line->text.substr(eq + 1)), line->number};
  }
  std::array<int, 3> dims{};
  const char* keys[3] = {"XDIM", "YDIM", "ZDIM"};
  for (int a = 0; a < 3; ++a) {
    if (!h.get(keys[a])) fail_at_line(source, 1, std::string("the INR header has no ") + keys[a]);
    dims[a] = parse_dim(*h.get(keys[a]), source, h.line(keys[a]));
  }
  if (h.get("VDIM") && trim(*h.get("VDIM")) != "1")
    h.fail("VDIM", "only VDIM=1 (one value per voxel) is supported");
  const std::string type = h.get("TYPE") ? *h.get("TYPE") : "";
  const int bits = h.get("PIXSIZE") ? std::atoi(h.get("PIXSIZE")->c_str()) : 0;
  std::string name;
  if (type == "float" && (bits == 32 || bits == 64))
    name = bits == 32 ? "float32" : "float64";
  else if ((type == "unsigned fixed" || type == "signed fixed") &&
           (bits == 8 || bits == 16 || bits == 32 || bits == 64))
    name = std::string(type[0] == 'u' ? "uint" : "int") + std::to_string(bits);
  else
    h.fail("TYPE", "unsupported INR TYPE '" + type + "' with PIXSIZE " + std::to_string(bits));
  const Element e = *element_named(name);
  const std::string cpu = h.get("CPU") ? lower(*h.get("CPU")) : "decm";
  const bool big = cpu == "sun" || cpu == "sgi";
  if (!big && cpu != "decm" && cpu != "alpha" && cpu != "pc")
    h.fail("CPU", "unknown INR CPU '" + cpu + "' (decm, alpha, pc: little-endian; sun, sgi: big)");
  VolumeFile f;
  f.format = VolumeFormat::Inr;
  f.element_type = e.name;
  f.volume = unit_volume(dims);
  f.volume.values = decode(data.substr(header), f.volume.count(), e, big, source, header);
  if (header % 256 != 0)
    f.warnings.push_back(source + ": the INR header is " + std::to_string(header) +
                         " bytes, not a multiple of 256 (read up to its '##}' line, as CGAL does)");
  const char* sk[3] = {"VX", "VY", "VZ"};
  const char* tk[3] = {"TX", "TY", "TZ"};
  std::array<double, 3> o{};
  for (int a = 0; a < 3; ++a) {
    if (h.get(sk[a])) f.volume.spacing[a] = parse_number(*h.get(sk[a]), source, h.line(sk[a]));
    if (h.get(tk[a])) o[a] = parse_number(*h.get(tk[a]), source, h.line(tk[a]));
  }
  f.volume.origin = {o[0], o[1], o[2]};
  return f;
}

VolumeFormat detect(std::string_view data, const std::string& source) {
  if (data.starts_with(kBinaryMagic)) return VolumeFormat::FieldBinary;
  if (io::looks_like_vdb(data)) return VolumeFormat::Vdb;
  if (data.starts_with("NRRD000")) return VolumeFormat::Nrrd;
  if (data.starts_with("#INRIMAGE")) return VolumeFormat::Inr;
  const std::string head(data.substr(0, 4096));
  if (head.find("NDims") != std::string::npos && head.find("ElementType") != std::string::npos)
    return VolumeFormat::MetaImage;
  if (head.find(kTextMagic) != std::string::npos) return VolumeFormat::FieldText;
  return volume_format_from_extension(source);
}

// What a gzipped binary form's header declares: the header and its counts' values. Other
// forms (text, NRRD, MetaImage, INR) declare nothing here; their own data is held to its
// header's size where it is compressed on its own.
detail::DeclaredSize binary_form_size() {
  return {kHeader2, [](std::string_view head) -> std::uint64_t {
            if (!head.starts_with(kBinaryMagic)) return 0;
            std::uint16_t version;
            std::memcpy(&version, head.data() + 4, 2);
            const auto type = static_cast<unsigned char>(head[6]);
            if ((version != 1 && version != 2) || type > 1) return 0;
            std::uint64_t count = 1;
            for (int a = 0; a < 3; ++a) {
              std::uint32_t d;
              std::memcpy(&d, head.data() + 8 + 4 * a, 4);
              if (d < 1 || d > kMaxDim) return 0;
              count *= d;
            }
            return (version == 2 ? kHeader2 : kHeader1) + count * (type == 0 ? 4 : 8);
          }};
}

VolumeFile parse_any(std::string_view bytes, const std::string& source, const VolumeReadOptions& o,
                     const std::filesystem::path* folder) {
  if (bytes.empty()) throw InputError(source + " is empty");
  if (bytes.size() > o.max_bytes)
    throw InputError(source + " is larger than the limit of " + std::to_string(o.max_bytes) +
                     " bytes");
  std::string inflated;
  bool gz = false;
  if (bytes.size() >= 2 && static_cast<unsigned char>(bytes[0]) == 0x1f &&
      static_cast<unsigned char>(bytes[1]) == 0x8b) {
    inflated = detail::inflate_bytes(bytes, source, o.max_bytes, binary_form_size());
    bytes = inflated, gz = true;
  }
  const VolumeFormat format = o.format == VolumeFormat::Auto ? detect(bytes, source) : o.format;
  VolumeFile f;
  switch (format) {
    case VolumeFormat::FieldText:
      f = parse_field_text(bytes, source);
      break;
    case VolumeFormat::FieldBinary:
      f = parse_field_binary(bytes, source);
      break;
    case VolumeFormat::Nrrd:
      f = parse_nrrd(bytes, source, folder, o.max_bytes);
      break;
    case VolumeFormat::MetaImage:
      f = parse_metaimage(bytes, source, folder, o.max_bytes);
      break;
    case VolumeFormat::Inr:
      f = parse_inr(bytes, source);
      break;
    case VolumeFormat::Vdb:
      f = io::parse_vdb(bytes, source, o.max_bytes);
      break;
    case VolumeFormat::Auto:
      throw InputError(source +
                       ": not a field file tpmsfill reads (the seed's text or binary form, "
                       "NRRD, MetaImage, INR or OpenVDB)");
  }
  f.compressed = f.compressed || gz;
  for (double s : f.volume.spacing)
    if (!(s >= 0) || !std::isfinite(s))
      throw InputError(source + ": a voxel spacing is negative or not finite");
  if (!f.volume.has_physical_size() && f.volume.spacing != std::array<double, 3>{}) {
    f.warnings.push_back(source +
                         " gives a zero spacing on some axis; it is read as the unit cube");
    f.volume.spacing = {};
    f.volume.origin = {};
  }
  return f;
}

constexpr detail::Named<VolumeFormat> kFormats[] = {{VolumeFormat::Auto, "auto"},
                                                    {VolumeFormat::FieldText, "field-text"},
                                                    {VolumeFormat::FieldBinary, "field-binary"},
                                                    {VolumeFormat::Nrrd, "nrrd"},
                                                    {VolumeFormat::MetaImage, "metaimage"},
                                                    {VolumeFormat::Inr, "inr"},
                                                    {VolumeFormat::Vdb, "vdb"}};
constexpr detail::Named<FieldSign> kSigns[] = {{FieldSign::Unknown, "unknown"},
                                               {FieldSign::Signed, "signed"},
                                               {FieldSign::Unsigned, "unsigned"}};

std::string number_text(double v) {
  char b[32];
  const auto r = std::to_chars(b, b + sizeof b, v);  // shortest that reads back exactly
  return std::string(b, r.ptr);
}

}  // namespace

std::string_view volume_format_name(VolumeFormat format) {
  return detail::name_of(kFormats, format);
}
std::string_view field_sign_name(FieldSign sign) {
  return detail::name_of(kSigns, sign);
}
FieldSign field_sign_from_name(std::string_view name) {
  return detail::from_name(kSigns, name, "sign");
}

VolumeFormat volume_format_from_extension(const std::filesystem::path& path) {
  std::string name = lower(path.filename().string());
  if (name.ends_with(".gz")) name.resize(name.size() - 3);
  const std::string ext = std::filesystem::path(name).extension().string();
  if (ext == ".tdf") return VolumeFormat::FieldText;
  if (ext == ".tdfb") return VolumeFormat::FieldBinary;
  if (ext == ".nrrd" || ext == ".nhdr") return VolumeFormat::Nrrd;
  if (ext == ".mha" || ext == ".mhd") return VolumeFormat::MetaImage;
  if (ext == ".inr") return VolumeFormat::Inr;
  if (ext == ".vdb") return VolumeFormat::Vdb;
  return VolumeFormat::Auto;
}

void require_valid(const ScalarVolume& v) {
  for (int d : v.dims)
    if (d < 1) throw InputError("a volume needs at least one cell along each axis");
  if (v.values.size() != v.count())
    throw InputError("a volume's value count does not match its dimensions");
  for (double x : v.values)
    if (!std::isfinite(x)) throw InputError("a volume holds a value that is not finite");
  for (double s : v.spacing)
    if (!(s >= 0) || !std::isfinite(s))
      throw InputError("a voxel spacing is negative or not finite");
  if (!v.has_physical_size() && v.spacing != std::array<double, 3>{})
    throw InputError("a volume's spacing must be given on all three axes or none");
}

VolumeFile parse_volume(std::string_view bytes, const std::string& source,
                        const VolumeReadOptions& o) {
  return parse_any(bytes, source, o, nullptr);
}

VolumeFile read_volume_file(const std::filesystem::path& path, const VolumeReadOptions& o) {
  const std::string bytes = detail::read_file_bytes(path, o.max_bytes);
  const std::filesystem::path folder = path.parent_path();
  return parse_any(bytes, path.string(), o, &folder);
}

void write_volume(const std::filesystem::path& path, const ScalarVolume& v, VolumeFormat format,
                  bool exact) {
  require_valid(v);
  if (format == VolumeFormat::Auto) format = volume_format_from_extension(path);
  std::string out;
  const bool f64 = exact;
  std::array<double, 3> size{};
  for (int a = 0; a < 3; ++a) size[a] = v.spacing[a] * v.dims[a];
  if (format == VolumeFormat::FieldText) {
    out = std::string(kTextMagic) + " 1\n";
    if (v.has_physical_size())
      out += "size " + number_text(size[0]) + " " + number_text(size[1]) + " " +
             number_text(size[2]) + "\n";
    if (placed(v))
      out += "origin " + number_text(v.origin.x) + " " + number_text(v.origin.y) + " " +
             number_text(v.origin.z) + "\n";
    out += "sign " + std::string(field_sign_name(v.sign)) + "\n";
    out += std::to_string(v.dims[0]) + " " + std::to_string(v.dims[1]) + " " +
           std::to_string(v.dims[2]) + "\n";
    for (std::size_t n = 0; n < v.values.size(); ++n)
      out += number_text(exact ? v.values[n] : static_cast<float>(v.values[n])) +
             ((n + 1) % std::size_t(v.dims[0]) == 0 ? "\n" : " ");
  } else if (format == VolumeFormat::FieldBinary || format == VolumeFormat::Nrrd) {
    std::string values;
    values.reserve(v.values.size() * (f64 ? 8 : 4));
    for (double x : v.values) {
      char b[8];
      if (f64) {
        std::memcpy(b, &x, 8);
      } else {
        const float f = static_cast<float>(x);
        std::memcpy(b, &f, 4);
      }
      values.append(b, f64 ? 8 : 4);
    }
    if (format == VolumeFormat::FieldBinary) {
      out = std::string(kBinaryMagic);
      const std::uint16_t version = placed(v) ? 2 : 1;  // 1 where it adds nothing
      out.append(reinterpret_cast<const char*>(&version), 2);
      out.push_back(f64 ? 1 : 0);
      out.push_back(static_cast<char>(v.sign == FieldSign::Unknown  ? 0
                                      : v.sign == FieldSign::Signed ? 1
                                                                    : 2));
      for (int d : v.dims) {
        const auto u = static_cast<std::uint32_t>(d);
        out.append(reinterpret_cast<const char*>(&u), 4);
      }
      for (double s : v.has_physical_size() ? size : std::array<double, 3>{})
        out.append(reinterpret_cast<const char*>(&s), 8);
      if (version == 2)
        for (const double o : {v.origin.x, v.origin.y, v.origin.z})
          out.append(reinterpret_cast<const char*>(&o), 8);
    } else {
      out = "NRRD0004\n# written by tpmsfill\ntype: " + std::string(f64 ? "double" : "float") +
            "\ndimension: 3\nsizes: " + std::to_string(v.dims[0]) + " " +
            std::to_string(v.dims[1]) + " " + std::to_string(v.dims[2]) +
            "\nendian: little\nencoding: raw\ntpmsfill_sign:=" +
            std::string(field_sign_name(v.sign)) + "\n";
      if (v.has_physical_size())
        out += "space: left-posterior-superior\nspace directions: (" + number_text(v.spacing[0]) +
               ",0,0) (0," + number_text(v.spacing[1]) + ",0) (0,0," + number_text(v.spacing[2]) +
               ")\nspace origin: (" + number_text(v.origin.x) + "," + number_text(v.origin.y) +
               "," + number_text(v.origin.z) + ")\n";
      out += "\n";
    }
    out += values;
  } else if (format == VolumeFormat::Vdb) {
    out = io::vdb_bytes(v);
  } else {
    throw InputError(path.string() +
                     ": fields are written as .tdf (text), .tdfb (binary), .nrrd or .vdb");
  }
  write_file_atomically(path, out);
}

double sample_volume(const ScalarVolume& volume, Vec3 p, bool* outside) {
  int base[3];
  double weight[3];
  bool out = false;
  for (int a = 0; a < 3; ++a) {
    // Continuous cell index: cell centres at integers.
    const double x = (p[a] - volume.origin[a]) / volume.spacing[a];
    const double last = volume.dims[a] - 1;
    out |= x < -0.5 || x > last + 0.5;
    const double clamped = std::clamp(x, 0.0, last);
    base[a] = std::min(static_cast<int>(clamped), std::max(volume.dims[a] - 2, 0));
    weight[a] = volume.dims[a] > 1 ? clamped - base[a] : 0.0;
  }
  if (outside) *outside = out;
  double sum = 0;
  for (int c = 0; c < 8; ++c) {
    double w = 1;
    int at[3];
    for (int a = 0; a < 3; ++a) {
      const int bit = (c >> a) & 1;
      w *= bit ? weight[a] : 1 - weight[a];
      at[a] = std::min(base[a] + bit, volume.dims[a] - 1);
    }
    if (w != 0) sum += w * volume.at(at[0], at[1], at[2]);
  }
  return sum;
}

}  // namespace tpmsfill
