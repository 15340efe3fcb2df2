// `tpmsfill material info|fit` as a user runs them: a surface filled with tets and mapped onto
// the cube, a tet mesh written and read back with its material, a model fitted, written and
// summarised, and refusals with their exit codes.
#include <gtest/gtest.h>

// GCC 12 reports a false -Wrestrict inside std::string concatenation here (GCC bug 105329).
#pragma GCC diagnostic ignored "-Wrestrict"

#include <cmath>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>
#include <tpmsfill/io.hpp>
#include <tpmsfill/tet_mesh.hpp>

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
  ASSERT_EQ(material_info(quoted(model).append(" --json"), &out), 0) << out;
  const nlohmann::json info = json_of(out);
  EXPECT_EQ(info["control_points"], last["control_points"]);
  EXPECT_EQ(info["rounds"].size(), j["rounds"].size());
  EXPECT_NE(info["provenance"].get<std::string>().find("x ramp 0 to 1"), std::string::npos);
  // The uniform baseline: N^3 control points.
  ASSERT_EQ(material_fit(tets, dir / "u.tsm", "--uniform 5 --json", &out), 0) << out;
  EXPECT_EQ(json_of(out)["rounds"][0]["control_points"], 125);
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

}  // namespace
