#include "layers/covered_region.hpp"

#include <clipper.hpp>

#include <algorithm>
#include <cmath>

namespace tpmsfill::detail {

std::vector<Contour> nonzero_region(const std::vector<std::vector<Vec2>>& paths) {
  double x_lo = 1e300, x_hi = -1e300, y_lo = 1e300, y_hi = -1e300;
  for (const auto& path : paths)
    for (const Vec2& p : path) {
      x_lo = std::min(x_lo, p.x), x_hi = std::max(x_hi, p.x);
      y_lo = std::min(y_lo, p.y), y_hi = std::max(y_hi, p.y);
    }
  if (!(x_hi >= x_lo && y_hi >= y_lo)) return {};
  // Within Clipper's fast 32-bit-product range (|coordinate| < 2³⁰) with room to spare.
  const double cx = 0.5 * (x_lo + x_hi), cy = 0.5 * (y_lo + y_hi);
  const double extent = std::max({x_hi - x_lo, y_hi - y_lo, 1e-300});
  const double scale = std::ldexp(1.0, 29) / extent;
  ClipperLib::Paths in;
  in.reserve(paths.size());
  for (const auto& path : paths) {
    ClipperLib::Path p;
    p.reserve(path.size());
    for (const Vec2& v : path)
      p.emplace_back(static_cast<ClipperLib::cInt>(std::llround((v.x - cx) * scale)),
                     static_cast<ClipperLib::cInt>(std::llround((v.y - cy) * scale)));
    in.push_back(std::move(p));
  }
  ClipperLib::Clipper clipper;
  clipper.AddPaths(in, ClipperLib::ptSubject, true);
  ClipperLib::Paths out;
  clipper.Execute(ClipperLib::ctUnion, out, ClipperLib::pftNonZero, ClipperLib::pftNonZero);
  std::vector<Contour> contours;
  contours.reserve(out.size());
  for (const ClipperLib::Path& path : out) {
    Contour c;
    c.points.reserve(path.size());
    for (const ClipperLib::IntPoint& p : path)
      c.points.push_back(
          {cx + static_cast<double>(p.X) / scale, cy + static_cast<double>(p.Y) / scale});
    c.area = signed_area(c.points);
    contours.push_back(std::move(c));
  }
  return contours;
}

}  // namespace tpmsfill::detail
