// render_png: draws a mesh to a PNG, for the docs' catalogue (scripts/catalogue.sh) and for
// looking at a fill on a machine without a viewer.
//
//   render_png IN OUT.png [--size 640] [--view AZIMUTH ELEVATION] [--clip x|y|z VALUE]
//                         [--color R G B] [--background R G B]
//
// IN is anything tpmsfill reads (tpmsfill::read_mesh_file). The camera is orthographic, looks at
// the centre of the bounding box (of what --clip leaves) and is fitted so that box's projection
// fills the picture less a margin of kMargin of --size on every side; --size is the longer side
// of the picture, the other follows the projection's aspect. z is up: --view 0 0 looks along +y
// (x to the right), azimuth turns the camera counter-clockwise about z seen from above,
// elevation raises it (90 looks straight down). Past ±90 the camera goes on over the top (or
// under the bottom) and the picture turns upside down: 0 -155 looks from +y and slightly
// below, with -z up. Default 35 25.
//
// Phases: bin the triangles by strips of sample rows (points are projected where used, not
// stored); rasterize the strips in parallel into a 2x2-supersampled buffer that keeps, per
// sample, the nearest triangle (edge functions, per-sample depth and, with --clip, the
// per-sample clip coordinate, so a cut is exact to the sample and not to the triangle); shade
// each sample from its triangle's normal (ambient + two directional Lambert lights fixed to the
// camera), average each 2x2 block, encode an 8-bit RGB PNG (detail::encode_png: adaptive row
// filters, zlib) and write it atomically (tpmsfill::write_file_atomically). Each sample is
// written by one strip, in file order, so the picture does not depend on the number of threads.
//
// Back faces are what the eye meets first only where it looks into a closed solid, through a
// --clip cut: they are drawn flat in a darker, warmer tint of the colour, so a cut reads as a
// solid section.
//
// Exit code 0: written; 2: bad arguments or unreadable input; 1: anything else (nothing left
// after --clip, the PNG could not be written). Errors are one line on stderr.
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <cctype>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <limits>
#include <numbers>
#include <stdexcept>
#include <string>
#include <string_view>
#include <tpmsfill/error.hpp>
#include <tpmsfill/io.hpp>
#include <tpmsfill/types.hpp>
#include <vector>

#include "detail/png.hpp"

using namespace tpmsfill;

namespace {

constexpr double kMargin = 0.04;  ///< free border on every side, as a fraction of --size
constexpr int kSupersample = 2;   ///< samples per pixel along each axis
constexpr double kAmbient = 0.25;
constexpr double kKeyLight = 0.7;
constexpr double kFillLight = 0.25;

struct Rgb {
  double r = 0, g = 0, b = 0;
};

struct Options {
  std::string input, output;
  int size = 640;                       ///< longer side of the picture, pixels
  double azimuth = 35, elevation = 25;  ///< degrees
  int clip_axis = -1;                   ///< 0, 1, 2 for x, y, z; -1: no clip
  double clip_value = 0;                ///< mm: fragments with coordinate > this are discarded
  Rgb color{178, 196, 222};             ///< front faces, 0..255
  Rgb background{255, 255, 255};
};

/// A usage error: bad arguments (exit 2).
struct UsageError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

constexpr const char* kUsage =
    "usage: render_png IN OUT.png [--size 640] [--view AZIMUTH ELEVATION] [--clip x|y|z VALUE] "
    "[--color R G B] [--background R G B]";

double parse_number(std::string_view flag, std::string_view text) {
  double value = 0;
  auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), value);
  if (ec != std::errc{} || end != text.data() + text.size() || !std::isfinite(value))
    throw UsageError(std::string(flag) + ": '" + std::string(text) + "' is not a number");
  return value;
}

Options parse_args(int argc, char** argv) {
  Options o;
  std::vector<std::string> positional;
  auto take = [&](int& i, std::string_view flag, int n) {
    if (i + n >= argc)
      throw UsageError(std::string(flag) + " needs " + std::to_string(n) + " value" +
                       (n > 1 ? "s" : ""));
    std::vector<double> values;
    for (int k = 1; k <= n; ++k) values.push_back(parse_number(flag, argv[i + k]));
    i += n;
    return values;
  };
  auto color = [](std::string_view flag, const std::vector<double>& v) {
    for (double c : v)
      if (c < 0 || c > 255) throw UsageError(std::string(flag) + ": components are 0 to 255");
    return Rgb{v[0], v[1], v[2]};
  };
  for (int i = 1; i < argc; ++i) {
    const std::string_view arg = argv[i];
    if (arg == "-h" || arg == "--help") {
      std::printf("%s\n", kUsage);
      std::exit(0);
    }
    if (arg == "--size") {
      const double s = take(i, arg, 1)[0];
      if (s < 16 || s > 16384 || s != std::floor(s))
        throw UsageError("--size: a whole number of pixels from 16 to 16384");
      o.size = static_cast<int>(s);
    } else if (arg == "--view") {
      const std::vector<double> v = take(i, arg, 2);
      o.azimuth = v[0];
      o.elevation = v[1];
      if (std::abs(o.elevation) > 180) throw UsageError("--view: elevation is -180 to 180 degrees");
    } else if (arg == "--clip") {
      if (i + 2 >= argc) throw UsageError("--clip needs an axis (x, y or z) and a value");
      const std::string_view axis = argv[i + 1];
      if (axis != "x" && axis != "y" && axis != "z")
        throw UsageError("--clip: '" + std::string(axis) + "' is not x, y or z");
      o.clip_axis = axis[0] - 'x';
      o.clip_value = parse_number(arg, argv[i + 2]);
      i += 2;
    } else if (arg == "--color") {
      o.color = color(arg, take(i, arg, 3));
    } else if (arg == "--background") {
      o.background = color(arg, take(i, arg, 3));
    } else if (arg.starts_with("-") && arg.size() > 1 &&
               !std::isdigit(static_cast<unsigned char>(arg[1]))) {
      throw UsageError("unknown option '" + std::string(arg) + "' (render_png --help)");
    } else {
      positional.emplace_back(arg);
    }
  }
  if (positional.size() != 2) throw UsageError(kUsage);
  o.input = positional[0];
  o.output = positional[1];
  return o;
}

Vec3 normalized(Vec3 v) {
  const double n = norm(v);
  return n > 0 ? (1.0 / n) * v : v;
}

/// The bounding box of the part of `soup` with coordinate[axis] <= value (all of it when
/// axis < 0): kept corners plus the points where edges cross the plane.
Box3 clipped_box(const TriangleSoup& soup, int axis, double value) {
  constexpr double inf = std::numeric_limits<double>::infinity();
  std::array<double, 3> lo{inf, inf, inf}, hi{-inf, -inf, -inf};
  auto extend = [&](Vec3 p) {
    for (int k = 0; k < 3; ++k) {
      lo[k] = std::min(lo[k], p[k]);
      hi[k] = std::max(hi[k], p[k]);
    }
  };
  for (const Triangle& t : soup.triangles)
    for (int e = 0; e < 3; ++e) {
      const Vec3 a = soup.points[t[e]];
      if (axis < 0) {
        extend(a);
        continue;
      }
      const Vec3 b = soup.points[t[(e + 1) % 3]];
      if (a[axis] <= value) extend(a);
      if ((a[axis] < value) != (b[axis] < value) && a[axis] != b[axis])
        extend(a + ((value - a[axis]) / (b[axis] - a[axis])) * (b - a));
    }
  Box3 box;
  box.min = {lo[0], lo[1], lo[2]};
  box.max = {hi[0], hi[1], hi[2]};
  return box;
}

/// Orthographic camera. (right, up, toward) is right-handed; `toward` points from the scene to
/// the camera, so a larger depth is nearer. Raster coordinates are in samples, y up.
struct Camera {
  Vec3 right, up, toward, center;
  double scale = 1;           ///< samples per mm
  int width = 0, height = 0;  ///< output pixels
  int samples_x() const { return width * kSupersample; }
  int samples_y() const { return height * kSupersample; }
};

Camera fit_camera(const Options& o, const Box3& box) {
  const double az = o.azimuth * std::numbers::pi / 180, el = o.elevation * std::numbers::pi / 180;
  Camera c;
  c.toward = {std::sin(az) * std::cos(el), -std::cos(az) * std::cos(el), std::sin(el)};
  c.right = {std::cos(az), std::sin(az), 0};
  c.up = cross(c.toward, c.right);
  c.center = box.centre();
  double ex = 0, ey = 0;  // half extents of the box's projection, mm
  for (int corner = 0; corner < 8; ++corner) {
    const Vec3 p{corner & 1 ? box.max.x : box.min.x, corner & 2 ? box.max.y : box.min.y,
                 corner & 4 ? box.max.z : box.min.z};
    ex = std::max(ex, std::abs(dot(p - c.center, c.right)));
    ey = std::max(ey, std::abs(dot(p - c.center, c.up)));
  }
  const double longer = 2 * std::max(ex, ey);
  if (!(longer > 0)) throw std::runtime_error(o.input + ": the mesh has no extent in this view");
  const double margin = std::round(kMargin * o.size);
  const double pixels_per_mm = (o.size - 2 * margin) / longer;
  c.width = ex >= ey ? o.size : static_cast<int>(std::ceil(2 * ex * pixels_per_mm + 2 * margin));
  c.height = ey > ex ? o.size : static_cast<int>(std::ceil(2 * ey * pixels_per_mm + 2 * margin));
  c.scale = pixels_per_mm * kSupersample;
  return c;
}

/// Per sample: depth of the nearest fragment and its triangle (kNone: background; the top bit
/// marks a back face).
struct Frame {
  static constexpr std::uint32_t kNone = 0xffffffffu;
  static constexpr std::uint32_t kBack = 0x80000000u;
  std::vector<float> depth;
  std::vector<std::uint32_t> face;
};

/// A point in raster space (samples, y up; z: depth, larger is nearer) with its coordinate
/// along the clip axis (mm).
struct Projected {
  double x, y, z, clip;
};

/// The edge function of the directed edge p -> r: at(s) is twice the signed area of (p, r, s),
/// positive when s lies to the left. Its coefficients are computed with p and r in a fixed
/// order and negated when swapped (rounding is symmetric in sign), so the two triangles sharing
/// an edge get exactly opposite values at every sample and a sample on it is never missed.
struct Edge {
  double a = 0, b = 0, c = 0;
  Edge(const Projected& p, const Projected& r) {
    const bool swap = r.x < p.x || (r.x == p.x && r.y < p.y);
    const Projected& u = swap ? r : p;
    const Projected& v = swap ? p : r;
    a = u.y - v.y;
    b = v.x - u.x;
    c = -(a * u.x + b * u.y);
    if (swap) flip();
  }
  void flip() {
    a = -a;
    b = -b;
    c = -c;
  }
  /// Value at (sx, sy), given row = row_part(sy): split so a row's share is computed once.
  double row_part(double sy) const { return b * sy + c; }
  double at(double sx, double row) const { return a * sx + row; }
};

constexpr int kStripRows = 32;  ///< sample rows per parallel task

// Samples sit at (i + 0.5, j + 0.5); a triangle spanning [lo, hi] on an axis covers at most
// samples first_sample(lo, ...) to last_sample(hi, ...), clamped to [low, high]. Written with
// casts, not std::ceil/floor, which are calls on baseline x86-64.
inline int first_sample(double lo, int low) {
  const double u = lo - 0.5;
  if (!(u > low)) return low;
  if (u > 1 << 30) return 1 << 30;
  const int i = static_cast<int>(u);  // u > 0: truncation is floor
  return i < u ? i + 1 : i;
}
inline int last_sample(double hi, int high) {
  const double u = hi - 0.5;
  if (!(u < high)) return high;
  if (u < -1) return -1;
  const int i = static_cast<int>(u);
  return i > u ? i - 1 : i;
}

Frame rasterize(const TriangleSoup& soup, const Camera& cam, int clip_axis, double clip_value) {
  const int W = cam.samples_x(), H = cam.samples_y();
  if (soup.triangles.size() >= Frame::kBack) throw std::runtime_error("too many triangles");
  Frame f;
  f.depth.assign(static_cast<std::size_t>(W) * H, -std::numeric_limits<float>::infinity());
  f.face.assign(f.depth.size(), Frame::kNone);

  // Points are projected where triangles use them, not stored: an STL soup has three per
  // triangle, and a projected copy of 6 million would cost more than the picture.
  auto project = [&](std::uint32_t v) {
    const Vec3 d = soup.points[v] - cam.center;
    return Projected{dot(d, cam.right) * cam.scale + 0.5 * W, dot(d, cam.up) * cam.scale + 0.5 * H,
                     dot(d, cam.toward) * cam.scale,
                     clip_axis < 0 ? 0.0 : soup.points[v][clip_axis]};
  };

  // Bin the triangles by the strips of sample rows their bounding boxes touch (count, scan,
  // fill: each bin keeps the triangles in file order, so depth ties resolve as in one pass).
  const int strips = (H + kStripRows - 1) / kStripRows;
  auto strip_range = [&](const Triangle& t) -> std::pair<int, int> {
    const Projected a = project(t[0]), b = project(t[1]), c = project(t[2]);
    if (clip_axis >= 0 && a.clip > clip_value && b.clip > clip_value && c.clip > clip_value)
      return {1, 0};
    const double lo = std::min({a.y, b.y, c.y}), hi = std::max({a.y, b.y, c.y});
    if (!(hi >= 0.5 && lo <= H - 0.5)) return {1, 0};  // off the picture, or not finite
    const int j0 = first_sample(lo, 0), j1 = last_sample(hi, H - 1);
    return {j0 / kStripRows, j1 / kStripRows};
  };
  std::vector<std::size_t> start(strips + 1, 0);
  for (const Triangle& t : soup.triangles) {
    const auto [s0, s1] = strip_range(t);
    for (int s = s0; s <= s1; ++s) ++start[s + 1];
  }
  for (int s = 0; s < strips; ++s) start[s + 1] += start[s];
  std::vector<std::uint32_t> binned(start[strips]);
  {
    std::vector<std::size_t> next(start.begin(), start.end() - 1);
    for (std::uint32_t t = 0; t < soup.triangles.size(); ++t) {
      const auto [s0, s1] = strip_range(soup.triangles[t]);
      for (int s = s0; s <= s1; ++s) binned[next[s]++] = t;
    }
  }

  tbb::parallel_for(0, strips, [&](int strip) {
    const int row0 = strip * kStripRows, row1 = std::min(H, row0 + kStripRows) - 1;
    for (std::size_t n = start[strip]; n < start[strip + 1]; ++n) {
      const std::uint32_t t = binned[n];
      const Triangle& tri = soup.triangles[t];
      const Projected a = project(tri[0]), b = project(tri[1]), c = project(tri[2]);
      const bool clip_each =
          clip_axis >= 0 && (a.clip > clip_value || b.clip > clip_value || c.clip > clip_value);
      Edge ea(b, c), eb(c, a), ec(a, b);
      double area = ec.at(c.x, ec.row_part(c.y));
      if (area == 0 || !std::isfinite(area)) continue;
      // Front faces wind counter-clockwise in raster space (x right, y up); for back faces
      // the edge functions turn round, so inside is where all three are >= 0 either way.
      const bool back = area < 0;
      if (back) {
        ea.flip();
        eb.flip();
        ec.flip();
        area = -area;
      }
      const double inv = 1.0 / area;
      const std::uint32_t id = back ? (t | Frame::kBack) : t;
      const int x0 = first_sample(std::min({a.x, b.x, c.x}), 0);
      const int x1 = last_sample(std::max({a.x, b.x, c.x}), W - 1);
      const int y0 = first_sample(std::min({a.y, b.y, c.y}), row0);
      const int y1 = last_sample(std::max({a.y, b.y, c.y}), row1);
      for (int j = y0; j <= y1; ++j) {
        const double sy = j + 0.5;
        const double ra = ea.row_part(sy), rb = eb.row_part(sy), rc = ec.row_part(sy);
        for (int i = x0; i <= x1; ++i) {
          const double sx = i + 0.5;
          const double wa = ea.at(sx, ra), wb = eb.at(sx, rb), wc = ec.at(sx, rc);
          if (wa < 0 || wb < 0 || wc < 0) continue;
          const float z = static_cast<float>((wa * a.z + wb * b.z + wc * c.z) * inv);
          const std::size_t k = static_cast<std::size_t>(j) * W + i;
          if (z <= f.depth[k]) continue;
          if (clip_each && (wa * a.clip + wb * b.clip + wc * c.clip) * inv > clip_value) continue;
          f.depth[k] = z;
          f.face[k] = id;
        }
      }
    }
  });
  return f;
}

/// 8-bit RGB image, rows top to bottom.
struct Image {
  int width = 0, height = 0;
  std::vector<std::uint8_t> rgb;
};

Image shade(const TriangleSoup& soup, const Camera& cam, const Frame& f, const Options& o) {
  // Lights fixed to the camera: a key light from the upper left, a fill light from the right.
  const Vec3 key = normalized(-0.7 * cam.right + 0.7 * cam.up + 0.4 * cam.toward);
  const Vec3 fill = normalized(0.3 * cam.right - 0.2 * cam.up + 0.9 * cam.toward);
  // A back face is what the eye meets first only where it looks into the solid, through a
  // --clip cut (for a closed mesh): exactly where a section cap would be. It is drawn flat, in
  // a darker and warmer tint of the colour, so a cut reads as a solid section.
  const Rgb cap{0.35 * o.color.r + 70, 0.35 * o.color.g + 20, 0.35 * o.color.b + 10};
  auto sample_color = [&](std::uint32_t id) -> Rgb {
    if (id == Frame::kNone) return o.background;
    if (id & Frame::kBack) return cap;
    const Triangle& t = soup.triangles[id];
    const Vec3 n = normalized(
        cross(soup.points[t[1]] - soup.points[t[0]], soup.points[t[2]] - soup.points[t[0]]));
    const double light = kAmbient + kKeyLight * std::max(0.0, dot(n, key)) +
                         kFillLight * std::max(0.0, dot(n, fill));
    return {o.color.r * light, o.color.g * light, o.color.b * light};
  };

  Image img{cam.width, cam.height, {}};
  img.rgb.resize(static_cast<std::size_t>(img.width) * img.height * 3);
  const int W = cam.samples_x(), H = cam.samples_y();
  tbb::parallel_for(0, img.height, [&](int y) {
    for (int x = 0; x < img.width; ++x) {
      Rgb sum;
      for (int dy = 0; dy < kSupersample; ++dy)
        for (int dx = 0; dx < kSupersample; ++dx) {
          // Raster rows go up, image rows go down.
          const int sj = H - 1 - (y * kSupersample + dy), si = x * kSupersample + dx;
          const Rgb c = sample_color(f.face[static_cast<std::size_t>(sj) * W + si]);
          sum.r += c.r;
          sum.g += c.g;
          sum.b += c.b;
        }
      const double n = kSupersample * kSupersample;
      std::uint8_t* p = &img.rgb[(static_cast<std::size_t>(y) * img.width + x) * 3];
      p[0] = static_cast<std::uint8_t>(std::clamp(std::lround(sum.r / n), 0L, 255L));
      p[1] = static_cast<std::uint8_t>(std::clamp(std::lround(sum.g / n), 0L, 255L));
      p[2] = static_cast<std::uint8_t>(std::clamp(std::lround(sum.b / n), 0L, 255L));
    }
  });
  return img;
}

}  // namespace

int main(int argc, char** argv) {
  try {
    const Options o = parse_args(argc, argv);
    TriangleSoup soup;
    try {
      soup = read_mesh_file(o.input).soup;
    } catch (const Error& e) {  // unreadable input: exit 2, as tpmsfill's own commands
      std::fprintf(stderr, "render_png: %s\n", e.what());
      return 2;
    }
    const Box3 box = clipped_box(soup, o.clip_axis, o.clip_value);
    if (box.empty()) {
      std::fprintf(stderr, "render_png: %s: nothing is left after --clip %c %g\n", o.input.c_str(),
                   'x' + o.clip_axis, o.clip_value);
      return 1;
    }
    const Camera cam = fit_camera(o, box);
    const Frame frame = rasterize(soup, cam, o.clip_axis, o.clip_value);
    const Image img = shade(soup, cam, frame, o);
    write_file_atomically(o.output, detail::encode_png(img.width, img.height, 3, img.rgb.data()));
    return 0;
  } catch (const UsageError& e) {
    std::fprintf(stderr, "render_png: %s\n", e.what());
    return 2;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "render_png: %s\n", e.what());
    return 1;
  }
}
