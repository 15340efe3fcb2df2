// Stage "render", the second half: marked edges and points over the shaded picture, the
// legend below it, and the marks of a check (mark_defects).
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <string>

#include "mesh/internal/bitmap_font.hpp"
#include "mesh/internal/render_frame.hpp"
#include "tpmsfill/mesh/clean.hpp"
#include "tpmsfill/render.hpp"

namespace tpmsfill {
namespace detail {
namespace {

/// Per pixel: the mark on top and whether it shows (2), is hidden by the surface (1) or absent
/// (0). A visible mark beats a hidden one; between equals, the later one wins.
struct MarkLayer {
  int width = 0, height = 0;
  std::vector<std::uint8_t> state;
  std::vector<Rgb> colour;
};

/// What every stamp of one drawing needs.
struct Pen {
  MarkLayer& layer;
  const std::vector<float>& nearest;  ///< per pixel, pixels towards the camera
  double tolerance;                   ///< depth (pixels) a mark may lie behind the surface
};

/// A disc of `radius` pixels around (x, y) at `depth` (pixels towards the camera).
void stamp(const Pen& pen, double x, double y, double depth, double radius, Rgb colour) {
  MarkLayer& m = pen.layer;
  const int i0 = std::max(0, static_cast<int>(std::floor(x - radius)));
  const int i1 = std::min(m.width - 1, static_cast<int>(std::floor(x + radius)));
  const int j0 = std::max(0, static_cast<int>(std::floor(y - radius)));
  const int j1 = std::min(m.height - 1, static_cast<int>(std::floor(y + radius)));
  for (int j = j0; j <= j1; ++j)
    for (int i = i0; i <= i1; ++i) {
      const double dx = i + 0.5 - x, dy = j + 0.5 - y;
      if (dx * dx + dy * dy > radius * radius + 1e-9) continue;
      const std::size_t k = static_cast<std::size_t>(j) * m.width + i;
      const std::uint8_t s = depth >= pen.nearest[k] - pen.tolerance ? 2 : 1;
      if (s < m.state[k]) continue;
      m.state[k] = s;
      m.colour[k] = colour;
    }
}

/// The part of edge a-b that the clip leaves (false: none).
bool clip_edge(const ClipTest& clip, Vec3& a, Vec3& b) {
  if (clip.axis < 0) return true;
  const double va = clip.value(a), vb = clip.value(b);
  if (va > clip.limit && vb > clip.limit) return false;
  if (va > clip.limit) a = a + ((clip.limit - va) / (vb - va)) * (b - a);
  if (vb > clip.limit) b = b + ((clip.limit - vb) / (va - vb)) * (a - b);
  return true;
}

void draw_edge(const Pen& pen, const Camera& cam, const ClipTest& clip, Vec3 a, Vec3 b,
               double radius, Rgb colour) {
  if (!clip_edge(clip, a, b)) return;
  const Projection p = cam.project(a), q = cam.project(b);
  const double length = std::hypot(q.x - p.x, q.y - p.y);
  if (!std::isfinite(length)) return;
  // Stamps half a pixel apart at most; an edge longer than the picture's perimeter is off it.
  const double cap = 4.0 * (pen.layer.width + pen.layer.height);
  const int steps = std::max(1, static_cast<int>(std::ceil(std::min(length, cap) / 0.5)));
  for (int s = 0; s <= steps; ++s) {
    const double t = static_cast<double>(s) / steps;
    stamp(pen, p.x + t * (q.x - p.x), p.y + t * (q.y - p.y),
          (p.depth + t * (q.depth - p.depth)) * cam.pixels_per_mm, radius, colour);
  }
}

int line_width(const RenderOptions& o, const Camera& cam) {
  if (o.line_width > 0) return o.line_width;
  return 3 + std::max(0, std::max(cam.width, cam.height) - 640) / 320;
}

}  // namespace

void draw_marks(Image& image, const std::vector<float>& nearest, const Camera& cam,
                const ClipTest& clip, const RenderOptions& options) {
  if (options.edges.empty() && options.points.empty()) return;
  MarkLayer layer{image.width, image.height, {}, {}};
  layer.state.assign(static_cast<std::size_t>(image.width) * image.height, 0);
  layer.colour.assign(layer.state.size(), Rgb{});
  const int width = line_width(options, cam);
  // A surface within about a line's width in depth does not hide a mark: the mark's own
  // triangles, and their neighbours at a slant, are that close.
  const Pen pen{layer, nearest, width + 1.0};
  for (const EdgeMarks& marks : options.edges)
    for (const auto& [a, b] : marks.edges)
      draw_edge(pen, cam, clip, a, b, 0.5 * width, marks.colour);
  for (const PointMarks& marks : options.points)
    for (const Vec3& p : marks.points) {
      if (clip.cuts(p)) continue;
      const Projection q = cam.project(p);
      stamp(pen, q.x, q.y, q.depth * cam.pixels_per_mm, width, marks.colour);
    }
  // Hidden marks show through, at 45 %: the user sees every defect and which face it is on.
  for (std::size_t k = 0; k < layer.state.size(); ++k) {
    if (layer.state[k] == 0) continue;
    std::uint8_t* px = &image.rgb[3 * k];
    const Rgb c = layer.colour[k];
    if (layer.state[k] == 2) {
      px[0] = c.r;
      px[1] = c.g;
      px[2] = c.b;
    } else {
      auto mix = [](std::uint8_t mark, std::uint8_t under) {
        return static_cast<std::uint8_t>((45 * mark + 55 * under + 50) / 100);
      };
      px[0] = mix(c.r, px[0]);
      px[1] = mix(c.g, px[1]);
      px[2] = mix(c.b, px[2]);
    }
  }
}

void add_legend(Image& image, const RenderOptions& options) {
  if (options.legend.empty()) return;
  const int s = std::clamp(image.width / 240, 1, 4);  // font scale: pixels a font cell
  const int line = 11 * s, pad = 4 * s;
  const int band = static_cast<int>(options.legend.size()) * line + 2 * pad;
  const int top = image.height;
  image.height += band;
  image.rgb.resize(static_cast<std::size_t>(image.width) * image.height * 3);
  const Rgb bg = options.background;
  const bool dark = 299 * bg.r + 587 * bg.g + 114 * bg.b < 128000;
  const Rgb ink = dark ? Rgb{255, 255, 255} : Rgb{0, 0, 0};
  auto fill = [&](int x0, int y0, int w, int h, Rgb c) {
    for (int y = std::max(0, y0); y < std::min(image.height, y0 + h); ++y)
      for (int x = std::max(0, x0); x < std::min(image.width, x0 + w); ++x) {
        std::uint8_t* p = &image.rgb[(static_cast<std::size_t>(y) * image.width + x) * 3];
        p[0] = c.r;
        p[1] = c.g;
        p[2] = c.b;
      }
  };
  fill(0, top, image.width, band, bg);
  for (std::size_t n = 0; n < options.legend.size(); ++n) {
    const LegendEntry& entry = options.legend[n];
    const int y = top + pad + static_cast<int>(n) * line + 2 * s;  // the glyphs' top row
    if (entry.swatch) {
      fill(pad, y, kGlyphHeight * s, kGlyphHeight * s, ink);
      fill(pad + s, y + s, (kGlyphHeight - 2) * s, (kGlyphHeight - 2) * s, *entry.swatch);
    }
    int x = pad + (kGlyphHeight + 3) * s;
    for (char c : entry.text) {
      const auto& rows = glyph(c);
      for (int r = 0; r < kGlyphHeight; ++r)
        for (int col = 0; col < kGlyphWidth; ++col)
          if (rows[r] & (1u << (kGlyphWidth - 1 - col))) fill(x + col * s, y + r * s, s, s, ink);
      x += kGlyphAdvance * s;
    }
  }
}

}  // namespace detail

namespace {

std::string count_text(const char* what, std::uint64_t found, std::size_t drawn) {
  std::string text = std::string(what) + ": " + std::to_string(found);
  if (drawn < found) text += " (" + std::to_string(drawn) + " drawn)";
  return text;
}

std::vector<std::array<Vec3, 2>> edge_ends(const std::vector<EdgeLocation>& locations) {
  std::vector<std::array<Vec3, 2>> ends;
  ends.reserve(locations.size());
  for (const EdgeLocation& e : locations) ends.push_back(e.ends);
  return ends;
}

std::vector<LegendEntry> defect_legend(const MeshCheck& check, const CleanResult& cleaned,
                                       const DefectColours& colours) {
  std::vector<LegendEntry> legend;
  legend.push_back({std::nullopt, "not valid: " + std::to_string(check.problems().size()) +
                                      (check.problems().size() == 1 ? " problem" : " problems")});
  std::string border =
      count_text("border edges", check.border_edges, check.border_edge_examples.size());
  // As check's text says it: holes without border edges open where non-manifold edges split.
  if (check.holes.value_or(0) > 0)
    border += (check.border_edges > 0 ? ", " : "; ") + std::to_string(*check.holes) +
              (check.border_edges > 0 ? " holes" : " holes once its non-manifold edges are split");
  legend.push_back({colours.border_edge, border});
  legend.push_back(
      {colours.non_manifold_edge, count_text("non-manifold edges", check.non_manifold_edges,
                                             check.non_manifold_edge_examples.size())});
  legend.push_back(
      {colours.non_manifold_vertex, count_text("non-manifold vertices", check.non_manifold_vertices,
                                               check.non_manifold_vertex_examples.size())});
  legend.push_back({colours.self_intersection,
                    check.self_intersecting_pairs
                        ? count_text("self-intersecting pairs", *check.self_intersecting_pairs,
                                     check.self_intersection_examples.size())
                        : std::string("self-intersecting pairs: not searched")});
  // Whole pieces turned round are judged with their holes capped (clean_soup's step 4): said,
  // so an open mesh's text (which cannot call it inside out) and picture agree.
  std::string flipped = "flipped triangles: " + std::to_string(cleaned.reversed.size());
  if (const std::uint64_t pieces = cleaned.report.reversed_pieces; pieces > 0)
    flipped += " (" + std::to_string(pieces) + (pieces == 1 ? " piece" : " pieces") +
               " facing inward" + (check.closed() ? "" : " once its holes are capped") + ")";
  legend.push_back({colours.flipped, flipped});
  if (check.degenerate_triangles + check.duplicate_triangles > 0)
    legend.push_back({std::nullopt,
                      "not drawn: " + std::to_string(check.degenerate_triangles) + " degenerate, " +
                          std::to_string(check.duplicate_triangles) + " duplicate triangles"});
  legend.push_back({std::nullopt, "pale marks are hidden behind the surface"});
  return legend;
}

}  // namespace

RenderOptions mark_defects(const TriangleSoup& soup, const MeshCheck& check, RenderOptions options,
                           const DefectColours& colours) {
  options.colour = colours.surface;
  options.back_colour = colours.inside;
  options.face_colours.clear();
  options.edges.clear();
  options.points.clear();
  options.legend.clear();
  if (check.valid()) {
    options.legend.push_back({std::nullopt, "valid: a closed, outward-oriented 2-manifold"});
    options.legend.push_back({std::nullopt, check.self_intersecting_pairs
                                                ? "without self-intersections or degenerate faces"
                                                : "self-intersections not searched"});
    return options;
  }
  // Flipped: what clean_soup() turns round (against its piece, or a whole piece inside out).
  const CleanResult cleaned = clean_soup(soup);
  options.face_colours.assign(soup.triangles.size(), colours.surface);
  for (std::uint32_t t : cleaned.reversed) options.face_colours[t] = colours.flipped;
  EdgeMarks outlines{colours.self_intersection, {}};
  for (const auto& pair : check.self_intersection_examples)
    for (std::uint32_t t : pair) {
      if (t >= soup.triangles.size()) continue;
      options.face_colours[t] = colours.self_intersection;
      const Triangle& tri = soup.triangles[t];
      for (int k = 0; k < 3; ++k)
        outlines.edges.push_back({soup.points[tri[k]], soup.points[tri[(k + 1) % 3]]});
    }
  options.edges.push_back(std::move(outlines));
  options.edges.push_back({colours.border_edge, edge_ends(check.border_edge_examples)});
  options.edges.push_back({colours.non_manifold_edge, edge_ends(check.non_manifold_edge_examples)});
  options.points.push_back({colours.non_manifold_vertex, check.non_manifold_vertex_examples});
  options.legend = defect_legend(check, cleaned, colours);
  return options;
}

}  // namespace tpmsfill
