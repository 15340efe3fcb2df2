// to_json(RepairReport) and to_text(RepairReport): what `tpmsfill repair` prints (fields in
// repair.hpp). No CGAL here.
#include <cinttypes>
#include <cstdio>
#include <nlohmann/json.hpp>
#include <string>

#include "tpmsfill/repair.hpp"

namespace tpmsfill {
namespace {

using json = nlohmann::ordered_json;

std::string g(double v) {
  char buffer[64];
  std::snprintf(buffer, sizeof buffer, "%.6g", v);
  return buffer;
}

// The input's state in a few words, as `tpmsfill check` would print it.
std::string summary(const MeshCheck& c) {
  std::string s = std::to_string(c.triangles) + " triangles, " + std::to_string(c.vertices) +
                  " vertices, " + std::to_string(c.components) + " component" +
                  (c.components == 1 ? "" : "s");
  if (c.volume) s += ", volume " + g(*c.volume) + " mm^3";
  if (c.genus) s += ", genus " + std::to_string(*c.genus);
  return s;
}

json deviation_json(const RepairDeviation& d) {
  return {{"to_input", {{"max", d.to_input.max}, {"p95", d.to_input.p95}}},
          {"from_input", {{"max", d.from_input.max}, {"p95", d.from_input.p95}}},
          {"volume_change", d.volume_change},
          {"bbox_growth", d.bbox_growth},
          {"added_thickness", d.added_thickness}};
}

std::string deviation_text(const RepairDeviation& d) {
  char s[256];
  std::snprintf(s, sizeof s,
                "output to input max %.3g mm (95 %% within %.3g), input to output max %.3g mm "
                "(95 %% within %.3g), volume %+.2f %%",
                d.to_input.max, d.to_input.p95, d.from_input.max, d.from_input.p95,
                100 * d.volume_change);
  return s;
}

}  // namespace

std::string to_json(const RepairReport& r) {
  json actions = json::array();
  for (const RepairAction& a : r.actions)
    actions.push_back(
        {{"defect", a.defect}, {"found", a.found}, {"action", a.action}, {"fixed", a.fixed}});
  json candidates = json::array();
  for (const RepairCandidate& c : r.candidates) {
    const bool wrap = c.route == "wrap", volume = c.route == "volume";
    candidates.push_back({{"route", c.route},
                          {"alpha", wrap ? json(c.alpha) : json(nullptr)},
                          {"offset", wrap ? json(c.offset) : json(nullptr)},
                          {"voxel", volume ? json(c.voxel) : json(nullptr)},
                          {"decimation", c.decimation > 0 ? json(c.decimation) : json(nullptr)},
                          {"triangles", c.triangles},
                          {"valid", c.valid},
                          {"taken", c.taken},
                          {"deviation", c.valid ? deviation_json(c.deviation) : json(nullptr)},
                          {"failure", c.valid ? json(nullptr) : json(c.failure)}});
  }
  json j = {
      {"valid", r.valid()},
      {"problems", r.after.problems()},
      {"warnings", r.warnings},
      {"within_tolerance", r.within_tolerance},
      {"tolerance", r.tolerance},
      {"deviation", deviation_json(r.deviation)},
      {"route", r.route.empty() ? json(nullptr) : json(r.route)},
      {"candidates", std::move(candidates)},
      {"wrapped", r.wrapped},
      {"alpha", r.wrapped ? json(r.alpha) : json(nullptr)},
      {"offset", r.wrapped ? json(r.offset) : json(nullptr)},
      {"voxel", r.route == "volume" ? json(r.voxel) : json(nullptr)},
      {"unresolved", r.unresolved},
      {"float_repasses", r.float_repasses},
      {"min_component_fraction", r.min_component_fraction},
      {"small_component_threshold", r.small_component_threshold},
      {"components", r.components},
      {"holes_faired", r.holes_faired},
      {"holes_flat", r.holes_flat},
      {"fairing_undone", r.fairing_undone},
      {"actions", std::move(actions)},
      {"before", json::parse(to_json(r.before))},
      {"after", json::parse(to_json(r.after))},
  };
  return j.dump(2);
}

std::string to_text(const RepairReport& r) {
  std::string s = "input    " + summary(r.before) + "\n";
  const std::vector<std::string> input_problems = r.before.problems();
  if (input_problems.empty()) s += "  the input is already valid\n";
  for (const std::string& p : input_problems) s += "  - " + p + "\n";

  bool any = false;
  for (const RepairAction& a : r.actions) {
    if (a.found == 0) continue;
    if (!any) s += "repairs\n";
    any = true;
    std::string head = "  " + a.defect + ": " + std::to_string(a.found) + " found, " + a.action;
    if (a.fixed != a.found) head += " (" + std::to_string(a.fixed) + " fixed)";
    if (a.defect == "small components")
      head += " (area below " + g(r.small_component_threshold) + " mm^2)";
    if (a.defect == "holes" && a.fixed > 0)
      head += " (" + std::to_string(r.holes_flat) + " flat, " + std::to_string(r.holes_faired) +
              " faired" +
              (r.fairing_undone ? ", " + std::to_string(r.fairing_undone) +
                                      " left unfaired where fairing outgrew the hole"
                                : std::string()) +
              ")";
    s += head + "\n";
  }
  if (!any) s += "repairs  none needed\n";
  s += "specks   components with area below " + g(r.small_component_threshold) + " mm^2 (" +
       g(r.min_component_fraction) + " of the largest of " + std::to_string(r.components) +
       ") are removed\n";

  if (r.float_repasses > 0)
    s += "float    rounding to float (for STL) broke the repair: repaired again " +
         std::to_string(r.float_repasses) + (r.float_repasses == 1 ? " time\n" : " times\n");
  if (r.candidates.size() > 1) {
    s += "routes   tried because the repaired mesh " +
         std::string(r.candidates.front().valid ? "was valid but" : "still had:") + "\n";
    for (const std::string& p : r.unresolved) s += "  - " + p + "\n";
    for (const RepairCandidate& c : r.candidates) {
      s += "  " + c.route;
      if (c.route == "wrap") s += " (alpha " + g(c.alpha) + " mm, offset " + g(c.offset) + " mm)";
      if (c.route == "volume")
        s += " (voxel " + g(c.voxel) + " mm" +
             (c.decimation > 0 ? ", decimated within " + g(c.decimation) + " mm" : "") + ")";
      if (c.valid)
        s += ": valid, lies up to " + g(c.deviation.worst()) + " mm from the input" +
             (c.deviation.worst() <= r.tolerance ? "" : " (beyond the tolerance)");
      else
        s += ": " + c.failure;
      if (c.taken) s += "  <- taken";
      s += "\n";
    }
  }
  s += "output   " + summary(r.after) + "\n";
  if (r.valid()) {
    s += "deviation " + deviation_text(r.deviation) + "; tolerance " + g(r.tolerance) +
         " mm: " + (r.within_tolerance ? "within" : "BEYOND") + "\n";
  }
  for (const std::string& w : r.warnings) s += "warning  " + w + "\n";
  if (r.valid() && !r.within_tolerance) {
    // Valid, yet not the part that came in: said here, where the verdict is read.
    s += "verdict: VALID but BEYOND the tolerance: it lies up to " + g(r.deviation.worst()) +
         " mm from the input, the tolerance is " + g(r.tolerance) +
         " mm; held back (not written) unless the deviation is accepted\n";
  } else if (r.valid()) {
    s += "verdict: VALID: a closed, outward-oriented 2-manifold without self-intersections or "
         "degenerate faces\n";
  } else {
    s += "verdict: NOT VALID\n";
    for (const std::string& p : r.after.problems()) s += "  - " + p + "\n";
  }
  return s;
}

}  // namespace tpmsfill
