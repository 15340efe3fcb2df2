// Stage "conformal": its report as JSON (nlohmann, kept private) and as a human summary.
#include <cmath>
#include <cstdio>
#include <nlohmann/json.hpp>
#include <string>

#include "core/format_numbers.hpp"
#include "tpmsfill/conformal.hpp"
#include "tpmsfill/report.hpp"

namespace tpmsfill {
namespace {

using json = nlohmann::ordered_json;

json spread(const Spread& s) {
  return {{"min", s.min}, {"p5", s.p5}, {"p50", s.p50}, {"p95", s.p95}, {"max", s.max}};
}

json finite_or_null(double x) {
  return std::isfinite(x) ? json(x) : json(nullptr);
}

using detail::format;

}  // namespace

std::string to_json(const ConformalResult& result) {
  json j = json::parse(to_json(result.fill));
  const ConformalReport& r = result.report;
  const SurfaceParameterization& p = r.layout;
  const ConformalOptions& o = result.layer;
  j["conformal"] = {
      {"height", o.height},
      {"side", surface_side_name(o.side)},
      {"normal_scale", o.normal_scale},
      {"skin_surface", o.skin_surface},
      {"skin_top", o.skin_top},
      {"slab", {r.length_u, r.length_v}},
      {"map", slab_map_name(r.map)},
      {"vertex_map", r.map == SlabMap::Vertex ? json{{"split_edges", r.vertex_map.split_edges},
                                                     {"clamped", r.vertex_map.clamped},
                                                     {"chord_error", r.vertex_map.chord_error}}
                                              : json(nullptr)},
      {"layer_volume", result.fill.model_volume},
      {"layout",
       {{"method", layout_method_name(p.method)},
        {"free_iterations", p.free_iterations},
        {"other_area_scale", p.other_area_scale ? spread(*p.other_area_scale) : json(nullptr)},
        {"boundary_loops", p.boundary_loops},
        {"periodic_u", p.periodic_u},
        {"seam_edges", p.seam_edges},
        {"corners", p.corners},
        {"length_u", p.length_u},
        {"length_v", p.length_v},
        {"area", p.area},
        {"flips", p.flips},
        {"area_scale", spread(p.area_scale)},
        {"angle_distortion", spread(p.angle_distortion)}}},
      {"cell_size", spread(r.cell_size)},
      {"focal_distance", finite_or_null(r.focal_distance)},
      {"height_min", r.height_min},
      {"height_max", r.height_max}};
  return j.dump(2) + "\n";
}

std::string to_text(const ConformalResult& result) {
  const ConformalReport& r = result.report;
  const SurfaceParameterization& p = r.layout;
  const ConformalOptions& o = result.layer;
  const FillReport& f = result.fill;
  std::string s;
  s +=
      "lattice      " + f.design + format(", cell %g x %g x %g mm\n", f.cell.x, f.cell.y, f.cell.z);
  s += format("layer        %g mm ", o.height) + (o.side == SurfaceSide::Out ? "out" : "in") +
       format(" of the surface, slab %.4g x %.4g mm", r.length_u, r.length_v);
  if (o.normal_scale != 1) s += format(", normal scale %g", o.normal_scale);
  if (o.skin_surface > 0 || o.skin_top > 0)
    s += format(", skins %g mm (surface) and %g mm (top)", o.skin_surface, o.skin_top);
  s += "\n";
  if (r.map == SlabMap::Vertex)
    s += format("map          vertex by vertex: %.0f edges split, chords within %.3g mm\n",
                static_cast<double>(r.vertex_map.split_edges), r.vertex_map.chord_error);
  s += "layout       " +
       (p.periodic_u ? format("a tube cut along %.0f seam edges", static_cast<double>(p.seam_edges))
                     : std::string("a disk")) +
       (p.method == LayoutMethod::Free ? ", free (as rigid as possible)" : ", on the square") +
       format(", %.0f flips, area %.4g mm2\n", static_cast<double>(p.flips), p.area);
  if (p.other_area_scale)
    s += std::string("             the ") + (p.method == LayoutMethod::Free ? "square" : "free") +
         format(" layout's area scale: %.3g / %.3g / %.3g\n", p.other_area_scale->p5,
                p.other_area_scale->p50, p.other_area_scale->p95);
  s += format("distortion   area scale %.3g / %.3g / %.3g, angle %.3g", p.area_scale.p5,
              p.area_scale.p50, p.area_scale.p95, p.angle_distortion.p5) +
       format(" / %.3g / %.3g (p5 / p50 / p95)\n", p.angle_distortion.p50, p.angle_distortion.p95);
  s += format("cells        %.3g to %.3g mm on the surface (p5 to p95; median %.3g)\n",
              r.cell_size.p5, r.cell_size.p95, r.cell_size.p50);
  s += std::isfinite(r.focal_distance)
           ? format("curvature    smallest radius on the layer's side %.3g mm\n", r.focal_distance)
           : std::string("curvature    none towards the layer (it cannot fold)\n");
  s += format("heights      %.3g to %.3g mm above the surface\n", r.height_min, r.height_max);
  s += format("output       %.0f vertices, %.0f triangles, %.0f component(s)\n",
              static_cast<double>(f.vertices()), static_cast<double>(f.triangles()),
              static_cast<double>(f.components()));
  s += format("volume       lattice %.1f mm3 of a %.1f mm3 layer: porosity %.2f %%\n",
              f.lattice_volume(), f.model_volume, 100 * f.porosity());
  if (f.islands_removed)
    s += format("islands      %.0f removed (%.3g mm3)\n", static_cast<double>(f.islands_removed),
                f.islands_volume);
  s += std::string("validation   ") + (f.validation.valid() ? "valid" : "NOT valid") +
       ": closed, 2-manifold, outward, no self-intersections\n";
  double seconds = 0;
  for (const StageTime& t : f.stages) seconds += t.seconds;
  s += format("time         %.2f s\n", seconds);
  return s;
}

}  // namespace tpmsfill
