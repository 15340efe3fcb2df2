// Stage "render": camera, rasterizer and shading (this file), marks and legend (render_marks.cpp).
#include "tpmsfill/render.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <limits>
#include <numbers>
#include <string>
#include <utility>

#include "core/parallel.hpp"
#include "io/png.hpp"
#include "mesh/internal/render_frame.hpp"
#include "mesh/soup_indices.hpp"
#include "tpmsfill/error.hpp"
#include "tpmsfill/io.hpp"

namespace tpmsfill {

using detail::ClipTest;
using detail::Frame;
using detail::kSupersample;

namespace {

constexpr double kMargin = 0.04;  ///< free border on every side, as a fraction of the size
constexpr double kAmbient = 0.25;
constexpr double kKeyLight = 0.7;
constexpr double kFillLight = 0.25;
constexpr int kMinSize = 16, kMaxSize = 16384;

Vec3 normalized(Vec3 v) {
  const double n = norm(v);
  return n > 0 ? (1.0 / n) * v : v;
}

void require_options(const TriangleSoup& soup, const RenderOptions& o) {
  auto side = [](int pixels) { return pixels >= kMinSize && pixels <= kMaxSize; };
  if (!side(o.width) || (o.height != 0 && !side(o.height)))
    throw InputError("render: a picture's sides are 16 to 16384 pixels");
  if (!std::isfinite(o.view.azimuth) || !(std::abs(o.view.elevation) <= 180))
    throw InputError("render: the view's elevation is -180 to 180 degrees");
  if (o.clip.axis < -1 || o.clip.axis > 2 || !std::isfinite(o.clip.position) || o.clip.side < -1 ||
      o.clip.side > 1)
    throw InputError("render: a clip is an axis 0, 1 or 2, a finite position and a side");
  if (soup.triangles.empty()) throw InputError("render: the mesh has no triangles");
}

/// Calls f(p) for what the clip leaves: kept corners plus the points where edges cross the
/// plane.
template <class F>
void for_kept_points(const TriangleSoup& soup, const ClipTest& clip, const F& f) {
  for (const Triangle& t : soup.triangles)
    for (int e = 0; e < 3; ++e) {
      const Vec3 a = soup.points[t[e]];
      if (clip.axis < 0) {
        f(a);
        continue;
      }
      const Vec3 b = soup.points[t[(e + 1) % 3]];
      const double va = clip.value(a), vb = clip.value(b);
      if (va <= clip.limit) f(a);
      if ((va < clip.limit) != (vb < clip.limit) && va != vb)
        f(a + ((clip.limit - va) / (vb - va)) * (b - a));
    }
}

/// The box of what the clip leaves in the camera's frame (right, up, toward): the picture is
/// framed on the mesh's own outline, not on its 3D box's corners, which an oblique view
/// projects well outside it (a quarter to half of the frame was left empty).
Box3 view_box(const TriangleSoup& soup, const ClipTest& clip, const Camera& c) {
  Box3 box;
  for_kept_points(soup, clip, [&](Vec3 p) {
    box.extend({dot(p, c.right), dot(p, c.up), dot(p, c.toward)});
  });
  return box;
}

// --- rasterizing --------------------------------------------------------------------------

/// A point in raster space (samples, y up; z: depth, larger is nearer) with its clip value.
struct Projected {
  double x, y, z, clip;
};

/// The edge function of the directed edge p -> r: at(s) is twice the signed area of (p, r, s),
/// positive when s lies to the left. Its coefficients are computed with p and r in a fixed
/// order and negated when swapped (rounding is symmetric in sign), so the two triangles sharing
/// an edge get exactly opposite values at every sample and a sample on it is never missed.
struct EdgeFunction {
  double a = 0, b = 0, c = 0;
  EdgeFunction(const Projected& p, const Projected& r) {
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

/// Projects points where triangles use them (not stored: an STL soup has three per triangle,
/// and a projected copy of 6 million would cost more than the picture).
struct Projector {
  const TriangleSoup& soup;
  const Camera& cam;
  const ClipTest& clip;
  double scale, half_w, half_h;
  Projector(const TriangleSoup& s, const Camera& c, const ClipTest& k)
      : soup(s),
        cam(c),
        clip(k),
        scale(c.pixels_per_mm * kSupersample),
        half_w(0.5 * c.width * kSupersample),
        half_h(0.5 * c.height * kSupersample) {}
  Projected operator()(std::uint32_t v) const {
    const Vec3 d = soup.points[v] - cam.centre;
    return {dot(d, cam.right) * scale + half_w, dot(d, cam.up) * scale + half_h,
            dot(d, cam.toward) * scale, clip.axis < 0 ? 0.0 : clip.value(soup.points[v])};
  }
};

/// The triangles by the strips of sample rows their bounding boxes touch (count, scan, fill:
/// each bin keeps the triangles in file order, so depth ties resolve as in one pass).
struct Bins {
  std::vector<std::size_t> start;  ///< per strip, and one past the last
  std::vector<std::uint32_t> triangles;
};

Bins bin_triangles(const TriangleSoup& soup, const Projector& project, const ClipTest& clip,
                   int strips, int rows) {
  auto strip_range = [&](const Triangle& t) -> std::pair<int, int> {
    const Projected a = project(t[0]), b = project(t[1]), c = project(t[2]);
    if (clip.axis >= 0 && a.clip > clip.limit && b.clip > clip.limit && c.clip > clip.limit)
      return {1, 0};
    const double lo = std::min({a.y, b.y, c.y}), hi = std::max({a.y, b.y, c.y});
    if (!(hi >= 0.5 && lo <= rows - 0.5)) return {1, 0};  // off the picture, or not finite
    return {first_sample(lo, 0) / kStripRows, last_sample(hi, rows - 1) / kStripRows};
  };
  Bins bins;
  bins.start.assign(static_cast<std::size_t>(strips) + 1, 0);
  for (const Triangle& t : soup.triangles) {
    const auto [s0, s1] = strip_range(t);
    for (int s = s0; s <= s1; ++s) ++bins.start[s + 1];
  }
  for (int s = 0; s < strips; ++s) bins.start[s + 1] += bins.start[s];
  bins.triangles.resize(bins.start[strips]);
  std::vector<std::size_t> next(bins.start.begin(), bins.start.end() - 1);
  for (std::uint32_t t = 0; t < soup.triangles.size(); ++t) {
    const auto [s0, s1] = strip_range(soup.triangles[t]);
    for (int s = s0; s <= s1; ++s) bins.triangles[next[s]++] = t;
  }
  return bins;
}

/// Draws triangle t into the rows [row0, row1] of the frame.
void rasterize_triangle(const TriangleSoup& soup, const Projector& project, const ClipTest& clip,
                        std::uint32_t t, int row0, int row1, Frame& f) {
  const int W = f.width;
  const Triangle& tri = soup.triangles[t];
  const Projected a = project(tri[0]), b = project(tri[1]), c = project(tri[2]);
  const bool clip_each =
      clip.axis >= 0 && (a.clip > clip.limit || b.clip > clip.limit || c.clip > clip.limit);
  EdgeFunction ea(b, c), eb(c, a), ec(a, b);
  double area = ec.at(c.x, ec.row_part(c.y));
  if (area == 0 || !std::isfinite(area)) return;
  // Front faces wind counter-clockwise in raster space (x right, y up); for back faces the
  // edge functions turn round, so inside is where all three are >= 0 either way.
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
      if (clip_each && (wa * a.clip + wb * b.clip + wc * c.clip) * inv > clip.limit) continue;
      f.depth[k] = z;
      f.face[k] = id;
    }
  }
}

Frame rasterize(const TriangleSoup& soup, const Camera& cam, const ClipTest& clip) {
  if (soup.triangles.size() >= Frame::kBack) throw InputError("render: too many triangles");
  Frame f;
  f.width = cam.width * kSupersample;
  f.height = cam.height * kSupersample;
  f.depth.assign(static_cast<std::size_t>(f.width) * f.height,
                 -std::numeric_limits<float>::infinity());
  f.face.assign(f.depth.size(), Frame::kNone);
  const Projector project(soup, cam, clip);
  const int strips = (f.height + kStripRows - 1) / kStripRows;
  const Bins bins = bin_triangles(soup, project, clip, strips, f.height);
  detail::parallel_for(static_cast<std::size_t>(strips), 1, [&](std::size_t s0, std::size_t s1) {
    for (std::size_t strip = s0; strip < s1; ++strip) {
      const int row0 = static_cast<int>(strip) * kStripRows;
      const int row1 = std::min(f.height, row0 + kStripRows) - 1;
      for (std::size_t n = bins.start[strip]; n < bins.start[strip + 1]; ++n)
        rasterize_triangle(soup, project, clip, bins.triangles[n], row0, row1, f);
    }
  });
  return f;
}

// --- shading ------------------------------------------------------------------------------

struct Colour {
  double r = 0, g = 0, b = 0;
};

Colour colour_of(Rgb c) {
  return {double(c.r), double(c.g), double(c.b)};
}

/// The picture's pixels from the frame; `nearest` gets each pixel's nearest sample depth
/// (in pixels, -inf where the background shows).
std::vector<std::uint8_t> shade(const TriangleSoup& soup, const Camera& cam, const Frame& f,
                                const RenderOptions& o, std::vector<float>& nearest) {
  // Lights fixed to the camera: a key light from the upper left, a fill light from the right.
  const Vec3 key = normalized(-0.7 * cam.right + 0.7 * cam.up + 0.4 * cam.toward);
  const Vec3 fill = normalized(0.3 * cam.right - 0.2 * cam.up + 0.9 * cam.toward);
  const Colour background = colour_of(o.background);
  auto sample_colour = [&](std::uint32_t id) -> Colour {
    if (id == Frame::kNone) return background;
    const std::uint32_t t = id & ~Frame::kBack;
    const Colour base = colour_of(o.face_colours.empty() ? o.colour : o.face_colours[t]);
    // A back face seen through a cut, where a section cap would be: flat, darker and warmer.
    // A triangle with a colour of its own is lit on both sides: a marked face shows in its
    // colour whichever way it faces (a flipped face is a back face seen from outside).
    const bool two_sided = !o.face_colours.empty() && !(o.face_colours[t] == o.colour);
    const bool back = (id & Frame::kBack) != 0;
    if (back && !two_sided)
      return o.back_colour ? colour_of(*o.back_colour)
                           : Colour{0.35 * base.r + 70, 0.35 * base.g + 20, 0.35 * base.b + 10};
    const Triangle& tri = soup.triangles[t];
    const Vec3 n =
        (back ? -1.0 : 1.0) * normalized(cross(soup.points[tri[1]] - soup.points[tri[0]],
                                               soup.points[tri[2]] - soup.points[tri[0]]));
    const double light = kAmbient + kKeyLight * std::max(0.0, dot(n, key)) +
                         kFillLight * std::max(0.0, dot(n, fill));
    return {base.r * light, base.g * light, base.b * light};
  };
  std::vector<std::uint8_t> rgb(static_cast<std::size_t>(cam.width) * cam.height * 3);
  nearest.assign(static_cast<std::size_t>(cam.width) * cam.height, 0.0f);
  const int W = f.width, H = f.height;
  detail::parallel_for(
      static_cast<std::size_t>(cam.height), 8, [&](std::size_t y0, std::size_t y1) {
        for (int y = static_cast<int>(y0); y < static_cast<int>(y1); ++y)
          for (int x = 0; x < cam.width; ++x) {
            Colour sum;
            float z = -std::numeric_limits<float>::infinity();
            for (int dy = 0; dy < kSupersample; ++dy)
              for (int dx = 0; dx < kSupersample; ++dx) {
                // Raster rows go up, image rows go down.
                const int sj = H - 1 - (y * kSupersample + dy), si = x * kSupersample + dx;
                const std::size_t k = static_cast<std::size_t>(sj) * W + si;
                const Colour c = sample_colour(f.face[k]);
                sum.r += c.r;
                sum.g += c.g;
                sum.b += c.b;
                z = std::max(z, f.depth[k]);
              }
            const std::size_t p = static_cast<std::size_t>(y) * cam.width + x;
            nearest[p] = z / kSupersample;
            const double n = kSupersample * kSupersample;
            rgb[3 * p] = static_cast<std::uint8_t>(std::clamp(std::lround(sum.r / n), 0L, 255L));
            rgb[3 * p + 1] =
                static_cast<std::uint8_t>(std::clamp(std::lround(sum.g / n), 0L, 255L));
            rgb[3 * p + 2] =
                static_cast<std::uint8_t>(std::clamp(std::lround(sum.b / n), 0L, 255L));
          }
      });
  return rgb;
}

}  // namespace

namespace detail {

ClipTest clip_test(const Clip& clip, const Vec3& toward) {
  if (clip.axis < 0) return {};
  const int side = clip.side != 0 ? clip.side : (toward[clip.axis] >= 0 ? 1 : -1);
  return {clip.axis, double(side), side * clip.position};
}

}  // namespace detail

View named_view(std::string_view name) {
  if (name == "iso") return {};
  if (name == "x") return {90, 0};
  if (name == "-x") return {-90, 0};
  if (name == "y") return {180, 0};
  if (name == "-y") return {0, 0};
  if (name == "z") return {0, 90};
  if (name == "-z") return {0, -90};
  throw InputError("'" + std::string(name) +
                   "' is not a view (iso, x, y, z, -x, -y, -z, or azimuth and elevation in "
                   "degrees)");
}

Projection Camera::project(Vec3 p) const {
  const Vec3 d = p - centre;
  return {dot(d, right) * pixels_per_mm + 0.5 * width, 0.5 * height - dot(d, up) * pixels_per_mm,
          dot(d, toward)};
}

Camera fit_camera(const TriangleSoup& soup, const RenderOptions& options) {
  require_options(soup, options);
  detail::require_indices_in_range(soup, "render: ");
  const double az = options.view.azimuth * std::numbers::pi / 180;
  const double el = options.view.elevation * std::numbers::pi / 180;
  Camera c;
  c.toward = {std::sin(az) * std::cos(el), -std::cos(az) * std::cos(el), std::sin(el)};
  c.right = {std::cos(az), std::sin(az), 0};
  c.up = cross(c.toward, c.right);
  const ClipTest clip = detail::clip_test(options.clip, c.toward);
  const Box3 box = view_box(soup, clip, c);
  if (box.empty()) {
    char where[64];
    std::snprintf(where, sizeof where, "%c = %g", 'x' + options.clip.axis, options.clip.position);
    throw InputError(std::string("render: nothing is left after the clip at ") + where);
  }
  const Vec3 mid = box.centre();  // in the camera's frame
  c.centre = mid.x * c.right + mid.y * c.up + mid.z * c.toward;
  const double ex = 0.5 * box.size().x, ey = 0.5 * box.size().y;
  if (!(std::max(ex, ey) > 0)) throw InputError("render: the mesh has no extent in this view");
  const double inf = std::numeric_limits<double>::infinity();
  if (options.height == 0) {
    const int size = options.width;
    const double margin = std::round(kMargin * size);
    c.pixels_per_mm = (size - 2 * margin) / (2 * std::max(ex, ey));
    auto side = [&](double e) {
      return std::clamp(static_cast<int>(std::ceil(2 * e * c.pixels_per_mm + 2 * margin)), 1, size);
    };
    c.width = ex >= ey ? size : side(ex);
    c.height = ey > ex ? size : side(ey);
  } else {
    const double margin = std::round(kMargin * std::min(options.width, options.height));
    c.pixels_per_mm = std::min(ex > 0 ? (options.width - 2 * margin) / (2 * ex) : inf,
                               ey > 0 ? (options.height - 2 * margin) / (2 * ey) : inf);
    c.width = options.width;
    c.height = options.height;
  }
  return c;
}

Image render_mesh(const TriangleSoup& soup, const RenderOptions& options) {
  const Camera cam = fit_camera(soup, options);
  if (!options.face_colours.empty() && options.face_colours.size() != soup.triangles.size())
    throw InputError("render: " + std::to_string(options.face_colours.size()) +
                     " face colours for " + std::to_string(soup.triangles.size()) + " triangles");
  if (options.line_width < 0 || options.line_width > 64)
    throw InputError("render: the line width is 0 to 64 pixels");
  const ClipTest clip = detail::clip_test(options.clip, cam.toward);
  const Frame frame = rasterize(soup, cam, clip);
  Image image{cam.width, cam.height, {}};
  std::vector<float> nearest;
  image.rgb = shade(soup, cam, frame, options, nearest);
  detail::draw_marks(image, nearest, cam, clip, options);
  detail::add_legend(image, options);
  return image;
}

std::string encode_png(const Image& image) {
  return detail::encode_png(image.width, image.height, 3, image.rgb.data());
}

void write_png(const std::filesystem::path& path, const Image& image) {
  std::string ext = path.extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(),
                 [](unsigned char ch) { return static_cast<char>(std::tolower(ch)); });
  if (ext != ".png") throw InputError(path.string() + ": a picture's name ends in .png");
  write_file_atomically(path, encode_png(image));
}

}  // namespace tpmsfill
