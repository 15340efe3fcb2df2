// `tpmsfill decimate` and `tpmsfill fill --decimate` as a user runs them: exit codes, nothing
// written on refusal, JSON that parses, and what is written passes `tpmsfill check`.
#include <gtest/gtest.h>

#include <cmath>

// GCC 12 reports a false -Wrestrict inside std::string concatenation here (GCC bug 105329).
#pragma GCC diagnostic ignored "-Wrestrict"

#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>
#include <tpmsfill/check.hpp>
#include <tpmsfill/io.hpp>

#include "test_util.hpp"

using namespace tpmsfill;
namespace fs = std::filesystem;

namespace {

std::string cli() {
  return TPMSFILL_CLI;
}

int decimate(const fs::path& in, const fs::path& out, const std::string& flags,
             std::string* output) {
  return test::run_command(
      cli() + " decimate '" + in.string() + "' '" + out.string() + "' " + flags, output);
}

nlohmann::json json_of(const std::string& out) {
  const std::size_t open = out.find('{'), close = out.rfind('}');
  EXPECT_NE(open, std::string::npos) << out;
  return nlohmann::json::parse(out.substr(open, close - open + 1));
}

}  // namespace

TEST(DecimateCli, WritesAValidLighterMeshAndItsReport) {
  const auto dir = test::scratch_dir();
  write_mesh(dir / "ball.stl", test::make_sphere({0, 0, 0}, 10, 5));  // an STL soup
  std::string out;
  ASSERT_EQ(decimate(dir / "ball.stl", dir / "light.stl",
                     "--tolerance 0.05 --report '" + (dir / "r.json").string() + "'", &out),
            0)
      << out;
  EXPECT_NE(out.find("triangles    20,480 -> "), std::string::npos) << out;
  EXPECT_NE(out.find("verdict      VALID"), std::string::npos) << out;
  const TriangleSoup light = read_mesh(dir / "light.stl");
  EXPECT_LT(light.triangles.size() * 4, 20480u);
  EXPECT_TRUE(check_mesh(light).valid());
  EXPECT_EQ(test::run_command(cli() + " check '" + (dir / "light.stl").string() + "'", &out), 0)
      << out;
  const auto j = nlohmann::json::parse(test::read_file(dir / "r.json"));
  EXPECT_EQ(j["valid"], true);
  EXPECT_EQ(j["triangles_before"], 20480);
  EXPECT_EQ(j["triangles_after"], light.triangles.size());
  EXPECT_LE(j["to_input"]["max"].get<double>(), 0.05 * (1 + 1e-4));
  EXPECT_GT(j["hausdorff"].get<double>(), 0.0);
  EXPECT_LT(std::abs(j["volume_change"].get<double>()), 0.01);
  EXPECT_EQ(j["stop"], "tolerance");
}

TEST(DecimateCli, JsonAndTargetWarning) {
  const auto dir = test::scratch_dir();
  write_mesh(dir / "ball.off", test::make_sphere({0, 0, 0}, 10, 4));
  std::string out;
  ASSERT_EQ(
      decimate(dir / "ball.off", dir / "light.obj", "--tolerance 0.001 --target 10 --json", &out),
      0)
      << out;
  const auto j = json_of(out.substr(0, out.rfind('}') + 1));
  EXPECT_EQ(j["target_triangles"], 10);
  EXPECT_GT(j["triangles_after"].get<int>(), 10);
  // Not reaching the target is said, with the numbers.
  EXPECT_NE(out.find("tpmsfill: warning: the target of 10 triangles was not reached"),
            std::string::npos)
      << out;
  EXPECT_TRUE(check_mesh(read_mesh(dir / "light.obj")).valid());
}

TEST(DecimateCli, InvalidInputIsRefusedAndNothingWritten) {
  const auto dir = test::scratch_dir();
  write_mesh(dir / "open.stl", test::make_box_with_hole({0, 0, 0}, {10, 10, 10}));
  std::string out;
  EXPECT_EQ(decimate(dir / "open.stl", dir / "out.stl", "--tolerance 0.1", &out), 2) << out;
  EXPECT_NE(out.find("is not a valid closed 2-manifold"), std::string::npos) << out;
  EXPECT_NE(out.find("tpmsfill repair"), std::string::npos) << out;
  EXPECT_FALSE(fs::exists(dir / "out.stl"));
  // Bad arguments: no tolerance, a negative one, an unknown extension.
  write_mesh(dir / "box.stl", test::make_box({0, 0, 0}, {1, 1, 1}));
  EXPECT_EQ(decimate(dir / "box.stl", dir / "out.stl", "", &out), 2) << out;
  EXPECT_EQ(decimate(dir / "box.stl", dir / "out.stl", "--tolerance -1", &out), 2) << out;
  EXPECT_EQ(decimate(dir / "box.stl", dir / "out.xyz", "--tolerance 1", &out), 2) << out;
  EXPECT_FALSE(fs::exists(dir / "out.stl"));
  EXPECT_EQ(test::files_in(dir, 1 << 30).size(), 2u);  // no staged leftovers
}

TEST(DecimateCli, FillDecimateWritesTheDecimatedLattice) {
  const auto dir = test::scratch_dir();
  write_mesh(dir / "ball.stl", test::make_sphere({0, 0, 0}, 3, 4));
  std::string out;
  const std::string job = cli() + " fill '" + (dir / "ball.stl").string() + "' '" +
                          (dir / "full.stl").string() + "' --cell 2 --voxel 0.2";
  ASSERT_EQ(test::run_command(job, &out), 0) << out;
  const std::string decimated =
      cli() + " fill '" + (dir / "ball.stl").string() + "' '" + (dir / "light.stl").string() +
      "' --cell 2 --voxel 0.2 --decimate 0.05 --report '" + (dir / "r.json").string() + "'";
  ASSERT_EQ(test::run_command(decimated, &out), 0) << out;
  EXPECT_NE(out.find("decimated\ntriangles"), std::string::npos) << out;
  const TriangleSoup full = read_mesh(dir / "full.stl"), light = read_mesh(dir / "light.stl");
  EXPECT_LT(light.triangles.size(), full.triangles.size());
  EXPECT_TRUE(check_mesh(light).valid());
  const auto j = nlohmann::json::parse(test::read_file(dir / "r.json"));
  // The report's own figures are the lattice as filled; "decimation" describes OUT.
  EXPECT_EQ(j["decimation"]["triangles_before"], full.triangles.size());
  EXPECT_EQ(j["decimation"]["triangles_after"], light.triangles.size());
  EXPECT_EQ(j["decimation"]["valid"], true);
  EXPECT_EQ(j["decimation"]["tolerance"], 0.05);
  // Only OUT and the report are left: the undecimated scratch file is gone.
  EXPECT_EQ(test::files_in(dir, 1 << 30).size(), 4u);
}
