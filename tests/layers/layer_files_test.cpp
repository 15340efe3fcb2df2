// Stage "layer files": every format is read back by a small reader written here from the format's
// definition (CLI 2.0, SVG 1.1, PNG), not by the writer's own code, and compared with the layers.
#include <gtest/gtest.h>
#include <zlib.h>

#include <algorithm>
#include <bit>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <numbers>
#include <optional>
#include <string>
#include <string_view>
#include <tpmsfill/error.hpp>
#include <tpmsfill/layer_files.hpp>
#include <tpmsfill/slice.hpp>
#include <vector>

#include "test_util.hpp"

using namespace tpmsfill;

namespace {

Contour contour(std::vector<Vec2> points) {
  Contour c{std::move(points), 0};
  for (std::size_t i = 0; i < c.points.size(); ++i) {
    const Vec2 a = c.points[i], b = c.points[(i + 1) % c.points.size()];
    c.area += 0.5 * (a.x * b.y - b.x * a.y);
  }
  return c;
}

/// Two layers: a square with a square hole (coordinates that need all six decimals), then a
/// triangle.
std::vector<Layer> two_layers() {
  Layer a;
  a.index = 0;
  a.bottom = 0;
  a.top = 0.1;
  a.z = 0.05;
  a.contours = {contour({{0.1234567, 0.2345678},
                         {9.8765432, 0.2345678},
                         {9.8765432, 9.7654321},
                         {0.1234567, 9.7654321}}),
                contour({{3.3333333, 3.3333333},
                         {3.3333333, 6.6666667},
                         {6.6666667, 6.6666667},
                         {6.6666667, 3.3333333}})};
  Layer b;
  b.index = 1;
  b.bottom = 0.1;
  b.top = 0.2;
  b.z = 0.15;
  b.contours = {contour({{1, 1}, {8, 1}, {4.5, 7.25}})};
  return {a, b};
}

LayerFileOptions options(LayerFormat format) {
  LayerFileOptions o;
  o.format = format;
  o.bounds.min = {0, 0, 0};
  o.bounds.max = {10, 10, 0.2};
  o.layer_count = 2;
  o.layer = 0.1;
  o.label = "square,hole";
  return o;
}

std::vector<std::filesystem::path> write_layers(const std::filesystem::path& path,
                                                const LayerFileOptions& o,
                                                const std::vector<Layer>& layers) {
  LayerFileWriter writer(path, o);
  for (const Layer& l : layers) writer.add(l);
  writer.finish();
  return writer.files();
}

std::vector<std::string> split(std::string_view text, char separator) {
  std::vector<std::string> parts;
  std::size_t start = 0;
  for (std::size_t at; (at = text.find(separator, start)) != std::string_view::npos; start = at + 1)
    parts.emplace_back(text.substr(start, at - start));
  parts.emplace_back(text.substr(start));
  return parts;
}

double number(const std::string& text) {
  double v = std::nan("");
  const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), v);
  EXPECT_TRUE(ec == std::errc{} && end == text.data() + text.size()) << "'" << text << "'";
  return v;
}

std::size_t count(std::string_view text, std::string_view what) {
  std::size_t n = 0;
  for (std::size_t at = text.find(what); at != std::string_view::npos;
       at = text.find(what, at + what.size()))
    ++n;
  return n;
}

// --- CLI ------------------------------------------------------------------------------------

/// What a CLI file says, read as a machine would.
struct CliPolyline {
  int id = 0, dir = 0;
  std::vector<Vec2> points;
};
struct CliLayer {
  double z = 0;
  std::vector<CliPolyline> polylines;
};
struct CliFile {
  std::vector<std::pair<std::string, std::string>> header;  ///< ("$$UNITS", "...")
  std::vector<CliLayer> layers;
  std::string value(const std::string& key) const {
    for (const auto& [k, v] : header)
      if (k == key) return v;
    return "(none)";
  }
};

/// The ASCII header up to $$HEADEREND; `rest` gets what follows it.
CliFile parse_cli_header(const std::string& bytes, std::string* rest) {
  CliFile f;
  const std::size_t end = bytes.find("$$HEADEREND");
  EXPECT_NE(end, std::string::npos);
  for (const std::string& line : split(std::string_view(bytes).substr(0, end), '\n')) {
    if (line.empty()) continue;
    const std::size_t slash = line.find('/');
    f.header.emplace_back(line.substr(0, slash),
                          slash == std::string::npos ? "" : line.substr(slash + 1));
  }
  *rest = bytes.substr(end + std::strlen("$$HEADEREND"));
  return f;
}

CliFile parse_cli_ascii(const std::string& bytes) {
  std::string rest;
  CliFile f = parse_cli_header(bytes, &rest);
  std::vector<std::string> lines = split(rest, '\n');
  EXPECT_EQ(lines.at(0), "");  // $$HEADEREND ends its line
  EXPECT_EQ(lines.at(1), "$$GEOMETRYSTART");
  EXPECT_EQ(lines.at(lines.size() - 2), "$$GEOMETRYEND");
  EXPECT_EQ(lines.back(), "");
  for (std::size_t i = 2; i + 2 < lines.size(); ++i) {
    const std::string& line = lines[i];
    if (line.starts_with("$$LAYER/")) {
      f.layers.push_back({number(line.substr(8)), {}});
    } else {
      EXPECT_TRUE(line.starts_with("$$POLYLINE/")) << line;
      EXPECT_FALSE(f.layers.empty());
      const std::vector<std::string> v = split(line.substr(11), ',');
      CliPolyline p{int(number(v.at(0))), int(number(v.at(1))), {}};
      const auto n = static_cast<std::size_t>(number(v.at(2)));
      EXPECT_EQ(v.size(), 3 + 2 * n) << line;
      for (std::size_t k = 0; k < n && 4 + 2 * k < v.size(); ++k)
        p.points.push_back({number(v[3 + 2 * k]), number(v[4 + 2 * k])});
      f.layers.back().polylines.push_back(p);
    }
  }
  return f;
}

template <typename T>
T read_le(const std::string& bytes, std::size_t& at) {
  std::array<char, sizeof(T)> b{};
  EXPECT_LE(at + sizeof(T), bytes.size());
  if (at + sizeof(T) <= bytes.size()) std::memcpy(b.data(), bytes.data() + at, sizeof(T));
  if constexpr (std::endian::native == std::endian::big) std::reverse(b.begin(), b.end());
  at += sizeof(T);
  return std::bit_cast<T>(b);
}

CliFile parse_cli_binary(const std::string& bytes) {
  std::string rest;
  CliFile f = parse_cli_header(bytes, &rest);
  for (std::size_t at = 0; at < rest.size();) {
    const auto command = read_le<std::uint16_t>(rest, at);
    if (command == 127) {
      f.layers.push_back({read_le<float>(rest, at), {}});
    } else {
      EXPECT_EQ(command, 130) << "at byte " << at - 2 << " after $$HEADEREND";
      if (command != 130) break;
      CliPolyline p;
      p.id = read_le<std::int32_t>(rest, at);
      p.dir = read_le<std::int32_t>(rest, at);
      const auto n = read_le<std::int32_t>(rest, at);
      for (std::int32_t k = 0; k < n; ++k) {
        const float x = read_le<float>(rest, at), y = read_le<float>(rest, at);
        p.points.push_back({x, y});
      }
      EXPECT_FALSE(f.layers.empty());
      if (!f.layers.empty()) f.layers.back().polylines.push_back(p);
    }
  }
  return f;
}

/// The layers as the file says them: a $$LAYER per layer at its top, one closed polyline per
/// contour with the contour's orientation, points within `tolerance` of `stored(input)`.
template <typename Stored>
void expect_cli_matches(const CliFile& f, const std::vector<Layer>& layers, double tolerance,
                        Stored stored) {
  ASSERT_EQ(f.layers.size(), layers.size());
  for (std::size_t l = 0; l < layers.size(); ++l) {
    EXPECT_NEAR(f.layers[l].z, stored(layers[l].top), tolerance);
    ASSERT_EQ(f.layers[l].polylines.size(), layers[l].contours.size());
    for (std::size_t c = 0; c < layers[l].contours.size(); ++c) {
      const Contour& in = layers[l].contours[c];
      const CliPolyline& out = f.layers[l].polylines[c];
      EXPECT_EQ(out.id, 1);
      EXPECT_EQ(out.dir, in.area > 0 ? 1 : 0);
      ASSERT_EQ(out.points.size(), in.points.size() + 1);
      EXPECT_EQ(out.points.front(), out.points.back());  // closed by repeating the first point
      for (std::size_t k = 0; k < in.points.size(); ++k) {
        EXPECT_NEAR(out.points[k].x, stored(in.points[k].x), tolerance);
        EXPECT_NEAR(out.points[k].y, stored(in.points[k].y), tolerance);
      }
    }
  }
}

void expect_cli_header(const CliFile& f, const char* mode) {
  ASSERT_GE(f.header.size(), 2u);
  EXPECT_EQ(f.header[0].first, "$$HEADERSTART");
  EXPECT_EQ(f.header[1].first, mode);
  EXPECT_EQ(number(f.value("$$UNITS")), 1.0);
  EXPECT_EQ(f.value("$$VERSION"), "200");
  EXPECT_EQ(f.value("$$LABEL"), "1,square_hole");  // a comma would end the field
  EXPECT_EQ(f.value("$$LAYERS"), "2");
  EXPECT_EQ(f.value("$$DATE"), "(none)");  // no wall clock: the same layers, the same bytes
  const std::vector<std::string> d = split(f.value("$$DIMENSION"), ',');
  ASSERT_EQ(d.size(), 6u);
  const std::vector<double> expected{0, 0, 0, 10, 10, 0.2};
  for (std::size_t i = 0; i < 6; ++i) EXPECT_EQ(number(d[i]), expected[i]);
}

TEST(LayerFiles, CliAsciiReadsBackAsTheLayers) {
  const std::filesystem::path file = test::scratch_dir() / "part.cli";
  const std::vector<Layer> layers = two_layers();
  EXPECT_EQ(write_layers(file, options(LayerFormat::Cli), layers),
            std::vector<std::filesystem::path>{file});
  const std::string bytes = test::read_file(file);
  const CliFile f = parse_cli_ascii(bytes);
  expect_cli_header(f, "$$ASCII");
  expect_cli_matches(f, layers, 1e-6, [](double v) { return v; });
  // Byte-reproducible: nothing in the file depends on when it was written.
  const std::filesystem::path again = file.parent_path() / "again.cli";
  write_layers(again, options(LayerFormat::Cli), layers);
  EXPECT_EQ(test::read_file(again), bytes);
}

TEST(LayerFiles, CliBinaryReadsBackAsTheLayers) {
  const std::filesystem::path file = test::scratch_dir() / "part.cli";
  const std::vector<Layer> layers = two_layers();
  write_layers(file, options(LayerFormat::CliBinary), layers);
  const std::string bytes = test::read_file(file);
  const CliFile f = parse_cli_binary(bytes);
  expect_cli_header(f, "$$BINARY");
  EXPECT_EQ(bytes.find("$$GEOMETRY"), std::string::npos);
  // IEEE floats: the inputs rounded to float, bit for bit.
  expect_cli_matches(f, layers, 0, [](double v) { return double(float(v)); });
  // 2 layer commands (2 + 4 bytes), 3 polyline commands (2 + 12 bytes), 5 + 5 + 4 points.
  const std::size_t body = bytes.size() - bytes.find("$$HEADEREND") - 11;
  EXPECT_EQ(body, 2 * 6 + 3 * 14 + (5 + 5 + 4) * 8);
}

TEST(LayerFiles, CliLayerCountMustMatchItsHeader) {
  const std::filesystem::path file = test::scratch_dir() / "part.cli";
  LayerFileOptions o = options(LayerFormat::Cli);
  o.layer_count = 3;
  LayerFileWriter writer(file, o);
  for (const Layer& l : two_layers()) writer.add(l);
  EXPECT_THROW(writer.finish(), InputError);
}

// --- SVG ------------------------------------------------------------------------------------

TEST(LayerFiles, SvgHasAGroupPerLayerAndASubpathPerContour) {
  const std::filesystem::path file = test::scratch_dir() / "part.svg";
  const std::vector<Layer> layers = two_layers();
  write_layers(file, options(LayerFormat::Svg), layers);
  const std::string svg = test::read_file(file);
  EXPECT_TRUE(svg.starts_with("<?xml"));
  EXPECT_NE(svg.find("width=\"10.000000mm\" height=\"10.000000mm\" viewBox=\"0 0 10.000000 "
                     "10.000000\""),
            std::string::npos);
  EXPECT_NE(svg.find("translate(0.000000,10.000000) scale(1,-1)"), std::string::npos);
  EXPECT_NE(svg.find("<title>square,hole</title>"), std::string::npos);
  EXPECT_EQ(count(svg, "<g id=\"layer-"), layers.size());
  EXPECT_EQ(count(svg, "<g"), count(svg, "</g>"));
  EXPECT_TRUE(svg.ends_with("</svg>\n"));
  for (const Layer& l : layers) {
    const std::size_t at = svg.find("<g id=\"layer-" + std::to_string(l.index) + "\"");
    ASSERT_NE(at, std::string::npos);
    const std::string group = svg.substr(at, svg.find("</g>", at) - at);
    EXPECT_EQ(count(group, "display=\"none\""), l.index == 0 ? 0u : 1u);  // the lowest shows
    EXPECT_NE(group.find("data-top=\"" + std::string(l.index == 0 ? "0.1" : "0.2")),
              std::string::npos);
    EXPECT_EQ(count(group, "<path"), 1u);
    EXPECT_NE(group.find("fill-rule=\"nonzero\""), std::string::npos);
    EXPECT_EQ(count(group, "M "), l.contours.size());
    EXPECT_EQ(count(group, " Z"), l.contours.size());
  }
  EXPECT_NE(svg.find("M 0.123457 0.234568 L 9.876543 0.234568"), std::string::npos);
}

TEST(LayerFiles, SvgLayersAreOneVisibleFilePerLayer) {
  const std::filesystem::path dir = test::scratch_dir();
  const std::vector<Layer> layers = two_layers();
  const auto files = write_layers(dir, options(LayerFormat::SvgLayers), layers);
  ASSERT_EQ(files.size(), 2u);
  EXPECT_EQ(files[0], dir / "layer_00000.svg");
  EXPECT_EQ(files[1], dir / "layer_00001.svg");
  for (std::size_t i = 0; i < 2; ++i) {
    const std::string svg = test::read_file(files[i]);
    EXPECT_EQ(count(svg, "<g id=\"layer-" + std::to_string(i) + "\""), 1u);
    EXPECT_EQ(count(svg, "<g id=\"layer-"), 1u);
    EXPECT_EQ(count(svg, "display=\"none\""), 0u);
    EXPECT_EQ(count(svg, "M "), layers[i].contours.size());
    EXPECT_TRUE(svg.ends_with("</svg>\n"));
  }
}

// --- PNG ------------------------------------------------------------------------------------

test::Png decode_grey(const std::string& bytes) {
  return test::decode_png(bytes, 1);
}

/// A layer whose plane field is phi(x, y) on nodes every `spacing` over [x0, x1] × [y0, y1].
template <typename Phi>
Layer field_layer(std::uint64_t index, double x0, double y0, double x1, double y1, double spacing,
                  Phi phi) {
  Layer l;
  l.index = index;
  l.bottom = 0;
  l.top = 0.1;
  l.z = 0.05;
  Grid& g = l.field.grid;
  g.origin = {x0, y0, l.z};
  g.spacing = spacing;
  g.dims = {int(std::lround((x1 - x0) / spacing)) + 1, int(std::lround((y1 - y0) / spacing)) + 1,
            1};
  for (int j = 0; j < g.dims[1]; ++j)
    for (int i = 0; i < g.dims[0]; ++i)
      l.field.values.push_back(float(phi(g.coordinate(0, i), g.coordinate(1, j))));
  return l;
}

TEST(LayerFiles, PngOfADiskCoversItsArea) {
  const std::filesystem::path dir = test::scratch_dir();
  constexpr double kRadius = 3, kPixel = 0.05;
  const Layer disk = field_layer(
      7, 0, 0, 10, 10, 0.1, [](double x, double y) { return std::hypot(x - 5, y - 4) - kRadius; });
  LayerFileOptions o = options(LayerFormat::PngLayers);
  o.pixel = kPixel;
  const auto files = write_layers(dir, o, {disk});
  ASSERT_EQ(files, std::vector<std::filesystem::path>{dir / "layer_00007.png"});
  const test::Png png = decode_grey(test::read_file(files[0]));
  ASSERT_EQ(png.width, 200);  // 10 mm / 0.05 mm, not 201 for the quotient's rounding
  ASSERT_EQ(png.height, 200);
  EXPECT_EQ(png.phys_x, 20000u);  // pixels per metre
  EXPECT_EQ(png.phys_y, 20000u);
  EXPECT_EQ(png.phys_unit, 1);
  // The centre (5, 4) is column 100, row (10 − 4) / 0.05 = 120 from the top.
  EXPECT_EQ(png.value(100, 120), 255);
  EXPECT_EQ(png.value(99, 119), 255);
  EXPECT_EQ(png.value(5, 5), 0);
  EXPECT_EQ(png.value(100, 120 - 70), 0);    // 3.5 mm above the centre
  EXPECT_EQ(png.value(100, 120 + 50), 255);  // 2.5 mm below it (a flipped image fails here)
  double area = 0;
  for (const std::uint8_t v : png.pixels) area += v / 255.0 * kPixel * kPixel;
  EXPECT_NEAR(area, std::numbers::pi * kRadius * kRadius, 0.02 * std::numbers::pi * 9);
  long grey =
      std::count_if(png.pixels.begin(), png.pixels.end(), [](int v) { return v > 0 && v < 255; });
  EXPECT_GT(grey, 0);  // antialiased
}

TEST(LayerFiles, PngIsBlackOutsideTheFieldAndRowZeroIsTheTop) {
  const std::filesystem::path dir = test::scratch_dir();
  // Solid below y = 7.1 (φ = y − 7.1), known on [2, 8]²; the image covers [0, 10]².
  const Layer half = field_layer(0, 2, 2, 8, 8, 0.5, [](double, double y) { return y - 7.1; });
  LayerFileOptions o = options(LayerFormat::PngLayers);
  o.pixel = 0.25;
  const test::Png png = decode_grey(test::read_file(write_layers(dir, o, {half}).at(0)));
  ASSERT_EQ(png.width, 40);
  ASSERT_EQ(png.height, 40);
  EXPECT_EQ(png.value(20, 20), 255);  // (5.125, 4.875): inside the field, below y = 7
  EXPECT_EQ(png.value(20, 8), 0);     // y = 7.875: above the boundary
  EXPECT_EQ(png.value(4, 20), 0);     // x = 1.125: outside the field's nodes
  EXPECT_EQ(png.value(20, 36), 0);    // y = 0.875: outside the field's nodes
  // Row 11's centre is at y = 7.125, φ = 0.025 = 0.1 pixel: coverage 0.5 − 0.1. Row 12's, at
  // y = 6.875, is 0.9 pixel inside: clamped to 1.
  EXPECT_EQ(png.value(20, 11), 102);
  EXPECT_EQ(png.value(20, 12), 255);
  EXPECT_EQ(png.value(20, 10), 0);
}

TEST(LayerFiles, PngWithoutAFieldIsRefusedUnlessTheLayerIsEmpty) {
  const std::filesystem::path dir = test::scratch_dir();
  LayerFileWriter writer(dir, options(LayerFormat::PngLayers));
  Layer empty;
  writer.add(empty);
  const test::Png png = decode_grey(test::read_file(dir / "layer_00000.png"));
  EXPECT_EQ(std::count(png.pixels.begin(), png.pixels.end(), 0), 200 * 200);
  EXPECT_THROW(writer.add(two_layers()[1]), InputError);
}

// --- options --------------------------------------------------------------------------------

TEST(LayerFiles, FormatNamesRoundTripAndUnknownOnesAreRefused) {
  for (LayerFormat f : {LayerFormat::Cli, LayerFormat::CliBinary, LayerFormat::Svg,
                        LayerFormat::SvgLayers, LayerFormat::PngLayers})
    EXPECT_EQ(layer_format_from_name(layer_format_name(f)), f);
  EXPECT_EQ(layer_format_from_name("png"), LayerFormat::PngLayers);
  EXPECT_THROW(layer_format_from_name("gcode"), InputError);
  EXPECT_THROW(layer_format_from_name("CLI"), InputError);
  EXPECT_FALSE(writes_folder(LayerFormat::Cli));
  EXPECT_FALSE(writes_folder(LayerFormat::Svg));
  EXPECT_TRUE(writes_folder(LayerFormat::SvgLayers));
  EXPECT_TRUE(writes_folder(LayerFormat::PngLayers));
}

TEST(LayerFiles, BadOptionsAreRefusedBeforeAnythingIsWritten) {
  const std::filesystem::path dir = test::scratch_dir();
  for (const double pixel : {0.0, -0.1, std::nan("")}) {
    LayerFileOptions o = options(LayerFormat::PngLayers);
    o.pixel = pixel;
    EXPECT_THROW(LayerFileWriter(dir, o), InputError) << pixel;
  }
  LayerFileOptions huge = options(LayerFormat::PngLayers);
  huge.pixel = 10.0 / 40000;  // 40000 pixels a side
  try {
    LayerFileWriter(dir, huge);
    ADD_FAILURE() << "an image of 40000 pixels a side was accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("a pixel of at least"), std::string::npos) << e.what();
  }
  LayerFileOptions empty = options(LayerFormat::Cli);
  empty.bounds = {};
  EXPECT_THROW(LayerFileWriter(dir / "a.cli", empty), InputError);
  EXPECT_TRUE(std::filesystem::is_empty(dir));
  // A folder format needs a folder; a file format a place it can create a file.
  EXPECT_THROW(LayerFileWriter(dir / "missing", options(LayerFormat::PngLayers)), IoError);
  EXPECT_THROW(LayerFileWriter(dir / "missing" / "a.cli", options(LayerFormat::Cli)), IoError);
}

}  // namespace

// --- Parts where printers put them ----------------------------------------------------------

// A sliced part anywhere on a bed (and far beyond: 10 m), at fine voxels, reads back from
// ASCII CLI (six decimals), binary CLI (floats) and SVG with contours that neither cross nor
// touch, as the file holds them, and no point repeated; or the job is refused before any work.
TEST(LayerFiles, SlicesAnywhereReadBackAsSimpleContours) {
  const auto dir = test::scratch_dir();
  int written = 0, refused = 0;
  for (const double offset : {0.0, 150.0, 1000.0, -1000.0, 1e4, 1e5}) {
    const TriangleSoup ball = test::make_sphere({offset, offset + 7, 3}, 1.5, 3);
    for (const double voxel : {0.05, 0.01, 0.005}) {
      for (const LayerFormat format : {LayerFormat::Cli, LayerFormat::CliBinary}) {
        const auto path = dir / "part.cli";
        FillOptions fill = test::gyroid_options(1, voxel);
        const Box3 box = bounding_box(ball);
        LayerFileOptions files{.format = format, .bounds = box, .layer = 0.2};
        files.layer_count = layer_count(box, {.layer = 0.2});
        try {
          std::optional<LayerFileWriter> writer;
          slice(ball, fill, {.layer = 0.2, .rounding = layer_rounding(format)},
                [&](const Layer& layer) {
                  if (!writer) writer.emplace(path, files);
                  writer->add(layer);
                });
          writer->finish();
        } catch (const InputError& e) {
          ++refused;
          EXPECT_NE(
              std::string(e.what()).find("or write ASCII CLI or SVG, which hold six decimals"),
              std::string::npos)
              << e.what();
          continue;
        }
        ++written;
        const std::string bytes = test::read_file(path);
        const CliFile f =
            format == LayerFormat::Cli ? parse_cli_ascii(bytes) : parse_cli_binary(bytes);
        ASSERT_EQ(f.layers.size(), files.layer_count);
        std::size_t points = 0;
        for (const CliLayer& layer : f.layers) {
          std::vector<Contour> contours;
          for (const CliPolyline& p : layer.polylines) {
            ASSERT_GE(p.points.size(), 4u);
            EXPECT_TRUE(p.points.front().x == p.points.back().x &&
                        p.points.front().y == p.points.back().y);
            contours.push_back(contour({p.points.begin(), p.points.end() - 1}));
            for (std::size_t k = 0; k + 1 < p.points.size(); ++k)
              ASSERT_FALSE(p.points[k].x == p.points[k + 1].x && p.points[k].y == p.points[k + 1].y)
                  << "a point repeated at offset " << offset << ", voxel " << voxel;
            points += p.points.size();
          }
          EXPECT_EQ(count_contour_defects(contours, voxel), 0u)
              << "offset " << offset << ", voxel " << voxel << ", " << layer_format_name(format)
              << ", layer at z = " << layer.z;
        }
        EXPECT_GT(points, 0u);
      }
    }
  }
  EXPECT_GT(written, 20);
  EXPECT_GT(refused, 0);  // floats at 100 m hold a coordinate every 0.008 mm
}
