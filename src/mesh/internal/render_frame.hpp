/// @file render_frame.hpp
/// @brief What the two halves of stage "render" share: the clip as a test on points, the
/// supersampled frame, and the marks and legend drawn over the shaded picture
/// (render_marks.cpp).
#pragma once

#include <cstdint>
#include <vector>

#include "tpmsfill/render.hpp"

namespace tpmsfill::detail {

inline constexpr int kSupersample = 2;  ///< samples per pixel along each axis

/// A Clip with its side settled: a point is cut away when value(p) > limit.
struct ClipTest {
  int axis = -1;  ///< -1: nothing is cut
  double sign = 1;
  double limit = 0;
  double value(const Vec3& p) const { return sign * p[axis]; }
  bool cuts(const Vec3& p) const { return axis >= 0 && value(p) > limit; }
};

/// `clip` for a camera looking from `toward` (Clip::side 0: the side the camera is on).
ClipTest clip_test(const Clip& clip, const Vec3& toward);

/// Per sample (rows bottom to top): depth of the nearest fragment (samples towards the camera)
/// and its triangle (kNone: background; the top bit marks a back face).
struct Frame {
  static constexpr std::uint32_t kNone = 0xffffffffu;
  static constexpr std::uint32_t kBack = 0x80000000u;
  int width = 0, height = 0;  ///< samples
  std::vector<float> depth;
  std::vector<std::uint32_t> face;
};

/// Draws options.edges and options.points over `image` (the shaded picture, cam.width ×
/// cam.height), thick, paler where the surface is nearer than the mark; `nearest` holds each
/// pixel's nearest surface depth in pixels (-inf: background).
void draw_marks(Image& image, const std::vector<float>& nearest, const Camera& cam,
                const ClipTest& clip, const RenderOptions& options);

/// Adds a band below the picture with options.legend, one entry a line (nothing when empty).
void add_legend(Image& image, const RenderOptions& options);

}  // namespace tpmsfill::detail
