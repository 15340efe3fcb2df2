// to_json(DecimateReport) and to_text(DecimateReport): what `tpmsfill decimate` and
// `tpmsfill fill --decimate` print (fields in decimate.hpp). No CGAL here.
#include <cstdio>
#include <nlohmann/json.hpp>
#include <string>

#include "core/format_numbers.hpp"
#include "tpmsfill/decimate.hpp"

namespace tpmsfill {
namespace {

using json = nlohmann::ordered_json;

using detail::format;

// 1234567 -> "1,234,567".
std::string count(std::uint64_t n) {
  std::string digits = std::to_string(n), s;
  for (std::size_t i = 0; i < digits.size(); ++i) {
    if (i > 0 && (digits.size() - i) % 3 == 0) s += ',';
    s += digits[i];
  }
  return s;
}

}  // namespace

std::string to_json(const DecimateReport& r) {
  json j = {
      {"tolerance", r.tolerance},
      {"target_triangles", r.target_triangles > 0 ? json(r.target_triangles) : json(nullptr)},
      {"triangles_before", r.triangles_before},
      {"triangles_after", r.triangles_after},
      {"reduction", r.reduction()},
      {"vertices_before", r.vertices_before},
      {"vertices_after", r.vertices_after},
      {"merged_points", r.merged_points},
      {"volume_before", r.volume_before},
      {"volume_after", r.volume_after},
      {"volume_change", r.volume_change()},
      {"area_before", r.area_before},
      {"area_after", r.area_after},
      {"hausdorff_bound", r.hausdorff_bound},
      {"hausdorff", r.distance.hausdorff()},
      {"to_input", {{"max", r.distance.to_input}, {"p95", r.distance.to_input_p95}}},
      {"from_input", {{"max", r.distance.from_input}, {"p95", r.distance.from_input_p95}}},
      {"rounds", r.rounds},
      {"locked_vertices", r.locked_vertices},
      {"invalid_pairs", r.invalid_pairs},
      {"stop", decimate_stop_name(r.stop)},
      {"seconds", r.seconds},
      {"valid", r.validation.valid()},
      {"problems", r.validation.problems()},
      {"warnings", r.warnings},
  };
  return j.dump(2);
}

std::string to_text(const DecimateReport& r) {
  std::string s;
  s += "triangles    " + count(r.triangles_before) + " -> " + count(r.triangles_after) +
       format(" (%.2fx fewer", r.reduction());
  if (r.target_triangles > 0) s += ", target " + count(r.target_triangles);
  s += std::string(", stopped by ") + decimate_stop_name(r.stop) + ")\n";
  s += format(
      "distance     within %g mm of the input both ways (proven); measured max %.3g mm to "
      "the input (95 %% within %.3g), %.3g mm from it (95 %% within %.3g)\n",
      r.hausdorff_bound, r.distance.to_input, r.distance.to_input_p95, r.distance.from_input,
      r.distance.from_input_p95);
  s += format("volume       %.6g -> %.6g mm^3 (%+.3f %%)\n", r.volume_before, r.volume_after,
              100 * r.volume_change());
  s += format("rounds       %g", r.rounds);
  if (r.rounds > 1)
    s += ", " + count(r.locked_vertices) + " input vertices locked where a round self-intersected";
  s += format(", %.2f s\n", r.seconds);
  s += r.validation.valid() ? "verdict      VALID: closed, 2-manifold, outward, no degenerate "
                              "faces, no self-intersections\n"
                            : "verdict      NOT VALID\n";
  return s;
}

}  // namespace tpmsfill
