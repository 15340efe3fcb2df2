// `tpmsfill material info|fit`: the heterogeneous-material pipeline (seed 001). info: a tet
// mesh, or a closed surface filled with tets, given a material, checked and mapped onto the
// unit cube; or a fitted model's summary. fit: the same, then G and M fitted as splines and
// written as a model. This file only parses, calls the stages, times and prints.
#include <algorithm>
#include <cctype>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <functional>
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <string_view>
#include <tpmsfill/error.hpp>
#include <tpmsfill/io.hpp>
#include <tpmsfill/io/volume.hpp>
#include <tpmsfill/material.hpp>
#include <tpmsfill/sampling/spatial.hpp>
#include <tpmsfill/solid/cube_map.hpp>
#include <tpmsfill/solid/cube_octree.hpp>
#include <tpmsfill/solid/fold_certificate.hpp>
#include <tpmsfill/solid/solid_model.hpp>
#include <tpmsfill/solid/solid_spline.hpp>
#include <tpmsfill/solid/tet_mesh.hpp>
#include <tpmsfill/solid/tetrahedralize.hpp>
#include <tpmsfill/solid/tspline_basis.hpp>
#include <tpmsfill/units.hpp>
#include <vector>

#include <unistd.h>
#include "cli/commands.hpp"

#include "cli/job_files.hpp"
#include "cli/progress_flag.hpp"
#include "cli/terminal_progress.hpp"
#include "cli/units_flag.hpp"
#include "cli/validators.hpp"
#include "io/file_bytes.hpp"

namespace tpmsfill::cli {
namespace {

struct MaterialArgs {
  std::string input, output, tets_output, units = "mm";
  double cell = 0, feature_angle = 180;
  std::vector<std::string> material;  // KIND ARGS...
  std::vector<double> up{0, 0, 1};
  std::vector<std::uint32_t> corners;
  SolidFitOptions fit;
  std::string method = "euler";
  bool json = false, quiet = false, allow_folds = false;
  bool fold_free = false;  // --fold-free, the default: changes nothing
  bool tspline = false;    // info --tspline
  bool refinements_given = false, refine_share_given = false;
};

double number_argument(const std::string& text, const std::string& what) {
  const std::optional<double> value = detail::as_number(text);
  if (!value || !std::isfinite(*value))
    throw InputError("--material " + what + " must be a number, not '" + text + "'");
  return *value;
}

// The material the arguments name, checked (and a CT volume read) before any tets are made, as
// a rule that gives tets their material and returns a phrase saying what it is.
using MaterialRule = std::function<std::string(TetMesh&)>;

MaterialRule material_rule(const MaterialArgs& a) {
  const auto& m = a.material;
  if (m.empty())
    return [](TetMesh& mesh) { return mesh.material.empty() ? "none" : "from the file"; };
  auto need = [&](std::size_t n, const char* usage) {
    if (m.size() != n) throw InputError(std::string("--material takes ") + usage);
  };
  const std::string& kind = m[0];
  if (kind == "point") {
    need(4, "point X Y Z");
    const Vec3 c{number_argument(m[1], "X"), number_argument(m[2], "Y"),
                 number_argument(m[3], "Z")};
    const std::string phrase = "distance to (" + m[1] + ", " + m[2] + ", " + m[3] + ")";
    return [c, phrase](TetMesh& mesh) {
      mesh.material = distance_material(mesh, c);
      return phrase;
    };
  }
  if (kind == "geodesic") {
    need(2,
         "geodesic DEPTH (the bottom: boundary points within DEPTH mm of the lowest along --up)");
    const double depth = number_argument(m[1], "DEPTH");
    const Vec3 up{a.up[0], a.up[1], a.up[2]};
    return [depth, up](TetMesh& mesh) {
      const auto sources = bottom_boundary_points(mesh, up, depth);
      mesh.material = geodesic_material(mesh, sources);
      return "geodesic distance to the bottom (" + std::to_string(sources.size()) + " points)";
    };
  }
  if (kind == "x" || kind == "y" || kind == "z" || kind == "radial") {
    need(3, "x|y|z|radial START END");
    const Ramp ramp{.shape = kind == "radial" ? RampShape::Radial : RampShape::Linear,
                    .axis = {kind == "x" ? 1.0 : 0.0, kind == "y" ? 1.0 : 0.0,
                             kind == "z" || kind == "radial" ? 1.0 : 0.0},
                    .start = number_argument(m[1], "START"),
                    .end = number_argument(m[2], "END")};
    const std::string phrase = kind + " ramp " + m[1] + " to " + m[2];
    return [ramp, phrase](TetMesh& mesh) {
      mesh.material = ramp_material(mesh, ramp);
      return phrase;
    };
  }
  if (kind == "ct") {
    need(2, "ct FILE (a volume: NRRD, MetaImage, INR, .tdf)");
    auto volume = std::make_shared<const ScalarVolume>(read_volume_file(m[1]).volume);
    const std::string file = m[1];
    return [volume, file](TetMesh& mesh) {
      std::uint64_t outside = 0;
      mesh.material = volume_material(mesh, *volume, &outside);
      if (outside > 0)
        print_warnings({std::to_string(outside) + " of " + std::to_string(mesh.points.size()) +
                        " points lie outside " + file + "'s box: they take its border values"});
      return "sampled from " + file;
    };
  }
  throw InputError("unknown --material '" + kind +
                   "' (known: point, geodesic, x, y, z, radial, ct)");
}

// The input file, read once: a tet mesh, or a closed surface (mm) to fill with tets.
struct MaterialInput {
  TetMesh tets;
  std::optional<TriangleSoup> surface;
};

MaterialInput read_input(const MaterialArgs& a) {
  const ModelUnits units{.units = units_from_name(a.units)};
  MaterialInput in;
  if (tet_format_from_extension(a.input) != TetFormat::Auto) {
    in.tets = read_tet_mesh(a.input);
    const double factor = units.factor();
    if (factor != 1)
      for (Vec3& p : in.tets.points) p = factor * p;
  } else {
    in.surface = to_millimetres(read_mesh(a.input), units);
  }
  return in;
}

// The input as a tet mesh: as read, or its surface filled with tets (smaller in `finer`).
TetMesh input_tets(const MaterialArgs& a, const MaterialInput& in,
                   const std::vector<FinerRegion>& finer, nlohmann::ordered_json& j,
                   Progress* progress) {
  if (!in.surface) {
    j["source"] = "tet mesh";
    return in.tets;
  }
  const TriangleSoup& surface = *in.surface;
  TetMesh mesh = tetrahedralize(surface, {.cell_size = a.cell,
                                          .feature_angle = a.feature_angle,
                                          .finer = finer,
                                          .progress = progress});
  double surface_volume = 0;
  for (const Triangle& t : surface.triangles)
    surface_volume +=
        dot(surface.points[t[0]], cross(surface.points[t[1]], surface.points[t[2]])) / 6;
  j["source"] = "surface";
  j["surface_triangles"] = surface.triangles.size();
  j["surface_volume_mm3"] = std::abs(surface_volume);
  return mesh;
}

void print_json_or_text(const nlohmann::ordered_json& j, bool json) {
  if (json) {
    std::printf("%s\n", j.dump(2).c_str());
  } else {
    for (const auto& [key, value] : j.items())
      std::printf("%-22s %s\n", key.c_str(), value.dump().c_str());
  }
  std::fflush(stdout);
}

// The input as a mapped ball: read or tetrahedralized, checked (and turned when all its tets
// are negative) and mapped onto the cube. Figures go into `j`; without a map, the sentence
// saying why the tets are not a ball.
struct MappedSolid {
  TetMesh mesh;
  std::optional<MeshIndex> surface;  // the surface the tets were made from, if they were
  std::optional<CubeMap> map;
  std::optional<std::string> problem;
};

MappedSolid map_once(const MaterialArgs& a, const MaterialInput& in,
                     const std::vector<FinerRegion>& finer, nlohmann::ordered_json& j,
                     std::vector<std::string>& warnings, Progress* progress) {
  MappedSolid out;
  out.mesh = input_tets(a, in, finer, j, progress);
  TetMesh& mesh = out.mesh;
  TetMeshReport report = check_tet_mesh(mesh);
  if (report.tets > 0 && report.negative_tets == report.tets) {  // the other convention: turned
    mesh = with_positive_tets(std::move(mesh), report);
    report = check_tet_mesh(mesh);
  }
  j["points"] = report.points;
  j["tets"] = report.tets;
  j["volume_mm3"] = report.volume;
  j["boundary_faces"] = report.boundary_faces;
  j["genus"] = report.genus ? nlohmann::ordered_json(*report.genus) : nullptr;
  out.problem = ball_problem(report);
  if (j.contains("surface_volume_mm3")) {
    const double before = j["surface_volume_mm3"], change = report.volume / before - 1;
    if (std::abs(change) > 0.01)
      warnings.push_back("the tets' volume differs from the surface's by " +
                         std::to_string(100 * change) +
                         " % (sharp edges rounded? try --feature-angle 60 or a smaller --cell)");
  }
  if (out.problem) return out;
  const std::size_t points_before = mesh.points.size();
  mesh = with_chords_split(std::move(mesh));
  j["split_points"] = mesh.points.size() - points_before;
  j["points"] = mesh.points.size();
  j["tets"] = mesh.tets.size();
  CubeMapOptions options;
  options.progress = progress;
  if (!a.corners.empty()) {
    std::array<std::uint32_t, 8> c{};
    std::copy(a.corners.begin(), a.corners.end(), c.begin());
    options.corners = c;
  }
  const CubeMap& map = out.map.emplace(map_to_cube(mesh, options));
  j["cube_map"] = {{"corners", map.corners},
                   {"flipped_boundary_faces", map.flipped_boundary_faces},
                   {"relaxed_patches", map.relaxed_patches},
                   {"harmonic_inverted_tets", map.harmonic_inverted_tets},
                   {"untangled_points", map.untangled_points},
                   {"inverted_tets", map.inverted_tets},
                   {"flat_tets", map.flat_tets},
                   {"interior_points", map.interior_points}};
  return out;
}

// A ball to mesh finer around a folded tet: 3 times its longest edge across, tets of 0.3 times
// it (a circumradius of about half the edge, halved). A centre within half the radius of a
// region as fine or finer adds nothing.
void add_finer_region(const TetMesh& mesh, const Tet& tet, std::vector<FinerRegion>& finer) {
  Vec3 centre{0, 0, 0};
  double longest = 0;
  for (int k = 0; k < 4; ++k) {
    centre = centre + 0.25 * mesh.points[tet[k]];
    for (int l = k + 1; l < 4; ++l)
      longest = std::max(longest, norm(mesh.points[tet[k]] - mesh.points[tet[l]]));
  }
  const FinerRegion region{centre, 3 * longest, 0.3 * longest};
  const bool covered = std::any_of(finer.begin(), finer.end(), [&](const FinerRegion& r) {
    return r.size <= region.size && norm(r.centre - centre) < 0.5 * r.radius;
  });
  if (!covered) finer.push_back(region);
}

// The progress of a finer pass: its stages (tetrahedralize, cube map) named with the pass,
// so that a user watching the same stages come round again sees why.
class PassProgress : public Progress {
 public:
  PassProgress(Progress* to, std::string pass) : to_(to), pass_(std::move(pass)) {}
  void begin(std::string_view stage) override {
    to_->begin(StageInfo{.name = stage, .step = pass_});
  }
  bool report(double fraction) override { return to_->report(fraction); }

 private:
  Progress* to_;
  std::string pass_;
};

// map_once(), and where the map folds on tets made from a surface, the surface meshed again
// with smaller tets around the folded ones, up to kFinerPasses times: the lower femur's
// stand-in kept 218 folded tets under its condyles at diagonal / 30 (43 at / 45 everywhere),
// 8 after one pass, 2 after two; a third made the same tets, the regions' sizes at the
// floor (cell / 8). Finer is not always better (with a floor of cell / 16 its passes went
// 116, 7, 25, 3,897 folded: the untangling of 241 k tets did not finish), so the pass with
// the fewest folds is kept, and a pass with no fewer ends the loop. The kept map's last folds
// are then untangled locally (with_folds_opened(); only there, since in every pass it changed
// which balls the next meshed finer). (Given corners are point ids of these tets, so they keep
// them as is.)
MappedSolid map_input(const MaterialArgs& a, nlohmann::ordered_json& j,
                      std::vector<std::string>& warnings, Progress* progress) {
  constexpr int kFinerPasses = 2;
  const MaterialRule give_material = material_rule(a);
  const MaterialInput input = read_input(a);
  struct Pass {
    MappedSolid solid;
    nlohmann::ordered_json j;
    std::vector<std::string> found;
    int index = 0;  // its folded tets: folded_by_pass[index]
  };
  std::optional<Pass> best;
  std::vector<FinerRegion> finer;
  std::vector<std::size_t> folded_by_pass;
  for (int pass = 0;; ++pass) {
    Pass now;
    now.j = j;
    now.index = pass;
    std::optional<PassProgress> pass_progress;
    if (progress && pass > 0)
      pass_progress.emplace(progress, "pass " + std::to_string(pass + 1) + " of up to " +
                                          std::to_string(kFinerPasses + 1) + ", finer around " +
                                          std::to_string(folded_by_pass.back()) + " folded tets");
    now.solid =
        map_once(a, input, finer, now.j, now.found, pass_progress ? &*pass_progress : progress);
    const std::vector<std::uint32_t> folded =
        now.solid.map ? folded_tets(now.solid.mesh, *now.solid.map) : std::vector<std::uint32_t>{};
    folded_by_pass.push_back(folded.size());
    // A finer mesh that is no ball (no map) never beats one that maps.
    const bool worse = best && (!now.solid.map || folded.size() >= folded_by_pass[best->index]);
    const std::size_t regions = finer.size();
    if (!worse && !folded.empty() && input.surface && a.corners.empty() && pass < kFinerPasses)
      for (std::uint32_t t : folded)
        add_finer_region(now.solid.mesh, now.solid.mesh.tets[t], finer);
    if (!worse) best = std::move(now);
    // Done when fold-free, out of passes, every fold already inside a ball as fine, or no
    // fewer folds than the best pass.
    if (!worse && finer.size() != regions) continue;
    j = std::move(best->j);
    std::string passes;
    if (pass > 0) {
      j["cube_map"]["finer_passes"] = pass;
      j["cube_map"]["finer_regions"] = finer.size();
      j["cube_map"]["folded_by_pass"] = folded_by_pass;
      j["cube_map"]["kept_pass"] = best->index;
      for (std::size_t n : folded_by_pass)
        passes += (passes.empty() ? "" : ", ") + std::to_string(n);
      passes =
          ", after " + std::to_string(pass) + " passes meshing finer around them (" + passes +
          " folded" +
          (best->index < pass ? "; pass " + std::to_string(best->index) + "'s tets kept" : "") +
          ")";
    }
    MappedSolid out = std::move(best->solid);
    std::size_t kept_folded = folded_by_pass[best->index];
    if (kept_folded > 0 && out.map) {  // the kept map's last folds, each region alone
      out.map = with_folds_opened(out.mesh, std::move(*out.map), progress);
      const std::size_t left = out.map->inverted_tets + out.map->flat_tets;
      j["cube_map"]["inverted_tets"] = out.map->inverted_tets;
      j["cube_map"]["flat_tets"] = out.map->flat_tets;
      j["cube_map"]["opened_points"] = out.map->opened_points;
      j["cube_map"]["folded_after_opening"] = left;
      if (left > 0)
        passes += " and a local untangling of the last (" + std::to_string(kept_folded) + " to " +
                  std::to_string(left) + ")";
      kept_folded = left;
    }
    if (kept_folded > 0)
      best->found.push_back(std::to_string(kept_folded) + " of " +
                            std::to_string(out.mesh.tets.size()) +
                            " tets fold over or flatten in the cube map, untangled or not" +
                            passes + " (smaller tets or other corners usually help)");
    warnings.insert(warnings.end(), best->found.begin(), best->found.end());
    if (!out.problem) {  // the map does not need the material: given once, to the kept tets
      j["material"] = give_material(out.mesh);
      if (!out.mesh.material.empty()) {
        const auto [lo, hi] =
            std::minmax_element(out.mesh.material.begin(), out.mesh.material.end());
        j["material_range"] = {*lo, *hi};
      }
    }
    if (input.surface) out.surface = build_index(*input.surface);  // the fit's boundary
    return out;
  }
}

int refuse_non_ball(const MaterialArgs& a, const std::optional<std::string>& problem) {
  std::fprintf(stderr, "tpmsfill: %s cannot be mapped onto the cube: %s\n", a.input.c_str(),
               problem->c_str());
  return kNotValid;
}

nlohmann::ordered_json round_json(const FitRound& r, bool material) {
  nlohmann::ordered_json j = {{"control_points", r.control_points},
                              {"elements", r.elements},
                              {"geometry_iterations", r.geometry_iterations},
                              {"geometry_rs_percent", r.geometry_rs},
                              {"geometry_rms_mm", r.geometry_rms},
                              {"geometry_max_mm", r.geometry_max}};
  if (material) {
    j["material_iterations"] = r.material_iterations;
    j["material_rs_percent"] = r.material_rs;
    j["material_rms"] = r.material_rms;
    j["material_max"] = r.material_max;
  }
  if (r.undone_steps > 0) j["undone_steps"] = r.undone_steps;              // not in the file
  if (r.solve_iterations > 0) j["solve_iterations"] = r.solve_iterations;  // not in the file
  if (r.fitted_folded_samples > 0) {                                       // not in the file
    j["fitted_folded_samples"] = r.fitted_folded_samples;
    j["untangled_control_points"] = r.untangled_functions;
  }
  if (r.held_functions > 0) j["held_control_points"] = r.held_functions;  // not in the file
  if (r.found_folds > 0) j["found_folded_points"] = r.found_folds;        // not in the file
  j["folded_samples"] = r.folded_samples;
  j["samples"] = r.samples;
  if (r.fine_samples > 0) {  // the last round; not in the file
    j["fine_folded_samples"] = r.fine_folded_samples;
    j["fine_samples"] = r.fine_samples;
  }
  j["split_leaves"] = r.split;
  j["seconds"] = r.seconds;
  return j;
}

// A point of the cube as the user can find it: (u, v, w) and its image in mm.
std::string where_in_solid(const SolidSpline& spline, const std::array<double, 3>& uvw) {
  const Vec3 x = evaluate_solid(spline, uvw).position;
  char where[160];
  std::snprintf(where, sizeof where, "(u, v, w) = (%.4f, %.4f, %.4f), near (%.6g, %.6g, %.6g) mm",
                uvw[0], uvw[1], uvw[2], x.x, x.y, x.z);
  return where;
}

// What the bound found folded, in words: "det J <= 0 found in 3 of 9,000 elements (least
// at ...)".
std::string found_folds(const SolidSpline& spline, const FoldCertificate& c) {
  return "det J <= 0 found in " + std::to_string(c.folded) + " of " + std::to_string(c.elements) +
         " elements (least at " + where_in_solid(spline, c.fold) + ")";
}

// Where det J_G > 0 is proven (fold_certificate.hpp), as the report's "fold_certificate",
// and a warning where a fold was found between the points the fit watched; the certificate
// itself in `made` when asked.
nlohmann::ordered_json certify(const SolidSpline& spline, std::vector<std::string>& warnings,
                               FoldCertificate* made = nullptr) {
  const auto t0 = std::chrono::steady_clock::now();
  const FoldCertificate c = certify_fold_free(spline);
  if (made) *made = c;
  if (c.folded > 0)
    warnings.push_back("G folds between the points the fit watched: " + found_folds(spline, c) +
                       "; slices may turn triangles over there");
  return {
      {"elements", c.elements},
      {"proven", c.proven},
      {"folded", c.folded},
      {"undecided", c.undecided},
      {"seconds", std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count()}};
}

// `material info MODEL`: what a fitted model holds.
int run_model_info(const MaterialArgs& a) {
  const SolidModel model = read_solid_model(a.input);
  const SolidSpline& s = model.fit.spline;
  nlohmann::ordered_json j;
  j["input"] = a.input;
  j["provenance"] = model.provenance;
  j["basis"] = s.basis.spans.size() == 1 && s.basis.spans[0] != 1 ? "uniform cubic B-spline"
                                                                  : "cubic THB on an octree";
  j["control_points"] = s.geometry.size();
  j["elements"] = s.basis.elements.size();
  j["levels"] = s.basis.spans.size();
  if (!s.material.empty()) {
    const auto [lo, hi] = std::minmax_element(s.material.begin(), s.material.end());
    j["material_control_range"] = {*lo, *hi};
  }
  j["greville_rms_mm"] = model.fit.greville_geometry_rms;
  nlohmann::ordered_json rounds = nlohmann::ordered_json::array();
  for (const FitRound& r : model.fit.rounds) rounds.push_back(round_json(r, !s.material.empty()));
  j["rounds"] = rounds;
  std::vector<std::string> warnings;
  j["fold_certificate"] = certify(s, warnings);
  print_json_or_text(j, a.json);
  print_warnings(warnings);
  return kOk;
}

int run_material_info(const MaterialArgs& a) {
  if (tpmsfill::detail::lower_extension(a.input) == ".tsm") {
    if (a.tspline)
      throw InputError("--tspline checks the octree a fit would make: give the mesh, not a model");
    return run_model_info(a);
  }
  if (!a.tets_output.empty()) {
    // What write_tet_mesh() takes, checked before the work rather than after it.
    const std::string ext = tpmsfill::detail::lower_extension(a.tets_output);
    if (ext != ".vtk" && ext != ".mesh")
      throw InputError("--tets " + a.tets_output + ": a tet mesh is written as .vtk or .mesh");
    require_writable_outputs({a.input}, {{"--tets", a.tets_output}});
  }
  const auto t0 = std::chrono::steady_clock::now();
  nlohmann::ordered_json j;
  j["input"] = a.input;
  std::vector<std::string> warnings;
  std::unique_ptr<TerminalProgress> progress;
  if (progress_wanted(false)) progress = std::make_unique<TerminalProgress>();
  const MappedSolid solid = map_input(a, j, warnings, progress.get());
  if (progress) progress->clear();
  if (solid.map) {
    // The splines' octree: cells split while they hold more than 5 tets (the seed's rule).
    const CubeOctree octree = build_cube_octree(tet_centroids(solid.mesh, *solid.map));
    j["octree"] = {{"leaves", octree.leaves.size()},
                   {"deepest_level", octree.deepest},
                   {"balance_splits", octree.balance_splits},
                   {"overfull_leaves", octree.overfull}};
    if (a.tspline) {
      // The seed's T-splines on that octree, beside the THB basis the fit uses.
      const SplineBasis tspline = tspline_basis(octree);
      const TSplineCheck check = check_tspline(tspline);
      j["thb"] = {{"functions", thb_basis(octree).functions.size()}};
      j["tspline"] = {{"functions", tspline.functions.size()},
                      {"elements", tspline.elements.size()},
                      {"unity_error", check.unity_error},
                      {"sum_range", check.sum_range},
                      {"incompatible_pairs", check.incompatible_pairs},
                      {"duplicate_functions", check.duplicates},
                      {"cells_affected", check.cells.size()},
                      {"suitable", check.suitable()}};
      char off[64];
      std::snprintf(off, sizeof off, "%.3g to %.3g", check.sum_range[0], check.sum_range[1]);
      if (!check.suitable())
        warnings.push_back(
            "the seed's T-splines on this octree do not sum to one (sums from " + std::string(off) +
            ") and " + std::to_string(check.incompatible_pairs) +
            " pairs of functions are not dual-compatible (linear independence is not assured), "
            "in " +
            std::to_string(check.cells.size()) + " of " + std::to_string(octree.leaves.size()) +
            " cells: `material fit` uses THB, which has both on every octree");
    }
  }
  j["wall_seconds"] = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  if (!a.tets_output.empty() && !solid.problem) write_tet_mesh(a.tets_output, solid.mesh);
  if (solid.problem) j["problem"] = *solid.problem;
  print_json_or_text(j, a.json);
  print_warnings(warnings);
  return solid.problem ? refuse_non_ball(a, solid.problem) : kOk;
}

int run_material_fit(const MaterialArgs& a) {
  if (tpmsfill::detail::lower_extension(a.output) != ".tsm")
    throw InputError(a.output + ": a solid spline model is written as .tsm");
  // A uniform basis is fitted in one round: a refinement asked for beside it would be dropped.
  if (a.fit.uniform > 0 && ((a.refinements_given && a.fit.refinements > 0) || a.refine_share_given))
    throw InputError(
        "--uniform fits one round on its N^3 basis: it takes no --refine-share, and "
        "--refinements 0 at most");
  require_writable_outputs({a.input}, {{"OUT", a.output}});
  const auto t0 = std::chrono::steady_clock::now();
  nlohmann::ordered_json j;
  j["input"] = a.input;
  std::vector<std::string> warnings;
  std::unique_ptr<TerminalProgress> progress;
  if (progress_wanted(a.quiet)) progress = std::make_unique<TerminalProgress>();
  const MappedSolid solid = map_input(a, j, warnings, progress.get());
  if (solid.problem) {
    if (progress) progress->clear();
    print_warnings(warnings);
    return refuse_non_ball(a, solid.problem);
  }
  SolidFitOptions options = a.fit;
  options.fold_free = !a.allow_folds;
  options.method = a.method == "euler" ? SolidFitMethod::Euler : SolidFitMethod::Newton;
  options.progress = progress.get();
  if (solid.surface) options.surface = &*solid.surface;
  SolidModel model{fit_solid_spline(solid.mesh, *solid.map, options), ""};
  if (progress) progress->clear();
  progress.reset();
  const bool material = !solid.mesh.material.empty();
  model.provenance =
      "tpmsfill material fit " + a.input + " (material: " + j["material"].get<std::string>() + ")";
  j["basis"] = options.uniform > 0 ? "uniform cubic B-spline" : "cubic THB on an octree";
  j["greville_rms_mm"] = model.fit.greville_geometry_rms;
  nlohmann::ordered_json rounds = nlohmann::ordered_json::array();
  for (const FitRound& r : model.fit.rounds) rounds.push_back(round_json(r, material));
  j["rounds"] = rounds;
  const FitRound& last = model.fit.rounds.back();
  // Fold-free (the default), a folded G is not what was asked: refused, with where, nothing
  // written. The report still says how close the fit came (JSON "refused").
  const auto refuse = [&](const std::string& why) {
    j["refused"] = why + "; nothing written";
    if (a.json) print_json_or_text(j, true);
    print_warnings(warnings);
    std::fprintf(stderr,
                 "tpmsfill: %s: %s; nothing written; try a smaller --cell, fewer --refinements, "
                 "or --allow-folds\n",
                 a.input.c_str(), why.c_str());
    return kNotValid;
  };
  if (options.fold_free && (last.folded_samples > 0 || last.fine_folded_samples > 0))
    return refuse("G still folds (det J <= 0) at " + std::to_string(last.folded_samples) + " of " +
                  std::to_string(last.samples) + " Gauss points and " +
                  std::to_string(last.fine_folded_samples) + " of " +
                  std::to_string(last.fine_samples) + " points of a finer sample (worst at " +
                  where_in_solid(model.fit.spline, last.worst_fold) + ")");
  if (last.folded_samples > 0)
    warnings.push_back("G folds (det J <= 0) at " + std::to_string(last.folded_samples) + " of " +
                       std::to_string(last.samples) +
                       " Gauss points (--allow-folds; without it the fit keeps G fold-free)");
  if (last.fine_folded_samples > 0)
    warnings.push_back("G folds between its Gauss points too: det J <= 0 at " +
                       std::to_string(last.fine_folded_samples) + " of " +
                       std::to_string(last.fine_samples) +
                       " points of a finer sample (5^3 inside an element, 4^3 reaching its faces, "
                       "9^3 along the cube's edges)");
  for (std::size_t k = 0; k < model.fit.rounds.size(); ++k)
    if (model.fit.rounds[k].undone_steps > 0)
      warnings.push_back("round " + std::to_string(k + 1) + ": the fit's last " +
                         std::to_string(model.fit.rounds[k].undone_steps) +
                         " steps moved it away from its data (RS fell over a point below its "
                         "best); the model keeps the best step's (try --method euler)");
  if (!material) warnings.push_back("the tets have no material: only G was fitted");
  // Fold-free, a fold the bound finds between the watched points is refused too: a model
  // that slices with turned-over triangles is not the solid asked for.
  FoldCertificate bound;
  std::vector<std::string> bound_warnings;
  j["fold_certificate"] = certify(model.fit.spline, bound_warnings, &bound);
  if (options.fold_free && bound.folded > 0)
    return refuse("G folds between the points the fit watched: " +
                  found_folds(model.fit.spline, bound));
  warnings.insert(warnings.end(), bound_warnings.begin(), bound_warnings.end());
  write_solid_model(a.output, model);
  j["output"] = a.output;
  j["wall_seconds"] = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  if (!a.quiet || a.json) print_json_or_text(j, a.json);
  print_warnings(warnings);
  return kOk;
}

}  // namespace

// The options `info` and `fit` share: the input, its material and its corners.
void add_input_options(CLI::App* sub, MaterialArgs& args) {
  sub->add_option("--cell", args.cell,
                  "Surfaces: largest tet size, mm (default: the bounding box's diagonal / 30)")
      ->check(positive());
  sub->add_option("--feature-angle", args.feature_angle,
                  "Surfaces: keep edges sharper than this many degrees (default 180: none, for "
                  "organic scans; 60 keeps a CAD part's edges)")
      ->check(between(1, 180, "1 to 180"));
  sub->add_option("--material", args.material, "KIND ARGS...: see below")->expected(1, 4);
  sub->add_option("--up", args.up, "The up direction for --material geodesic (default 0 0 1)")
      ->expected(3);
  sub->add_option("--corners", args.corners,
                  "Eight boundary point ids for the cube's corners, corner k at (k&1, k>>1&1, "
                  "k>>2&1) (default: found from the bounding box)")
      ->expected(8);
  add_units_flag(sub, args.units);
  sub->add_flag("--json", args.json, "Print JSON instead of text");
}

constexpr const char* kInputHelp =
    "IN is a tet mesh (.mesh + .sol, .node + .ele, .vtk) or a closed surface (STL, OBJ, PLY, "
    "OFF), which is filled with tets by CGAL's 3D mesh generation. The tets must form a ball: "
    "positive tets, a closed 2-manifold boundary, one piece, genus 0. The material comes from "
    "the file, or from --material:\n"
    "  point X Y Z          distance to a point, mm (the seed's duck)\n"
    "  geodesic DEPTH       geodesic distance to the bottom (boundary points within DEPTH mm of "
    "the lowest along --up; heat method, harmonic inside: the seed's femur)\n"
    "  x|y|z|radial A B     a ramp from A to B across the part\n"
    "  ct FILE              a CT or other volume, trilinear\n"
    "The tets are mapped onto [0,1]^3 (corners, curves, mean-value patches, harmonic "
    "interior: docs/method.md), and the flipped and inverted counts are reported.\n\n";

Command add_material_command(CLI::App& app) {
  auto args = std::make_shared<MaterialArgs>();
  CLI::App* material = app.add_subcommand(
      "material", "Heterogeneous-material solids (seed 001): tet meshes with a material");
  material->require_subcommand(1);
  CLI::App* info = material->add_subcommand(
      "info",
      "Check a tet mesh (or fill a closed surface with tets), give it a material, map it "
      "onto the unit cube, and say what was found; or say what a fitted model (.tsm) holds");
  info->footer(std::string(kInputHelp) +
               "Examples:\n"
               "  tpmsfill material info femur-end.stl --cell 2 --material geodesic 1 --tets "
               "femur.vtk\n"
               "  tpmsfill material info duck.mesh --material point 0 0 20 --json\n"
               "  tpmsfill material info duck.tsm\n\n"
               "Exit code 0: mapped; 1: the tets are not a ball (the sentence says why); 2: "
               "unreadable input or bad arguments.");
  info->add_option("IN", args->input, "Tet mesh, closed surface (mm), or a model (.tsm)")
      ->required();
  add_input_options(info, *args);
  info->add_option("--tets", args->tets_output,
                   "Write the tets with their material here (.vtk or .mesh + .sol)");
  info->add_flag("--tspline", args->tspline,
                 "Also build the seed's trivariate T-splines on the octree (anchors at its "
                 "vertices, knots by rays) and check them: do they sum to one, are they "
                 "dual-compatible (so linearly independent)? Seconds on large meshes");
  add_progress_flag(info);  // meshing and mapping a large part take minutes

  CLI::App* fit = material->add_subcommand(
      "fit",
      "Fit the solid and its material as trivariate cubic splines G and M on one adaptive "
      "basis (THB on an octree), and write the model (.tsm)");
  fit->footer(std::string(kInputHelp) +
              "The basis is THB on an octree split while a cell holds more than "
              "--max-tets-per-cell tets; each control value starts at the tets' value at its "
              "Greville point, then steps on the seed's energy (data term, first- and "
              "second-order regularisers, boundary normals) run until the similarity ratio RS "
              "moves by less than 0.05 points: the seed's explicit Euler steps by default, or "
              "damped Newton steps (--method newton); the leaves of largest residual "
              "(--refine-share) are split and the fit goes on, --refinements times. --uniform N "
              "fits the seed's baseline instead, a uniform "
              "tensor-product spline with N^3 control points.\n\n"
              "Examples:\n"
              "  tpmsfill material fit duck.stl duck.tsm --material point 0 0 20\n"
              "  tpmsfill material fit duck.stl duck-uniform.tsm --material point 0 0 20 "
              "--uniform 38\n\n"
              "Exit code 0: fitted and written; 1: the tets are not a ball; 2: unreadable input "
              "or bad arguments.");
  fit->add_option("IN", args->input, "Tet mesh or closed surface, mm")->required();
  fit->add_option("OUT", args->output, "The model to write (.tsm)")->required();
  add_input_options(fit, *args);
  fit->add_option("--max-tets-per-cell", args->fit.octree.max_per_cell,
                  "Split octree cells holding more tets than this (default 5, the seed's)")
      ->check(CLI::Range(1, 1000000));
  fit->add_option("--max-level", args->fit.octree.max_level,
                  "Deepest octree level (default 8: 256 cells per axis)")
      ->check(CLI::Range(2, 12));
  fit->add_option("--uniform", args->fit.uniform,
                  "Fit a uniform tensor-product spline with N^3 control points instead")
      ->check(CLI::Range(4, 100));
  fit->add_option("--method", args->method,
                  "euler (default: the seed's explicit steps of --step) or newton (damped Newton "
                  "steps solved by conjugate gradients, to the energy's minimum; slower)")
      ->check(CLI::IsMember({"newton", "euler"}));
  fit->add_option("--step", args->fit.step, "The Euler step epsilon (default 0.5; seed 0.4-0.6)")
      ->check(between(0.01, 1, "0.01 to 1"));
  fit->add_option("--refinements", args->fit.refinements,
                  "Progressive refinement rounds after the first (default 2)")
      ->check(CLI::Range(0, 20));
  fit->add_option("--refine-share", args->fit.refine_share,
                  "Which leaves a refinement round splits: the fewest that hold S of G's squared "
                  "residual, and of M's (default 0.5; more: closer fits, more control points); "
                  "0: those whose residual exceeds the mean by 2 standard deviations")
      ->check(between(0, 1, "0 to 1"));
  fit->add_option("--rs-change", args->fit.rs_change,
                  "Stop a field when RS moves by less than this many points a step (default 0.05; "
                  "0: run --max-iterations steps)")
      ->check(CLI::Range(0.0, 100.0));
  fit->add_option("--max-iterations", args->fit.max_iterations,
                  "Steps per field and round, at most (default 50)")
      ->check(CLI::Range(1, 10000));
  auto* allow =
      fit->add_flag("--allow-folds", args->allow_folds,
                    "Let G fold (det J <= 0) near the cube's faces and edges, and warn "
                    "of it: the plain fit, up to 2.3 times faster. By default G is "
                    "kept fold-free at every Gauss point and 5^3 + 4^3 points an element "
                    "(9^3 more along the cube's edges), or the model is refused with where");
  fit->add_flag("--fold-free", args->fold_free,
                "The default: keep G fold-free (for scripts written when it was not)")
      ->excludes(allow);
  fit->add_flag("--quiet", args->quiet, "Print nothing but errors and warnings");
  auto model_commands = add_material_model_commands(material);
  return [args, fit, model_commands] {
    if (const std::optional<int> code = model_commands()) return *code;
    args->refinements_given = fit->count("--refinements") > 0;
    args->refine_share_given = fit->count("--refine-share") > 0;
    return fit->parsed() ? run_material_fit(*args) : run_material_info(*args);
  };
}

}  // namespace tpmsfill::cli
