// Stage "slice": its report as JSON (the job's report, as fill writes it, plus the layers) and
// as a human summary.
#include <cmath>
#include <cstdio>
#include <nlohmann/json.hpp>
#include <string>

#include "core/format_numbers.hpp"
#include "lattice/report_text.hpp"
#include "tpmsfill/slice.hpp"

namespace tpmsfill {
namespace {

using json = nlohmann::ordered_json;

using detail::format;

}  // namespace

std::string to_json(const SliceReport& r) {
  // The job's part, as fill reports it; what only a mesh has (output, validation, islands,
  // cavities, measures) is not a slice's to report.
  json job = detail::job_json(r.job);
  json layers = json::array();
  for (const LayerSummary& l : r.layers)
    layers.push_back({{"z", l.z},
                      {"area", l.area},
                      {"outer", l.outer},
                      {"holes", l.holes},
                      {"points", l.points}});
  job["slice"] = {{"layer", r.layer},
                  {"layers", r.layers.size()},
                  {"first_bottom", r.layers.empty() ? 0.0 : r.layers.front().z - 0.5 * r.layer},
                  {"plane_nodes", r.plane_nodes},
                  {"slab_planes", r.slab_planes},
                  {"contours", r.contours},
                  {"holes", r.holes},
                  {"points", r.points},
                  {"volume", r.volume},
                  {"porosity", r.porosity()},
                  {"islands", "kept: a layer cannot tell a floating piece (fill removes them)"},
                  {"segment_pairs_checked", r.segment_pairs_checked},
                  {"contours_simple", true},
                  {"per_layer", layers}};
  return job.dump(2) + "\n";
}

std::string to_text(const SliceReport& r) {
  const JobReport& j = r.job;
  std::string s = detail::settings_text(j);
  s += format("planes       %.0f x %.0f nodes at %g mm", j.grid.dims[0], j.grid.dims[1],
              j.grid.spacing) +
       format(", %.0f planes classified per layer\n", r.slab_planes);
  s += "inside       " + detail::inside_text(j) + "\n";
  s += format("layers       %.0f of %g mm", static_cast<double>(r.layers.size()), r.layer) +
       format(", %.0f contours (%.0f holes)", static_cast<double>(r.contours),
              static_cast<double>(r.holes)) +
       format(", %.0f points\n", static_cast<double>(r.points));
  s += format("volume       lattice %.1f mm3 (sum of area x layer), model %.1f mm3\n", r.volume,
              j.model_volume);
  s += std::isfinite(j.unclipped_porosity)
           ? format("porosity     %.2f %% (unclipped lattice %.2f %%)\n", 100 * r.porosity(),
                    100 * j.unclipped_porosity)
           : format("porosity     %.2f %% (graded)\n", 100 * r.porosity());
  s += format(
      "contours     closed, outer counter-clockwise, holes clockwise; %.3g segment "
      "pairs checked exactly, none cross or touch\n",
      static_cast<double>(r.segment_pairs_checked));
  s += detail::closing_text(j);
  return s;
}

}  // namespace tpmsfill
