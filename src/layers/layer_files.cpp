// Stage "layer files": each format is a header, one block per layer and a trailer, so a layer
// is formatted into a buffer and written as soon as it comes (single files flush every
// kFlushBytes; folder formats write one whole file per layer).
#include "tpmsfill/layer_files.hpp"

#include <algorithm>
#include <array>
#include <bit>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <limits>
#include <optional>
#include <stdexcept>
#include <utility>

#include "core/parallel.hpp"
#include "io/png.hpp"
#include "io/xml_text.hpp"
#include "tpmsfill/error.hpp"

namespace tpmsfill {
namespace {

constexpr int kMaxImageSide = 1 << 15;
constexpr std::size_t kFlushBytes = std::size_t{1} << 20;
// CLI binary long commands (CLI 2.0, section "binary format").
constexpr std::uint16_t kCliStartLayerLong = 127;
constexpr std::uint16_t kCliStartPolylineLong = 130;
constexpr std::int32_t kCliPartId = 1;  // the one $$LABEL every polyline belongs to

struct FormatName {
  LayerFormat format;
  std::string_view name;
};
constexpr std::array<FormatName, 5> kFormatNames{{{LayerFormat::Cli, "cli"},
                                                  {LayerFormat::CliBinary, "cli-binary"},
                                                  {LayerFormat::Svg, "svg"},
                                                  {LayerFormat::SvgLayers, "svg-layers"},
                                                  {LayerFormat::PngLayers, "png"}}};

// Fixed point with six decimals (1 nm in mm): std::to_chars, so no locale can make the point a
// comma, which a CLI or SVG reader would take for a separator.
void append_fixed(std::string& out, double value) {
  std::array<char, 400> buf;  // the longest double in fixed notation, with room to spare
  const auto [end, ec] =
      std::to_chars(buf.data(), buf.data() + buf.size(), value, std::chars_format::fixed, 6);
  std::string_view text(buf.data(), static_cast<std::size_t>(end - buf.data()));
  if (text == "-0.000000") text = "0.000000";  // a tiny negative is noise, not a sign
  out += text;
}

// Shortest text that reads back exactly, for messages (std::to_string would use the locale).
std::string shortest(double value) {
  std::array<char, 32> buf;
  const auto [end, ec] = std::to_chars(buf.data(), buf.data() + buf.size(), value);
  return std::string(buf.data(), end);
}

// A size for a sentence: four significant digits, in any locale.
std::string readable(double value) {
  std::array<char, 32> buf;
  const auto [end, ec] =
      std::to_chars(buf.data(), buf.data() + buf.size(), value, std::chars_format::general, 4);
  return std::string(buf.data(), end);
}

template <typename T>
void append_le(std::string& out, T value) {
  auto bytes = std::bit_cast<std::array<char, sizeof(T)>>(value);
  if constexpr (std::endian::native == std::endian::big) std::reverse(bytes.begin(), bytes.end());
  out.append(bytes.data(), bytes.size());
}

// CLI header fields end at a comma or a line break, and the file is ASCII.
std::string cli_label(const std::string& label) {
  std::string out;
  for (const char c : label) {
    const auto u = static_cast<unsigned char>(c);
    out.push_back(u < 0x20 || u >= 0x7f || c == ',' ? '_' : c);
  }
  return out.empty() ? "part" : out;
}

// No $$DATE: the file must be a function of the layers alone (byte-reproducible jobs), and the
// field is optional in CLI 2.0.
std::string cli_header(const LayerFileOptions& o, bool binary) {
  std::string h = "$$HEADERSTART\n";
  h += binary ? "$$BINARY\n" : "$$ASCII\n";
  h += "$$UNITS/00000001.000000\n";  // coordinates are mm already
  h += "$$VERSION/200\n";
  h += "$$LABEL/" + std::to_string(kCliPartId) + "," + cli_label(o.label) + "\n";
  h += "$$DIMENSION/";
  const Box3& b = o.bounds;
  const std::array<double, 6> dims{b.min.x, b.min.y, b.min.z, b.max.x, b.max.y, b.max.z};
  for (std::size_t i = 0; i < dims.size(); ++i) {
    if (i > 0) h += ',';
    append_fixed(h, dims[i]);
  }
  h += "\n$$LAYERS/" + std::to_string(o.layer_count) + "\n";
  // Binary commands follow $$HEADEREND at once: a line break there would be read as a command.
  h += binary ? "$$HEADEREND" : "$$HEADEREND\n$$GEOMETRYSTART\n";
  return h;
}

// CLI's layer height is the layer's upper surface; polylines repeat their first point to close.
void append_cli_ascii_layer(std::string& out, const Layer& layer) {
  out += "$$LAYER/";
  append_fixed(out, layer.top);
  out += '\n';
  for (const Contour& c : layer.contours) {
    if (c.points.empty()) continue;
    out += "$$POLYLINE/" + std::to_string(kCliPartId) + (c.outer() ? ",1," : ",0,") +
           std::to_string(c.points.size() + 1);
    for (std::size_t i = 0; i <= c.points.size(); ++i) {
      const Vec2& p = c.points[i % c.points.size()];
      out += ',';
      append_fixed(out, p.x);
      out += ',';
      append_fixed(out, p.y);
    }
    out += '\n';
  }
}

void append_cli_binary_layer(std::string& out, const Layer& layer) {
  append_le(out, kCliStartLayerLong);
  append_le(out, static_cast<float>(layer.top));
  for (const Contour& c : layer.contours) {
    if (c.points.empty()) continue;
    append_le(out, kCliStartPolylineLong);
    append_le(out, kCliPartId);
    append_le(out, std::int32_t{c.outer() ? 1 : 0});
    append_le(out, static_cast<std::int32_t>(c.points.size() + 1));
    for (std::size_t i = 0; i <= c.points.size(); ++i) {
      const Vec2& p = c.points[i % c.points.size()];
      append_le(out, static_cast<float>(p.x));
      append_le(out, static_cast<float>(p.y));
    }
  }
}

// Millimetres on the page, +y up: the root group flips y and moves the bounds' corner
// (min.x, max.y) to the page's origin.
std::string svg_header(const LayerFileOptions& o) {
  const Box3& b = o.bounds;
  std::string w, h, tx, ty;
  append_fixed(w, b.max.x - b.min.x);
  append_fixed(h, b.max.y - b.min.y);
  append_fixed(tx, -b.min.x);
  append_fixed(ty, b.max.y);
  return "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n"
         "<svg xmlns=\"http://www.w3.org/2000/svg\" version=\"1.1\" width=\"" +
         w + "mm\" height=\"" + h + "mm\" viewBox=\"0 0 " + w + " " + h + "\">\n<title>" +
         detail::xml_escaped(o.label) + "</title>\n<g transform=\"translate(" + tx + "," + ty +
         ") scale(1,-1)\" fill=\"black\" stroke=\"none\">\n";
}

constexpr std::string_view kSvgTrailer = "</g>\n</svg>\n";

// The material scale at t ∈ [0, 1]: blue (0) → green (½) → yellow (1), linear between.
std::array<std::uint8_t, 3> material_rgb(double t) {
  static constexpr double kStops[3][3] = {{0.15, 0.25, 0.75}, {0.2, 0.7, 0.35}, {0.95, 0.85, 0.2}};
  const int i = t < 0.5 ? 0 : 1;
  const double s = 2 * t - i;
  std::array<std::uint8_t, 3> rgb;
  for (int c = 0; c < 3; ++c)
    rgb[c] = static_cast<std::uint8_t>(
        std::lround(255 * ((1 - s) * kStops[i][c] + s * kStops[i + 1][c])));
  return rgb;
}

// The scale's colour of m between lo and hi, as "#rrggbb".
std::string material_colour(double m, double lo, double hi) {
  const std::array<std::uint8_t, 3> rgb =
      material_rgb(hi > lo ? std::clamp((m - lo) / (hi - lo), 0.0, 1.0) : 0.5);
  std::array<char, 8> hex;
  std::snprintf(hex.data(), hex.size(), "#%02x%02x%02x", rgb[0], rgb[1], rgb[2]);
  return hex.data();
}

// A material section: each triangle filled with its mean material's colour (a hairline of the
// same colour closes the antialiasing seams between them).
void append_svg_material(std::string& out, const MaterialSection& m) {
  for (const auto& t : m.triangles) {
    const std::string colour =
        material_colour((m.material[t[0]] + m.material[t[1]] + m.material[t[2]]) / 3,
                        m.material_min, m.material_max);
    out += "<path fill=\"" + colour + "\" stroke=\"" + colour + "\" stroke-width=\"0.01\" d=\"M";
    for (int k = 0; k < 3; ++k) {
      out += ' ';
      append_fixed(out, m.points[t[k]].x);
      out += ' ';
      append_fixed(out, m.points[t[k]].y);
    }
    out += "\"/>\n";
  }
}

// One path per layer: holes are clockwise, so the nonzero rule leaves them empty. Over a
// material section the contours are outlines.
void append_svg_layer(std::string& out, const Layer& layer, bool visible) {
  out += "<g id=\"layer-" + std::to_string(layer.index) + "\" data-z=\"";
  append_fixed(out, layer.z);
  out += "\" data-top=\"";
  append_fixed(out, layer.top);
  out += visible ? "\">\n" : "\" display=\"none\">\n";
  const bool material = !layer.material.triangles.empty();
  if (material) append_svg_material(out, layer.material);
  bool any = false;
  for (const Contour& c : layer.contours) {
    if (c.points.empty()) continue;
    out += any ? " M "
               : (material ? "<path fill=\"none\" stroke=\"black\" stroke-width=\"0.05\" d=\"M "
                           : "<path fill-rule=\"nonzero\" d=\"M ");
    any = true;
    for (std::size_t i = 0; i < c.points.size(); ++i) {
      if (i == 1) out += " L";
      if (i > 0) out += ' ';
      append_fixed(out, c.points[i].x);
      out += ' ';
      append_fixed(out, c.points[i].y);
    }
    out += " Z";
  }
  if (any) out += "\"/>\n";
  out += "</g>\n";
}

// The PNG pixel grid over the bounds: column i's centre at x0 + (i + ½)·pixel, row r's (row 0
// at the top) at y0 − (r + ½)·pixel.
struct Raster {
  int width = 1, height = 1;
  double x0 = 0, y0 = 0, pixel = 1;
};

// Whole pixels over an extent, allowing for the rounding of extent / pixel (10 / 0.05 must be
// 200, not 201).
long long pixels_over(double extent, double pixel) {
  const double n = std::ceil(extent / pixel - 1e-9);
  return n < 1 ? 1 : (n > 1e15 ? static_cast<long long>(1e15) : static_cast<long long>(n));
}

// A mask's pixels off the contours deflate to about this share of a byte each (runs of white
// or black: femur and tube masks at 0.05 mm, docs/benchmarks.md §26).
constexpr double kPngPixelShare = 0.01;

bool has_plane(const Field& f) {
  return f.grid.dims[0] >= 2 && f.grid.dims[1] >= 2 && f.grid.dims[2] == 1 &&
         f.values.size() == f.grid.node_count() && f.grid.spacing > 0;
}

// φ at (x, y), bilinear between the plane's nodes; outside the nodes it is outside the solid.
double plane_phi(const Field& f, double x, double y) {
  const Grid& g = f.grid;
  const double u = (x - g.origin.x) / g.spacing, v = (y - g.origin.y) / g.spacing;
  if (!(u >= 0 && u <= g.dims[0] - 1 && v >= 0 && v <= g.dims[1] - 1))
    return std::numeric_limits<double>::infinity();
  const int i = std::min(static_cast<int>(u), g.dims[0] - 2);
  const int j = std::min(static_cast<int>(v), g.dims[1] - 2);
  const double s = u - i, t = v - j;
  const auto at = [&](int di, int dj) { return double{f.values[g.index(i + di, j + dj, 0)]}; };
  return (1 - t) * ((1 - s) * at(0, 0) + s * at(1, 0)) + t * ((1 - s) * at(0, 1) + s * at(1, 1));
}

// A material section: pixels whose centre lies in a triangle get 1 + 254 t, t the material
// interpolated there on the scale (0: empty). Triangles are disjoint, so each pixel is written
// by at most one, except on shared edges where both write the same value.
std::vector<std::uint8_t> rasterise_material(const MaterialSection& m, const Raster& r) {
  std::vector<std::uint8_t> image(static_cast<std::size_t>(r.width) * r.height, 0);
  const double span = m.material_max > m.material_min ? m.material_max - m.material_min : 1;
  for (const auto& t : m.triangles) {
    const Vec2 a = m.points[t[0]], b = m.points[t[1]], c = m.points[t[2]];
    const double det = (b.x - a.x) * (c.y - a.y) - (c.x - a.x) * (b.y - a.y);
    if (!(std::abs(det) > 0)) continue;
    const double x_lo = std::min({a.x, b.x, c.x}), x_hi = std::max({a.x, b.x, c.x});
    const double y_lo = std::min({a.y, b.y, c.y}), y_hi = std::max({a.y, b.y, c.y});
    const long long c0 = std::max(0LL, std::llround(std::floor((x_lo - r.x0) / r.pixel - 0.5)));
    const long long c1 =
        std::min(r.width - 1LL, std::llround(std::ceil((x_hi - r.x0) / r.pixel - 0.5)));
    const long long r0 = std::max(0LL, std::llround(std::floor((r.y0 - y_hi) / r.pixel - 0.5)));
    const long long r1 =
        std::min(r.height - 1LL, std::llround(std::ceil((r.y0 - y_lo) / r.pixel - 0.5)));
    for (long long row = r0; row <= r1; ++row) {
      const double y = r.y0 - (static_cast<double>(row) + 0.5) * r.pixel;
      for (long long col = c0; col <= c1; ++col) {
        const double x = r.x0 + (static_cast<double>(col) + 0.5) * r.pixel;
        const double wb = ((x - a.x) * (c.y - a.y) - (c.x - a.x) * (y - a.y)) / det;
        const double wc = ((b.x - a.x) * (y - a.y) - (x - a.x) * (b.y - a.y)) / det;
        const double wa = 1 - wb - wc;
        if (wa < 0 || wb < 0 || wc < 0) continue;
        const double value = wa * m.material[t[0]] + wb * m.material[t[1]] + wc * m.material[t[2]];
        const double level = std::clamp((value - m.material_min) / span, 0.0, 1.0);
        image[static_cast<std::size_t>(row) * r.width + col] =
            static_cast<std::uint8_t>(1 + std::lround(254 * level));
      }
    }
  }
  return image;
}

// Coverage = clamp(½ − φ/pixel, 0, 1): the fraction of the pixel on the solid side of a
// straight boundary at distance φ from its centre (exact for a boundary along a pixel axis).
std::vector<std::uint8_t> rasterise(const Layer& layer, const Raster& r) {
  if (!layer.material.triangles.empty()) return rasterise_material(layer.material, r);
  std::vector<std::uint8_t> image(static_cast<std::size_t>(r.width) * r.height, 0);
  if (!has_plane(layer.field)) return image;
  detail::parallel_for(static_cast<std::size_t>(r.height), 16, [&](std::size_t b, std::size_t e) {
    for (std::size_t row = b; row < e; ++row) {
      const double y = r.y0 - (static_cast<double>(row) + 0.5) * r.pixel;
      std::uint8_t* out = &image[row * r.width];
      for (int col = 0; col < r.width; ++col) {
        const double x = r.x0 + (col + 0.5) * r.pixel;
        const double coverage = 0.5 - plane_phi(layer.field, x, y) / r.pixel;
        // Written so that a NaN in the field reads as empty rather than as any byte.
        out[col] = coverage >= 1  ? 255
                   : coverage > 0 ? static_cast<std::uint8_t>(std::lround(255 * coverage))
                                  : 0;
      }
    }
  });
  return image;
}

std::string layer_file_name(std::uint64_t index, const char* extension) {
  std::array<char, 48> buf;
  std::snprintf(buf.data(), buf.size(), "layer_%05llu.%s", static_cast<unsigned long long>(index),
                extension);
  return buf.data();
}

// A file written through stdio's buffer; every failure is an IoError naming the file.
class OutFile {
 public:
  explicit OutFile(std::filesystem::path path) : path_(std::move(path)) {
    file_ = std::fopen(path_.c_str(), "wb");
    if (!file_) fail("cannot create ");
  }
  OutFile(const OutFile&) = delete;
  OutFile& operator=(const OutFile&) = delete;
  ~OutFile() {
    if (file_) std::fclose(file_);  // an abandoned file: the error is already being reported
  }
  void write(std::string_view bytes) {
    if (!bytes.empty() && std::fwrite(bytes.data(), 1, bytes.size(), file_) != bytes.size())
      fail("cannot write ");
  }
  // fclose is where a full disk shows up for the buffer's last bytes.
  void close() {
    if (std::fclose(std::exchange(file_, nullptr)) != 0) fail("cannot write ");
  }

 private:
  [[noreturn]] void fail(const char* what) {
    throw IoError(what + path_.string() + ": " + std::strerror(errno));
  }
  std::filesystem::path path_;
  std::FILE* file_ = nullptr;
};

bool is_cli(LayerFormat f) {
  return f == LayerFormat::Cli || f == LayerFormat::CliBinary;
}

}  // namespace

std::string_view layer_format_name(LayerFormat format) {
  for (const FormatName& n : kFormatNames)
    if (n.format == format) return n.name;
  return "unknown";
}

LayerFormat layer_format_from_name(std::string_view name) {
  std::string known;
  for (const FormatName& n : kFormatNames) {
    if (n.name == name) return n.format;
    known += (known.empty() ? "" : ", ") + std::string(n.name);
  }
  throw InputError("unknown layer format '" + std::string(name) + "' (one of " + known + ")");
}

bool writes_folder(LayerFormat format) {
  return format == LayerFormat::SvgLayers || format == LayerFormat::PngLayers;
}

CoordinateRounding layer_rounding(LayerFormat format) {
  switch (format) {
    case LayerFormat::CliBinary:
      return CoordinateRounding::Float;
    case LayerFormat::Cli:
    case LayerFormat::Svg:
    case LayerFormat::SvgLayers:
      return CoordinateRounding::SixDecimals;
    case LayerFormat::PngLayers:
      return CoordinateRounding::None;
  }
  return CoordinateRounding::None;
}

struct LayerFileWriter::Impl {
  std::filesystem::path path;
  LayerFileOptions options;
  std::vector<std::filesystem::path> files;
  std::optional<OutFile> file;  // the one-file formats'
  std::string buffer;           // what the one file has not been given yet
  std::uint64_t added = 0;
  bool finished = false;
  Raster raster;

  void write_one_file_layer(const Layer& layer);
  void write_folder_layer(const Layer& layer);
};

namespace {

void check_options(const LayerFileOptions& o) {
  const Box3& b = o.bounds;
  const bool finite = std::isfinite(b.min.x) && std::isfinite(b.min.y) && std::isfinite(b.min.z) &&
                      std::isfinite(b.max.x) && std::isfinite(b.max.y) && std::isfinite(b.max.z);
  if (b.empty() || !finite) throw InputError("the layers' bounds are empty or not finite");
  if (!(o.pixel > 0) || !std::isfinite(o.pixel))
    throw InputError("the pixel size must be positive (got " + shortest(o.pixel) + " mm)");
  if (o.format != LayerFormat::PngLayers) return;
  const double extent = std::max(b.max.x - b.min.x, b.max.y - b.min.y);
  if (pixels_over(extent, o.pixel) > kMaxImageSide) {
    throw InputError("a " + readable(o.pixel) + " mm pixel makes images of over " +
                     std::to_string(kMaxImageSide) + " pixels a side for a " + readable(extent) +
                     " mm part; a pixel of at least " + readable(extent / kMaxImageSide * 1.0001) +
                     " mm fits");
  }
}

}  // namespace

LayerFileWriter::LayerFileWriter(const std::filesystem::path& path, const LayerFileOptions& options)
    : impl_(std::make_unique<Impl>()) {
  check_options(options);
  Impl& m = *impl_;
  m.path = path;
  m.options = options;
  if (writes_folder(options.format)) {
    std::error_code ec;
    if (!std::filesystem::is_directory(path, ec))
      throw IoError("cannot write layers into " + path.string() + ": it is not a folder");
    const Box3& b = options.bounds;
    m.raster = {static_cast<int>(pixels_over(b.max.x - b.min.x, options.pixel)),
                static_cast<int>(pixels_over(b.max.y - b.min.y, options.pixel)), b.min.x, b.max.y,
                options.pixel};
    return;
  }
  m.file.emplace(path);
  m.files.push_back(path);
  if (is_cli(options.format))
    m.buffer = cli_header(options, options.format == LayerFormat::CliBinary);
  else
    m.buffer = svg_header(options);
}

LayerFileWriter::~LayerFileWriter() = default;

void LayerFileWriter::Impl::write_one_file_layer(const Layer& layer) {
  switch (options.format) {
    case LayerFormat::Cli:
      append_cli_ascii_layer(buffer, layer);
      break;
    case LayerFormat::CliBinary:
      append_cli_binary_layer(buffer, layer);
      break;
    default:
      append_svg_layer(buffer, layer, added == 0);  // only the lowest shows at first
  }
  if (buffer.size() >= kFlushBytes) {
    file->write(buffer);
    buffer.clear();
  }
}

void LayerFileWriter::Impl::write_folder_layer(const Layer& layer) {
  const bool png = options.format == LayerFormat::PngLayers;
  const std::filesystem::path name = path / layer_file_name(layer.index, png ? "png" : "svg");
  std::string bytes;
  if (png) {
    if (!has_plane(layer.field) && !layer.contours.empty() && layer.material.triangles.empty())
      throw InputError("layer " + std::to_string(layer.index) +
                       " has contours but no plane field to draw the PNG from");
    std::vector<std::uint8_t> image = rasterise(layer, raster);
    int channels = 1;
    // A material layer, or one with nothing in it (which must be the white page like the
    // others' empty pixels, not a grey image among RGB ones).
    if (options.material_colour && (!layer.material.triangles.empty() || layer.contours.empty())) {
      // Grey 1 + 254 t back to t, on the material scale; 0 (empty) is the white page.
      std::vector<std::uint8_t> rgb(image.size() * 3, 255);
      for (std::size_t n = 0; n < image.size(); ++n)
        if (image[n]) {
          const std::array<std::uint8_t, 3> c = material_rgb((image[n] - 1) / 254.0);
          std::copy(c.begin(), c.end(), rgb.begin() + 3 * n);
        }
      image = std::move(rgb);
      channels = 3;
    }
    const double per_metre = std::round(1000 / options.pixel);
    const auto phys = static_cast<std::uint32_t>(
        std::clamp(per_metre, 1.0, double{std::numeric_limits<std::uint32_t>::max()}));
    bytes = detail::encode_png(raster.width, raster.height, channels, image.data(), phys);
  } else {
    bytes = svg_header(options);
    append_svg_layer(bytes, layer, true);
    bytes += kSvgTrailer;
  }
  OutFile out(name);
  out.write(bytes);
  out.close();
  files.push_back(name);
}

void LayerFileWriter::add(const Layer& layer) {
  Impl& m = *impl_;
  if (m.finished) throw std::logic_error("LayerFileWriter::add after finish");
  if (writes_folder(m.options.format))
    m.write_folder_layer(layer);
  else
    m.write_one_file_layer(layer);
  ++m.added;
}

void LayerFileWriter::finish() {
  Impl& m = *impl_;
  if (m.finished) return;
  m.finished = true;
  if (!m.file) return;
  // A header that miscounts its layers is a file a machine may reject halfway through a build.
  if (is_cli(m.options.format) && m.added != m.options.layer_count)
    throw InputError(m.path.string() + ": $$LAYERS says " + std::to_string(m.options.layer_count) +
                     " layers but " + std::to_string(m.added) + " were added");
  if (m.options.format == LayerFormat::Cli) m.buffer += "$$GEOMETRYEND\n";
  if (m.options.format == LayerFormat::Svg) m.buffer += kSvgTrailer;
  m.file->write(m.buffer);
  m.buffer.clear();
  m.file->close();
  m.file.reset();
}

const std::vector<std::filesystem::path>& LayerFileWriter::files() const {
  return impl_->files;
}

double layer_file_bytes(const LayerFileOptions& o, double points, double material_triangles) {
  const Box3& b = o.bounds;
  const auto layers = static_cast<double>(o.layer_count);
  if (o.format == LayerFormat::PngLayers) {
    const double pixels = static_cast<double>(pixels_over(b.max.x - b.min.x, o.pixel)) *
                          static_cast<double>(pixels_over(b.max.y - b.min.y, o.pixel));
    const double channels = o.material_colour ? 3 : 1;
    return layers * (100 + channels * kPngPixelShare * pixels) + channels * points;
  }
  if (o.format == LayerFormat::CliBinary) return 200 + 8 * layers + 8 * points;
  // Six decimals after the integer digits and the sign: a point is two numbers and two
  // separators, an SVG triangle three points and its colour.
  const double reach = std::fmax(std::fmax(std::fabs(b.min.x), std::fabs(b.max.x)),
                                 std::fmax(std::fabs(b.min.y), std::fabs(b.max.y)));
  const double digits = std::floor(std::log10(std::fmax(reach, 1.0))) + 1 + 7 +
                        (b.min.x < 0 || b.min.y < 0 ? 0.5 : 0.0);
  const double point = 2 * digits + 2;
  const bool svg = o.format == LayerFormat::Svg || o.format == LayerFormat::SvgLayers;
  return 300 + 60 * layers + points * point + (svg ? material_triangles * (67 + 3 * point) : 0);
}

}  // namespace tpmsfill
