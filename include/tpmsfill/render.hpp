/// @file render.hpp
/// @brief Stage "render": a triangle soup drawn to a picture, for people who would rather look
/// than read (`tpmsfill render`, `fill --preview`, `check --picture`, the docs' catalogue).
///
/// An orthographic software rasterizer, no GPU and no display. The camera looks at the centre
/// of the bounding box of what the clip leaves and is fitted so that the box's projection fills
/// the picture less a margin of 4 % on every side. Phases: bin the triangles by strips of
/// sample rows; rasterize the strips in parallel into a 2×2-supersampled buffer that keeps, per
/// sample, the nearest triangle (edge functions, per-sample depth and clip coordinate, so a cut
/// is exact to the sample, not to the triangle); shade each sample from its triangle's normal
/// (ambient + two directional lights fixed to the camera) and average each 2×2 block; draw the
/// marked edges and points on top (thick, paler where the surface hides them); write the legend
/// in a band below the picture with a built-in 5×7 bitmap font.
///
/// Back faces are what the eye meets first only where it looks into a closed solid through a
/// cut: they are drawn flat in a darker, warmer tint of their colour, so a cut reads as a solid
/// section.
///
/// Deterministic: every sample and pixel is written by one task, marks are drawn in order, so
/// the same soup and options give the same bytes whatever the thread count.
#pragma once

#include <array>
#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "tpmsfill/check.hpp"
#include "tpmsfill/types.hpp"

namespace tpmsfill {

/// An 8-bit RGB colour.
struct Rgb {
  std::uint8_t r = 0, g = 0, b = 0;
  friend bool operator==(const Rgb&, const Rgb&) = default;
};

/// Where the camera looks from; z is up. Azimuth 0, elevation 0 looks along +y (from −y, x to
/// the right); the azimuth turns the camera counter-clockwise about z seen from above (90: from
/// +x), the elevation raises it (90: straight down, x to the right, y up). Past ±90 the camera
/// goes on over the top (or under the bottom) and the picture turns upside down.
struct View {
  double azimuth = 35;    ///< degrees
  double elevation = 25;  ///< degrees, −180 to 180
};

/// The views `tpmsfill render --view NAME` knows: "iso" (the default: azimuth 35°, elevation
/// 25°, a three-quarter view from the front right and above), "x", "y", "z" (from the positive
/// side of that axis: from +x and +y with z up, from +z with y up) and "-x", "-y", "-z" (from
/// the negative side).
/// @throws InputError  any other name
View named_view(std::string_view name);

/// A cut through the mesh along a plane normal to an axis: one side is cut away, so the
/// inside shows (a closed solid's section is drawn in the cut tint, see the file comment).
struct Clip {
  int axis = -1;        ///< 0, 1, 2 for x, y, z; −1: no cut
  double position = 0;  ///< of the plane along the axis, mm
  /// +1 cuts away the part with coordinate > position, −1 the part with coordinate <
  /// position; 0 the part nearer the camera (+1 when the camera looks from the positive side
  /// of the axis or square to it, else −1).
  int side = 0;
};

/// Edges drawn over the picture in one colour: `line_width` thick, over the surface, paler
/// where the surface hides them.
struct EdgeMarks {
  Rgb colour;
  std::vector<std::array<Vec3, 2>> edges;  ///< ends, mm
};

/// Points drawn over the picture as discs of twice `line_width` across, in one colour.
struct PointMarks {
  Rgb colour;
  std::vector<Vec3> points;  ///< mm
};

/// One line of the legend: a colour swatch (none when unset) and a text (ASCII; letters are
/// drawn upper-case, characters the font lacks as '?').
struct LegendEntry {
  std::optional<Rgb> swatch;
  std::string text;
};

struct RenderOptions {
  View view;
  Clip clip;
  /// Picture size in pixels (16 to 16384 each). With height 0, width is the longer side of the
  /// picture and the other side follows the aspect of the view; otherwise the view is fitted
  /// into width × height, centred. The legend adds a band below.
  int width = 640;
  int height = 0;
  Rgb colour{178, 196, 222};  ///< front faces (before shading)
  Rgb background{255, 255, 255};
  /// Back faces, drawn flat (what shows through a cut or a hole); unset: a darker, warmer
  /// tint of the face's colour.
  std::optional<Rgb> back_colour;
  /// Per triangle of the soup: its colour instead of `colour` (empty: all `colour`). A
  /// triangle whose colour is not `colour` is lit on both sides (a marked face shows in its
  /// colour whichever way it faces); the others show their back faces as back_colour says.
  std::vector<Rgb> face_colours;
  /// Drawn in order, later over earlier; points over edges; what the clip cuts away is not.
  std::vector<EdgeMarks> edges;
  std::vector<PointMarks> points;
  /// Width of marked edges, pixels; 0: 3 up to 640 pixels across, 1 more per 320 beyond.
  int line_width = 0;
  /// Lines of text in a band below the picture (no band when empty).
  std::vector<LegendEntry> legend;
};

/// Where a point lands in the picture.
struct Projection {
  double x = 0;      ///< pixels from the left edge (pixel i covers [i, i + 1))
  double y = 0;      ///< pixels from the top edge (row j covers [j, j + 1))
  double depth = 0;  ///< mm towards the camera from the view's centre (larger is nearer)
};

/// The orthographic camera of a picture. (right, up, toward) is right-handed; `toward` points
/// from the scene to the camera.
struct Camera {
  Vec3 right, up, toward;
  Vec3 centre;                ///< mm: lands in the middle of the picture
  double pixels_per_mm = 1;   ///< scale
  int width = 0, height = 0;  ///< the picture's pixels, without the legend band
  Projection project(Vec3 p) const;
};

/// The camera render_mesh() uses for `soup` and `options` (view, clip, size).
/// @throws InputError  the soup has no triangle, the clip leaves nothing, the mesh has no
///                     extent in this view, or a size is outside 16 to 16384
Camera fit_camera(const TriangleSoup& soup, const RenderOptions& options);

/// An 8-bit RGB picture, rows top to bottom.
struct Image {
  int width = 0, height = 0;
  std::vector<std::uint8_t> rgb;  ///< 3 bytes a pixel
  Rgb pixel(int x, int y) const {
    const std::uint8_t* p = &rgb[(static_cast<std::size_t>(y) * width + x) * 3];
    return {p[0], p[1], p[2]};
  }
};

/// Draws `soup` as `options` say.
/// @param[in] soup  any triangle soup (indices must be in range, which readers guarantee);
///                  degenerate triangles draw nothing
/// @throws InputError  see fit_camera(); face_colours neither empty nor one per triangle; a
///                     line width outside 0 to 64; more than 2^31 triangles
Image render_mesh(const TriangleSoup& soup, const RenderOptions& options = {});

/// The picture as PNG bytes (8-bit RGB, adaptive row filters, zlib).
std::string encode_png(const Image& image);

/// Writes the picture as a PNG, atomically (write_file_atomically).
/// @throws InputError  the path does not end in ".png" (any case)
/// @throws IoError     the file cannot be written
void write_png(const std::filesystem::path& path, const Image& image);

// --- pictures of a check ------------------------------------------------------------------

/// The colours of `check --picture`: from Okabe and Ito's palette, told apart with any of
/// the common colour-vision deficiencies, on a neutral grey surface.
struct DefectColours {
  Rgb surface{200, 200, 200};
  Rgb inside{95, 95, 95};                ///< back faces, seen through holes and cuts
  Rgb border_edge{213, 94, 0};           ///< vermilion
  Rgb non_manifold_edge{0, 114, 178};    ///< blue
  Rgb non_manifold_vertex{230, 159, 0};  ///< orange
  Rgb self_intersection{0, 158, 115};    ///< bluish green: both triangles of a pair, outlined
  Rgb flipped{204, 121, 167};            ///< reddish purple: faces that point the wrong way
};

/// `options` with the defects `check` found in `soup` marked, for render_mesh(): the surface
/// grey, flipped faces (those clean_soup() turns round: against their neighbours, or a whole
/// shell inside out) and both faces of each self-intersecting pair in their colours, the
/// triangles of self-intersecting pairs outlined, border and non-manifold edges drawn thick,
/// non-manifold vertices as discs (in that order, later on top), and a legend that names each
/// with its count, or says the mesh is valid.
/// @param[in] soup     the soup `check` was made from, in millimetres (default units)
/// @param[in] check    check_mesh(soup, ...): every example location it holds is drawn, so
///                     make it with max_examples as large as the picture should show (the
///                     legend says how many were drawn where that is fewer than found)
/// @param[in] options  view, clip, size, line width; its colours, marks and legend are replaced
/// @throws InputError  an index of `soup` is out of range
RenderOptions mark_defects(const TriangleSoup& soup, const MeshCheck& check,
                           RenderOptions options = {}, const DefectColours& colours = {});

}  // namespace tpmsfill
