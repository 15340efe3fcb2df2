// A solid's direct slice as a printer layer with its material (material_layers.hpp).
#include "tpmsfill/solid/material_layers.hpp"

#include <algorithm>
#include <cmath>

namespace tpmsfill {

Layer material_layer(const SolidSection& section, std::uint64_t index, double bottom, double top,
                     double lo, double hi) {
  Layer layer;
  layer.index = index;
  layer.bottom = bottom;
  layer.top = top;
  layer.z = section.z;
  layer.contours = section.contours;
  layer.area = section.area;
  MaterialSection& m = layer.material;
  m.points.reserve(section.mesh.points.size());
  for (const Vec3& p : section.mesh.points) m.points.push_back({p.x, p.y});
  m.material = section.mesh.material;
  m.triangles = section.mesh.triangles;
  m.material_min = lo;
  m.material_max = hi;
  return layer;
}

std::vector<double> material_histogram(const SolidSection& section, double lo, double hi,
                                       int bins) {
  std::vector<double> area(static_cast<std::size_t>(std::max(bins, 1)), 0.0);
  const SolidLevelSet& m = section.mesh;
  for (const auto& t : m.triangles) {
    const Vec3 a = m.points[t[0]], b = m.points[t[1]], c = m.points[t[2]];
    const double triangle = std::abs((b.x - a.x) * (c.y - a.y) - (c.x - a.x) * (b.y - a.y)) / 2;
    const double mean = (m.material[t[0]] + m.material[t[1]] + m.material[t[2]]) / 3;
    const double u = hi > lo ? (mean - lo) / (hi - lo) : 0;
    const auto bin = static_cast<std::size_t>(
        std::clamp(std::floor(u * static_cast<double>(area.size())), 0.0, area.size() - 1.0));
    area[bin] += triangle;
  }
  return area;
}

}  // namespace tpmsfill
