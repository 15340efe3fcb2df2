// `tpmsfill material info|fit` as a user runs them: a surface filled with tets and mapped onto
// the cube, a tet mesh written and read back with its material, a model fitted, written and
// summarised, and refusals with their exit codes.
#include <gtest/gtest.h>

// GCC 12 reports a false -Wrestrict inside std::string concatenation here (GCC bug 105329).
#pragma GCC diagnostic ignored "-Wrestrict"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>
#include <tpmsfill/check.hpp>
#include <tpmsfill/io.hpp>
#include <tpmsfill/solid/solid_model.hpp>
#include <tpmsfill/solid/solid_slice.hpp>
#include <tpmsfill/solid/tet_mesh.hpp>

#include "test_util.hpp"

using namespace tpmsfill;
namespace fs = std::filesystem;

namespace {

int material_info(const std::string& args, std::string* output) {
  return test::run_command(std::string(TPMSFILL_CLI) + " material info " + args, output);
}

nlohmann::json json_of(const std::string& out) {
  const std::size_t open = out.find('{'), close = out.rfind('}');
  EXPECT_NE(open, std::string::npos) << out;
  return nlohmann::json::parse(out.substr(open, close - open + 1));
}

TEST(MaterialCli, SurfaceIsFilledGivenAMaterialAndMapped) {
  const fs::path dir = test::scratch_dir();
  const fs::path in = dir / "ball.stl", tets = dir / "ball.vtk";
  write_mesh(in, test::make_sphere({0, 0, 0}, 10, 3));
  std::string out;
  ASSERT_EQ(material_info("'" + in.string() + "' --cell 2 --material z 0 1 --json --tets '" +
                              tets.string() + "'",
                          &out),
            0)
      << out;
  const nlohmann::json j = json_of(out);
  EXPECT_EQ(j["source"], "surface");
  EXPECT_EQ(j["genus"], 0);
  EXPECT_EQ(j["cube_map"]["flipped_boundary_faces"], 0);
  EXPECT_NEAR(j["material_range"][0].get<double>(), 0, 1e-12);
  EXPECT_NEAR(j["material_range"][1].get<double>(), 1, 1e-12);
  // The written tets hold the ramp: 0 at the bottom, 1 at the top, linear in z between.
  const TetMesh back = read_tet_mesh(tets);
  EXPECT_EQ(back.tets.size(), j["tets"].get<std::size_t>());
  ASSERT_EQ(back.material.size(), back.points.size());
  const Box3 box = check_tet_mesh(back).bounds;
  for (std::size_t v = 0; v < back.points.size(); ++v)
    EXPECT_NEAR(back.material[v], (back.points[v].z - box.min.z) / (box.max.z - box.min.z), 1e-9);

  // Read back as a tet mesh, its material comes from the file.
  ASSERT_EQ(material_info("'" + tets.string() + "' --json", &out), 0) << out;
  EXPECT_EQ(json_of(out)["material"], "from the file");

  // The seed's T-splines on its octree, checked beside THB: more functions, not summing to
  // one on an adaptive octree, and a warning that says so with the numbers.
  ASSERT_EQ(material_info("'" + tets.string() + "' --tspline --json", &out), 0) << out;
  const nlohmann::json t = json_of(out);
  ASSERT_TRUE(t.contains("tspline")) << out;
  const nlohmann::json& ts = t["tspline"];
  EXPECT_GT(ts["functions"].get<std::size_t>(), t["thb"]["functions"].get<std::size_t>());
  EXPECT_GE(ts["elements"].get<std::size_t>(), t["octree"]["leaves"].get<std::size_t>());
  ASSERT_GT(t["octree"]["deepest_level"].get<int>(), 2);  // adaptive: its regions have edges
  EXPECT_FALSE(ts["suitable"].get<bool>());
  EXPECT_GT(ts["sum_range"][1].get<double>(), 1 + 1e-6);
  EXPECT_GT(ts["incompatible_pairs"].get<std::size_t>(), 0u);
  EXPECT_NE(out.find("do not sum to one"), std::string::npos) << out;
  EXPECT_LE(ts["sum_range"][1].get<double>() - 1, ts["unity_error"].get<double>() + 1e-12);

  // Meshing and mapping a large part take many minutes: each stage's start is shown.
  ASSERT_EQ(material_info("'" + in.string() + "' --cell 2 --material z 0 1 --progress json", &out),
            0)
      << out;
  EXPECT_NE(out.find("{\"stage\": \"tetrahedralize\""), std::string::npos) << out;
  EXPECT_NE(out.find("{\"stage\": \"cube map\""), std::string::npos) << out;
}

TEST(MaterialCli, RefusalsAndTheirExitCodes) {
  const fs::path dir = test::scratch_dir();
  const fs::path torus = dir / "torus.stl", out_tets = dir / "torus.vtk";
  write_mesh(torus, test::make_torus(10, 4, 32, 16));
  std::string out;
  EXPECT_EQ(
      material_info("'" + torus.string() + "' --cell 2 --tets '" + out_tets.string() + "'", &out),
      1);
  EXPECT_NE(out.find("genus 1"), std::string::npos) << out;
  EXPECT_FALSE(fs::exists(out_tets));  // nothing written for a mesh that is refused
  const fs::path box = dir / "box.stl";
  write_mesh(box, test::make_box({0, 0, 0}, {2, 2, 2}));
  EXPECT_EQ(material_info("'" + box.string() + "' --material wood 1", &out), 2);
  EXPECT_NE(out.find("unknown --material 'wood'"), std::string::npos) << out;
  EXPECT_EQ(material_info("'" + box.string() + "' --material point 1 2", &out), 2);
  EXPECT_NE(out.find("point X Y Z"), std::string::npos) << out;
  EXPECT_EQ(material_info("'" + (dir / "missing.mesh").string() + "'", &out), 2);
  EXPECT_EQ(material_info("'" + box.string() + "' --corners 1 2 3", &out), 2);
}

// 'path', built without the `const char* + std::string` that trips GCC 12's -Wrestrict.
std::string quoted(const fs::path& path) {
  std::string s = "'";
  return s.append(path.string()).append("'");
}

// `tpmsfill material fit IN OUT ARGS`, its exit code and output.
int material_fit(const fs::path& in, const fs::path& model, const std::string& args,
                 std::string* output) {
  std::string command = TPMSFILL_CLI;
  command.append(" material fit '").append(in.string()).append("' '");
  command.append(model.string()).append("' ").append(args);
  return test::run_command(command, output);
}

TEST(MaterialCli, FitWritesAModelThatInfoReads) {
  const fs::path dir = test::scratch_dir();
  const fs::path tets = dir / "blob.vtk", model = dir / "blob.tsm";
  TetMesh blob = test::make_tet_grid({0, 0, 0}, {20, 10, 10}, {6, 3, 3}, 0.1);
  for (Vec3& p : blob.points) p = Vec3{p.x + std::sin(0.3 * p.y), p.y, p.z * (1 + 0.02 * p.x)};
  write_tet_mesh(tets, blob);
  std::string out;
  ASSERT_EQ(material_fit(tets, model, "--material x 0 1 --json", &out), 0) << out;
  const nlohmann::json j = json_of(out);
  ASSERT_FALSE(j["rounds"].empty());
  const nlohmann::json& last = j["rounds"].back();
  EXPECT_GT(last["geometry_rs_percent"].get<double>(), 0);
  EXPECT_GT(last["material_rs_percent"].get<double>(), 0);
  ASSERT_TRUE(fs::exists(model));
  ASSERT_EQ(material_info(quoted(model).append(" --tspline"), &out), 2) << out;
  EXPECT_NE(out.find("give the mesh, not a model"), std::string::npos) << out;
  ASSERT_EQ(material_info(quoted(model).append(" --json"), &out), 0) << out;
  const nlohmann::json info = json_of(out);
  EXPECT_EQ(info["control_points"], last["control_points"]);
  EXPECT_EQ(info["rounds"].size(), j["rounds"].size());
  EXPECT_NE(info["provenance"].get<std::string>().find("x ramp 0 to 1"), std::string::npos);
  // The uniform baseline: N^3 control points.
  ASSERT_EQ(material_fit(tets, dir / "u.tsm", "--uniform 5 --json", &out), 0) << out;
  EXPECT_EQ(json_of(out)["rounds"][0]["control_points"], 125);
  // Refinement asked for beside it is refused, not dropped; --refinements 0 agrees with it.
  for (const char* refine : {" --refinements 2", " --refine-share 0.5"}) {
    EXPECT_EQ(material_fit(tets, dir / "r.tsm", std::string("--uniform 5") + refine, &out), 2);
    EXPECT_NE(out.find("takes no --refine-share"), std::string::npos) << out;
    EXPECT_FALSE(fs::exists(dir / "r.tsm"));
  }
  EXPECT_EQ(material_fit(tets, dir / "r.tsm", "--uniform 5 --refinements 0", &out), 0) << out;
  // Refusals: a wrong extension before any work, a torus with exit 1 and nothing written.
  EXPECT_EQ(material_fit(tets, dir / "m.stl", "", &out), 2);
  EXPECT_NE(out.find("written as .tsm"), std::string::npos) << out;
  const fs::path torus = dir / "torus.stl", torus_model = dir / "torus.tsm";
  write_mesh(torus, test::make_torus(10, 4, 32, 16));
  EXPECT_EQ(material_fit(torus, torus_model, "--cell 2", &out), 1);
  EXPECT_FALSE(fs::exists(torus_model));
  // Sliced directly: a CLI file with a layer per 2 mm and a PNG folder with material grey.
  const fs::path cli = dir / "blob.cli", pngs = dir / "blob-png";
  std::string command = TPMSFILL_CLI;
  command.append(" material slice ").append(quoted(model)).append(" ").append(quoted(cli));
  ASSERT_EQ(test::run_command(command + " --layer 2 --json", &out), 0) << out;
  const nlohmann::json sliced = json_of(out);
  EXPECT_GE(sliced["layers"].get<int>(), 5);
  for (const nlohmann::json& layer : sliced["per_layer"]) {
    double binned = 0;
    for (double a : layer["material_area_mm2"]) binned += a;
    EXPECT_NEAR(binned, layer["area_mm2"].get<double>(), 1e-6 * 200);  // every triangle binned
  }
  EXPECT_TRUE(fs::exists(cli));
  command = TPMSFILL_CLI;
  command.append(" material slice ").append(quoted(model)).append(" ").append(quoted(pngs));
  ASSERT_EQ(test::run_command(command + " --layer 5 --format png --pixel 0.5", &out), 0) << out;
  EXPECT_TRUE(fs::exists(pngs / "layer_00000.png"));
  EXPECT_TRUE(fs::exists(pngs / "index.json"));
  // --colour: the same pixels in RGB on the documented scale (blue 0, green ½, yellow 1), the
  // empty ones white; grey = 1 + 254 t in the printer's PNG.
  const fs::path colour = dir / "blob-colour";
  command = TPMSFILL_CLI;
  command.append(" material slice ").append(quoted(model)).append(" ").append(quoted(colour));
  ASSERT_EQ(test::run_command(command + " --layer 5 --format png --pixel 0.5 --colour", &out), 0)
      << out;
  const test::Png grey = test::decode_png(test::read_file(pngs / "layer_00000.png"), 1);
  const test::Png rgb = test::decode_png(test::read_file(colour / "layer_00000.png"), 3);
  ASSERT_EQ(rgb.width, grey.width);
  ASSERT_EQ(rgb.height, grey.height);
  constexpr double kStops[3][3] = {{0.15, 0.25, 0.75}, {0.2, 0.7, 0.35}, {0.95, 0.85, 0.2}};
  int filled = 0, low = 255, high = 0;
  for (int y = 0; y < grey.height; ++y)
    for (int x = 0; x < grey.width; ++x) {
      const int g = grey.value(x, y);
      const std::uint8_t* c = rgb.at(x, y);
      if (g == 0) {
        ASSERT_TRUE(c[0] == 255 && c[1] == 255 && c[2] == 255) << x << " " << y;
        continue;
      }
      ++filled, low = std::min(low, g), high = std::max(high, g);
      const double t = (g - 1) / 254.0, s = t < 0.5 ? 2 * t : 2 * t - 1;
      const int i = t < 0.5 ? 0 : 1;
      for (int k = 0; k < 3; ++k)
        ASSERT_EQ(c[k], std::lround(255 * ((1 - s) * kStops[i][k] + s * kStops[i + 1][k])));
    }
  EXPECT_GT(filled, 100);
  EXPECT_LT(low, 40);  // the x ramp spans the layer: blue at one end, yellow at the other
  EXPECT_GT(high, 215);
  // A layer below the solid, with nothing in it, is the white page too (it was a black grey
  // image among the coloured ones).
  const double bottom = sliced["box_mm"][0][2].get<double>();
  ASSERT_EQ(test::run_command(command + "-below --layer 5 --format png --pixel 0.5 --colour " +
                                  "--start " + std::to_string(bottom - 6),
                              &out),
            0)
      << out;
  const test::Png empty = test::decode_png(
      test::read_file(fs::path(colour.string() + "-below") / "layer_00000.png"), 3);
  ASSERT_GT(empty.width, 0);
  for (int y = 0; y < empty.height; ++y)
    for (int x = 0; x < empty.width; ++x) {
      const std::uint8_t* c = empty.at(x, y);
      ASSERT_TRUE(c[0] == 255 && c[1] == 255 && c[2] == 255) << x << " " << y;
    }
  // A thickness in the wrong unit and a level that would not end: refused before any work.
  EXPECT_EQ(test::run_command(command + "-3 --layer 1e-7 --format png", &out), 2);
  EXPECT_NE(out.find("is the layer thickness in mm?"), std::string::npos) << out;
  EXPECT_EQ(test::run_command(command + "-3 --layer 5 --format png --max-level 16", &out), 2);
  EXPECT_FALSE(fs::exists(dir / "blob-colour-3"));
  EXPECT_EQ(test::run_command(command + "-2 --layer 5 --format svg-layers --colour", &out), 2);
  EXPECT_NE(out.find("--colour draws PNG layers"), std::string::npos) << out;
  // Iso-material surfaces: one mesh, each surface reported.
  const fs::path iso = dir / "iso.ply";
  command = TPMSFILL_CLI;
  command.append(" material iso ").append(quoted(model)).append(" ").append(quoted(iso));
  ASSERT_EQ(test::run_command(command + " --values 0.3 0.6 --json", &out), 0) << out;
  const nlohmann::json surfaces = json_of(out)["surfaces"];
  ASSERT_EQ(surfaces.size(), 2u);
  for (const nlohmann::json& s : surfaces) {
    EXPECT_GT(s["triangles"].get<int>(), 0);
    EXPECT_EQ(s["non_manifold_edges"], 0);
    EXPECT_LT(s["max_material_error"].get<double>(), 1e-6);
  }
  EXPECT_TRUE(fs::exists(iso));
  // A damaged model is refused with its byte offset.
  const fs::path cut = dir / "cut.tsm";
  fs::copy_file(model, cut);
  fs::resize_file(cut, fs::file_size(model) / 2);
  EXPECT_EQ(material_info(quoted(cut), &out), 2);
  EXPECT_NE(out.find("byte"), std::string::npos) << out;
}

// libcgal-demo's fandisk in coarse tets (diagonal / 12): with --allow-folds its fit folds, at
// its Gauss points and between them, and warns; by default the same fit is written with G
// fold-free at both, its steps having slid along the folds, proven so between them by det J_G's
// Bernstein bound, and no warning.
TEST(MaterialCli, FoldFreeFitOpensWhatThePlainFitWarnsOf) {
  const fs::path dir = test::scratch_dir();
  const fs::path fandisk = fs::path(TPMSFILL_CGAL_MESHES) / "fandisk.off";
  if (!fs::exists(fandisk)) GTEST_SKIP() << "libcgal-demo's meshes are not installed";
  const std::string args = "--cell 0.121 --material x 0 1 --refinements 1 --json";
  std::string out;
  ASSERT_EQ(material_fit(fandisk, dir / "folded.tsm", args + " --allow-folds", &out), 0) << out;
  const nlohmann::json plain = json_of(out)["rounds"].back();
  ASSERT_GT(plain["folded_samples"].get<std::size_t>(), 0u);
  ASSERT_GT(plain["fine_folded_samples"].get<std::size_t>(), 0u);
  EXPECT_NE(out.find("G folds (det J <= 0) at"), std::string::npos) << out;
  EXPECT_NE(out.find("between its Gauss points"), std::string::npos) << out;
  const nlohmann::json folds = json_of(out)["fold_certificate"];
  EXPECT_GT(folds["folded"].get<std::size_t>(), 0u);  // the bound finds them too
  ASSERT_EQ(material_fit(fandisk, dir / "free.tsm", args, &out), 0) << out;
  const nlohmann::json fit = json_of(out);
  for (const nlohmann::json& round : fit["rounds"])
    EXPECT_EQ(round["folded_samples"].get<std::size_t>(), 0u) << round;
  const nlohmann::json& last = fit["rounds"].back();
  EXPECT_EQ(last["fine_folded_samples"].get<std::size_t>(), 0u);
  EXPECT_GT(last["held_control_points"].get<std::size_t>(), 0u);
  EXPECT_GT(last["geometry_rs_percent"].get<double>(),
            plain["geometry_rs_percent"].get<double>() - 3);
  EXPECT_EQ(out.find("G folds"), std::string::npos) << out;
  // Between the watched points too: det J_G's Bernstein bound finds no fold, and proves all
  // but a few elements (1 of 6,546 is undecided after 6 halvings: det J_G nearly 0 there).
  const nlohmann::json& proof = fit["fold_certificate"];
  EXPECT_EQ(proof["folded"].get<std::size_t>(), 0u);
  EXPECT_GE(proof["proven"].get<double>(), 0.999 * proof["elements"].get<double>());
  EXPECT_TRUE(fs::exists(dir / "free.tsm"));
}

// The seed's upper femur (libcgal-demo's femur.off above 30 % of its height, the cut capped by
// `tpmsfill repair`, as scripts/bench.sh makes its stand-in) fitted on the uniform 30³ by
// Newton steps to the tables' stopping rule. The last G's folds between the watched points sit
// on a face of the cube, and a push that opens one at its point leaves another beside it, or
// cannot open it while its neighbours sit just above 0: with the folds pushed alone at up to
// 4 points an element the fit was refused (1 of 19,683 elements folded). Lifted with their
// neighbours, and watched densely where they come back, they open: the model is written, the
// bound finds no fold, and the slices turn no triangle over.
TEST(MaterialCli, FoldsOnTheCubesFacesOpenOnTheFemursUpperEnd) {
  const fs::path dir = test::scratch_dir();
  const fs::path femur = fs::path(TPMSFILL_CGAL_MESHES) / "femur.off";
  if (!fs::exists(femur)) GTEST_SKIP() << "libcgal-demo's meshes are not installed";
  const TriangleSoup whole = read_mesh(femur);
  double low = whole.points.front().z, high = low;
  for (const Vec3& p : whole.points) low = std::min(low, p.z), high = std::max(high, p.z);
  const double cut = low + 0.3 * (high - low);
  // The points below the cut stay in the file unreferenced: repair drops them, keeping the
  // others' order.
  TriangleSoup upper{whole.points, {}};
  for (const Triangle& t : whole.triangles)
    if (std::all_of(t.begin(), t.end(), [&](std::uint32_t v) { return whole.points[v].z >= cut; }))
      upper.triangles.push_back(t);
  write_mesh(dir / "cut.off", upper);
  std::string out;
  ASSERT_EQ(test::run_command(std::string(TPMSFILL_CLI) + " repair '" + (dir / "cut.off").string() +
                                  "' '" + (dir / "upper.off").string() + "' --quiet",
                              &out),
            0)
      << out;
  ASSERT_EQ(material_fit(dir / "upper.off", dir / "upper.tsm",
                         "--cell 0.025935 --material geodesic 0.0077806 --uniform 30 --method "
                         "newton --rs-change 0.01 --max-iterations 100 --json",
                         &out),
            0)
      << out;
  const nlohmann::json fit = json_of(out);
  EXPECT_EQ(fit["genus"], 0);
  const nlohmann::json& last = fit["rounds"].back();
  EXPECT_EQ(last["control_points"], 27000);
  EXPECT_GT(last["found_folded_points"].get<std::size_t>(), 0u);  // the bound found folds
  EXPECT_EQ(last["folded_samples"], 0);
  EXPECT_EQ(last["fine_folded_samples"], 0);
  EXPECT_EQ(fit["fold_certificate"]["folded"], 0);  // and none is left
  EXPECT_GT(last["geometry_rs_percent"].get<double>(), 40);
  EXPECT_GT(last["material_rs_percent"].get<double>(), 50);
  const SolidModel model = read_solid_model(dir / "upper.tsm");
  const Box3 box = solid_box(model.fit.spline);
  for (double t : {0.1, 0.35, 0.6, 0.85})
    EXPECT_EQ(slice_solid(model.fit.spline, box.min.z + t * (box.max.z - box.min.z), {}).flipped,
              0u)
        << t;
}

// A material slice's preflight slices a few layers first and forecasts the stack from them:
// near what the whole slice makes, and a stack past the limits refused before any file.
TEST(MaterialCli, SlicePreflightForecastsTheStack) {
  const fs::path dir = test::scratch_dir();
  const fs::path tets = dir / "blob.vtk", model = dir / "blob.tsm";
  write_tet_mesh(tets, test::make_tet_grid({0, 0, 0}, {20, 10, 10}, {6, 3, 3}, 0.1));
  std::string out;
  ASSERT_EQ(material_fit(tets, model, "--material x 0 1", &out), 0) << out;
  const fs::path svg = dir / "blob.svg";
  std::string command = TPMSFILL_CLI;
  command.append(" material slice ").append(quoted(model)).append(" ");
  ASSERT_EQ(test::run_command(command + quoted(svg) + " --layer 0.1 --progress json", &out), 0)
      << out;
  const std::size_t at = out.find("{\"preflight\"");
  ASSERT_NE(at, std::string::npos) << out;
  const auto f = nlohmann::json::parse(out.substr(at, out.find('\n', at) - at))["preflight"];
  ASSERT_EQ(test::run_command(command + quoted(svg) + " --layer 0.1 --json", &out), 0) << out;
  EXPECT_EQ(f["layers"], json_of(out)["layers"]);
  EXPECT_NEAR(f["triangles"].get<double>() / json_of(out)["triangles"].get<double>(), 1.0, 0.3);
  const double bytes = static_cast<double>(fs::file_size(svg));
  EXPECT_NEAR(f["bytes"].get<double>() / bytes, 1.0, 0.3) << out;
  EXPECT_LT(f["seconds"][0].get<double>(), f["seconds"][1].get<double>());
  // 0.1 µm layers: a hundred thousand of them, and gigabytes of SVG.
  const fs::path huge = dir / "huge.svg";
  EXPECT_EQ(test::run_command(command + quoted(huge) + " --layer 0.0001", &out), 2);
  EXPECT_NE(out.find("the job would write about"), std::string::npos) << out;
  EXPECT_NE(out.find("--yes runs it as it is"), std::string::npos) << out;
  EXPECT_FALSE(fs::exists(huge));
}

// Iso-material surfaces of a model anywhere: the report's degenerate triangles are the
// written file's (as its format holds the coordinates), and any the rounding made are warned
// about; PLY holds doubles and makes none.
TEST(MaterialCli, IsoSurfacesReportWhatTheirFileHolds) {
  const fs::path dir = test::scratch_dir();
  for (const double offset : {0.0, 1e5}) {
    TetMesh blob = test::make_tet_grid({0, 0, 0}, {20, 10, 10}, {6, 3, 3}, 0.1);
    for (Vec3& p : blob.points) p = p + Vec3{offset, offset, 0};
    const fs::path tets = dir / "blob.vtk", model = dir / "blob.tsm";
    write_tet_mesh(tets, blob);
    std::string out;
    ASSERT_EQ(material_fit(tets, model, "--material x 0 1", &out), 0) << out;
    for (const char* name : {"iso.stl", "iso.ply"}) {
      std::string command = TPMSFILL_CLI;
      command.append(" material iso ").append(quoted(model)).append(" ");
      ASSERT_EQ(test::run_command(command + quoted(dir / name) + " --values 0.3 0.6 --json", &out),
                0)
          << out;
      const std::size_t at = out.find('{');
      ASSERT_NE(at, std::string::npos) << out;
      const auto reported = nlohmann::json::parse(out.substr(at, out.rfind('}') - at + 1));
      const MeshCheck written = check_mesh(read_mesh(dir / name), {.self_intersections = false});
      EXPECT_EQ(reported["degenerate_triangles"].get<std::uint64_t>(), written.degenerate_triangles)
          << name << " at " << offset;
      if (std::string(name) == "iso.ply") {
        EXPECT_EQ(written.degenerate_triangles, 0u) << offset;
      }
      if (written.degenerate_triangles > 0) {
        EXPECT_NE(out.find("hold doubles"), std::string::npos) << out;
      }
      // A ramp along x cuts the box in squares: each surface one whole 10 × 10 mm piece.
      for (const auto& s : reported["surfaces"]) {
        EXPECT_EQ(s["pieces"].get<int>(), 1) << s.dump();
        EXPECT_EQ(s["small_pieces"].get<int>(), 0) << s.dump();
        EXPECT_EQ(s["non_manifold_edges"].get<int>(), 0) << s.dump();
        EXPECT_NEAR(s["smallest_piece_share"].get<double>(), 1, 1e-12);
        EXPECT_NEAR(s["area_mm2"].get<double>(), 100, 3) << s.dump();
      }
    }
    // Its stack holds the box's volume: 20 × 10 × 10 mm within 1 % (corners jittered 0.1 mm).
    std::string command = TPMSFILL_CLI;
    command.append(" material slice ").append(quoted(model)).append(" ");
    ASSERT_EQ(test::run_command(command + quoted(dir / "blob.cli") + " --layer 0.5 --json", &out),
              0)
        << out;
    const std::size_t at = out.find('{');
    ASSERT_NE(at, std::string::npos) << out;
    const auto stack = nlohmann::json::parse(out.substr(at, out.rfind('}') - at + 1));
    EXPECT_NEAR(stack["volume_mm3"].get<double>(), 2000, 20) << offset;
  }
}

TEST(MaterialCli, FillGradedByTheModelsMaterial) {
  // A box whose material rises with z: grading the porosity by the fitted material is grading
  // it along z (the material's range over the box is the box's height), and the report's recipe
  // reproduces the job from another folder.
  const fs::path dir = test::scratch_dir();
  const fs::path tets = dir / "box.vtk", model = dir / "box.tsm", surface = dir / "box.stl";
  write_tet_mesh(tets, test::make_tet_grid({0, 0, 0}, {20, 10, 10}, {4, 2, 2}));
  write_mesh(surface, test::make_box({0, 0, 0}, {20, 10, 10}));
  std::string out;
  ASSERT_EQ(material_fit(tets, model, "--material z 0 1 --quiet", &out), 0) << out;
  auto fill = [&](const std::string& name, const std::string& args) {
    std::string command = TPMSFILL_CLI;
    command.append(" fill ").append(quoted(surface)).append(" ").append(quoted(dir / name));
    command.append(" --cell 2.5 --voxel 0.125 --quiet --report ")
        .append(quoted(dir / (name + ".json")))
        .append(" ")
        .append(args);
    EXPECT_EQ(test::run_command(command, &out), 0) << out;
    return nlohmann::json::parse(test::read_file(dir / (name + ".json")));
  };
  const nlohmann::json by_material =
      fill("material.stl", "--grade porosity 0.4 0.8 --grade-by " + quoted(model));
  const nlohmann::json along_z = fill("z.stl", "--grade porosity 0.4 0.8 --grade-along z");
  const nlohmann::json& ramp = by_material["recipe"]["grading"][0];
  EXPECT_EQ(ramp["ramp"], "volume");
  EXPECT_NEAR(ramp["from"].get<double>(), 0, 0.02);  // the material's range over the box
  EXPECT_NEAR(ramp["to"].get<double>(), 1, 0.02);
  const double porosity = by_material["porosity"].get<double>();
  EXPECT_NEAR(porosity, along_z["porosity"].get<double>(), 0.005);
  EXPECT_NEAR(porosity, 0.6, 0.03);  // the ramp's mean
  // A graded porosity has no one unclipped value: null, not the base lattice's 50 %.
  EXPECT_TRUE(by_material["unclipped_porosity"].is_null());
  // The echoed recipe names the model by its absolute path: it runs from anywhere.
  const fs::path elsewhere = dir / "elsewhere";
  fs::create_directories(elsewhere);
  std::ofstream(elsewhere / "recipe.json") << by_material["recipe"].dump();
  const nlohmann::json again = fill("again.stl", "--recipe " + quoted(elsewhere / "recipe.json"));
  EXPECT_DOUBLE_EQ(again["porosity"].get<double>(), porosity);
  // The cell size follows the material too (a ladder of cell sizes, mixed).
  const nlohmann::json cells =
      fill("cells.stl", "--porosity 0.6 --grade cell 2 3 --grade-by " + quoted(model));
  EXPECT_TRUE(cells["valid"].get<bool>());
  EXPECT_NEAR(cells["porosity"].get<double>(), 0.6, 0.03);
  // Refusals: two places for one grade.
  std::string command = TPMSFILL_CLI;
  command.append(" fill ").append(quoted(surface)).append(" ").append(quoted(dir / "no.stl"));
  EXPECT_EQ(
      test::run_command(
          command + " --grade porosity 0.4 0.8 --grade-along x --grade-by " + quoted(model), &out),
      2);
  EXPECT_NE(out.find("give one"), std::string::npos) << out;
  // The part in cm, the model in mm: the volume meets under 1 % of the part's box.
  EXPECT_EQ(test::run_command(
                command + " --units cm --grade porosity 0.4 0.8 --grade-by " + quoted(model), &out),
            2);
  EXPECT_NE(out.find("other units"), std::string::npos) << out;
  EXPECT_FALSE(fs::exists(dir / "no.stl"));
}

}  // namespace
