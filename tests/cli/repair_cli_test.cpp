// `tpmsfill repair` as a user runs it: exit codes, nothing written on failure, JSON that
// parses, and what is written passes `tpmsfill check`.
#include <gtest/gtest.h>

#include <algorithm>
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

int repair(const fs::path& in, const fs::path& out, const std::string& flags, std::string* output) {
  return test::run_command(
      std::string(TPMSFILL_CLI) + " repair '" + in.string() + "' '" + out.string() + "' " + flags,
      output);
}

}  // namespace

TEST(RepairCli, RepairsAndWritesAValidMesh) {
  const auto dir = test::scratch_dir();
  write_mesh(dir / "open.stl", test::make_box_with_hole({0, 0, 0}, {10, 10, 10}));
  std::string out;
  ASSERT_EQ(repair(dir / "open.stl", dir / "fixed.obj", "", &out), 0) << out;
  EXPECT_NE(out.find("holes: 1 found"), std::string::npos) << out;
  EXPECT_NE(out.find("verdict: VALID"), std::string::npos) << out;
  ASSERT_TRUE(fs::exists(dir / "fixed.obj"));
  EXPECT_TRUE(check_mesh(read_mesh(dir / "fixed.obj")).valid());
  // What was written is what `check` calls valid.
  EXPECT_EQ(test::run_command(
                std::string(TPMSFILL_CLI) + " check '" + (dir / "fixed.obj").string() + "'", &out),
            0)
      << out;
}

TEST(RepairCli, JsonParsesAndNamesTheWrap) {
  const auto dir = test::scratch_dir();
  write_mesh(dir / "open.off", test::make_box_with_hole({0, 0, 0}, {10, 10, 10}));
  std::string out;
  // A 1.5 mm ball rounds the 10 mm box's edges by more than the default tolerance (1 % of
  // the diagonal, 0.17 mm): refused, exit 1, nothing written, unless accepted.
  EXPECT_EQ(repair(dir / "open.off", dir / "fixed.ply", "--no-fill-holes --alpha 1.5", &out), 1)
      << out;
  EXPECT_NE(out.find("beyond the tolerance of 0.173 mm; nothing was written"), std::string::npos)
      << out;
  // The verdict itself says it is held back: "VALID" alone above an exit 1 misled.
  EXPECT_NE(out.find("verdict: VALID but BEYOND the tolerance"), std::string::npos) << out;
  EXPECT_EQ(out.find("verdict: VALID: a closed"), std::string::npos) << out;
  EXPECT_FALSE(fs::exists(dir / "fixed.ply"));
  ASSERT_EQ(repair(dir / "open.off", dir / "fixed.ply",
                   "--json --no-fill-holes --alpha 1.5 --offset 0.05 --accept-deviation", &out),
            0)
      << out;
  // The JSON on stdout, then the warnings on stderr.
  const auto j = nlohmann::json::parse(out.substr(0, out.rfind('}') + 1));
  EXPECT_NE(out.find("tpmsfill: warning: the result lies up to"), std::string::npos) << out;
  EXPECT_EQ(j["valid"], true);
  EXPECT_EQ(j["within_tolerance"], false);
  EXPECT_GT(std::max(j["deviation"]["from_input"]["max"].get<double>(),
                     j["deviation"]["to_input"]["max"].get<double>()),
            j["tolerance"].get<double>());
  EXPECT_NEAR(j["tolerance"].get<double>(), 0.01 * std::sqrt(300.0), 1e-9);
  EXPECT_EQ(j["written"], true);
  EXPECT_EQ(j["wrapped"], true);
  EXPECT_EQ(j["route"], "wrap");
  // --alpha is the only wrap tried; without hole filling there is no volumetric route.
  ASSERT_EQ(j["candidates"].size(), 2u) << out;
  EXPECT_EQ(j["candidates"][0]["route"], "repair");
  EXPECT_EQ(j["candidates"][0]["valid"], false);
  EXPECT_TRUE(j["candidates"][0]["failure"].is_string());
  EXPECT_EQ(j["candidates"][1]["route"], "wrap");
  EXPECT_EQ(j["candidates"][1]["taken"], true);
  EXPECT_EQ(j["candidates"][1]["alpha"].get<double>(), 1.5);
  EXPECT_EQ(j["candidates"][1]["deviation"], j["deviation"]);
  EXPECT_EQ(j["alpha"].get<double>(), 1.5);
  EXPECT_EQ(j["offset"].get<double>(), 0.05);
  EXPECT_FALSE(j["unresolved"].empty());
  EXPECT_FALSE(j["actions"].empty());
  EXPECT_EQ(j["before"]["closed"], false);
  EXPECT_EQ(j["after"]["valid"], true);
  EXPECT_TRUE(fs::exists(dir / "fixed.ply"));
}

TEST(RepairCli, UnrepairableWritesNothingAndExitsOne) {
  const auto dir = test::scratch_dir();
  write_mesh(dir / "open.stl", test::make_box_with_hole({0, 0, 0}, {10, 10, 10}));
  std::string out;
  EXPECT_EQ(repair(dir / "open.stl", dir / "fixed.stl", "--no-fill-holes --no-wrap", &out), 1)
      << out;
  EXPECT_FALSE(fs::exists(dir / "fixed.stl"));
  EXPECT_NE(out.find("nothing was written"), std::string::npos) << out;
  EXPECT_NE(out.find("NOT VALID"), std::string::npos) << out;
  // --json still prints a parseable report.
  EXPECT_EQ(repair(dir / "open.stl", dir / "fixed.stl", "--no-fill-holes --no-wrap --json", &out),
            1);
  const std::size_t open = out.find('{'), close = out.rfind('}');
  ASSERT_NE(open, std::string::npos) << out;
  const auto j = nlohmann::json::parse(out.substr(open, close - open + 1));
  EXPECT_EQ(j["valid"], false);
  EXPECT_EQ(j["written"], false);
  EXPECT_FALSE(fs::exists(dir / "fixed.stl"));
}

TEST(RepairCli, BadInputAndArgumentsExitTwo) {
  const auto dir = test::scratch_dir();
  std::string out;
  EXPECT_EQ(repair(dir / "missing.stl", dir / "out.stl", "", &out), 2) << out;
  test::write_file(dir / "empty.off", "OFF\n0 0 0\n");
  EXPECT_EQ(repair(dir / "empty.off", dir / "out.stl", "", &out), 2) << out;
  write_mesh(dir / "box.stl", test::make_box({0, 0, 0}, {1, 1, 1}));
  EXPECT_EQ(repair(dir / "box.stl", dir / "out.xyz", "", &out), 2) << out;
  EXPECT_NE(out.find("unknown extension"), std::string::npos) << out;
  EXPECT_EQ(repair(dir / "box.stl", dir / "out.stl", "--alpha -1", &out), 2) << out;
  EXPECT_EQ(repair(dir / "box.stl", dir / "out.stl", "--min-component 2", &out), 2) << out;
  EXPECT_FALSE(fs::exists(dir / "out.stl"));
  EXPECT_FALSE(fs::exists(dir / "out.xyz"));
}

TEST(RepairCli, QuietPrintsNothingOnSuccess) {
  const auto dir = test::scratch_dir();
  write_mesh(dir / "soup.stl", test::make_sphere({0, 0, 0}, 3, 2));
  std::string out;
  ASSERT_EQ(repair(dir / "soup.stl", dir / "out.stl", "--quiet", &out), 0) << out;
  EXPECT_TRUE(out.empty()) << out;
  EXPECT_TRUE(fs::exists(dir / "out.stl"));
}
