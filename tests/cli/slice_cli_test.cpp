// `tpmsfill slice`: the formats it picks, the folder it stages, its report, and what it
// refuses (with nothing written).
#include <gtest/gtest.h>

#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>
#include <tpmsfill/io.hpp>

#include "test_util.hpp"

using namespace tpmsfill;
namespace fs = std::filesystem;

namespace {

int slice_cli(const std::string& args, std::string* out) {
  return test::run_command(std::string(TPMSFILL_CLI) + " slice " + args, out);
}

// The path shell-quoted (appended piece by piece: GCC 12 warns wrongly on "'" + s + "'").
std::string q(const fs::path& p) {
  std::string s(1, '\'');
  s.append(p.string());
  s.push_back('\'');
  return s;
}

}  // namespace

TEST(SliceCli, WritesCommonLayerInterfaceAndAReportThatAgreesWithFill) {
  const fs::path dir = test::scratch_dir();
  write_mesh(dir / "ball.stl", test::make_sphere({0, 0, 0}, 4, 4));
  const std::string job = " --cell 2 --voxel 0.1 --keep-islands";
  std::string out;
  ASSERT_EQ(
      test::run_command(std::string(TPMSFILL_CLI) + " fill " + q(dir / "ball.stl") + " " +
                            q(dir / "ball-lattice.stl") + job + " --report " + q(dir / "fill.json"),
                        &out),
      0)
      << out;
  // slice takes fill's job flags but not its mesh-only ones.
  EXPECT_EQ(slice_cli(q(dir / "ball.stl") + " " + q(dir / "ball.cli") + job + " --layer 0.1", &out),
            2)
      << out;
  ASSERT_EQ(slice_cli(q(dir / "ball.stl") + " " + q(dir / "ball.cli") +
                          " --cell 2 --voxel 0.1 --layer 0.05 --report " + q(dir / "slice.json"),
                      &out),
            0)
      << out;
  EXPECT_NE(out.find("layers       160 of 0.05 mm"), std::string::npos) << out;
  const std::string cli = test::read_file(dir / "ball.cli");
  EXPECT_EQ(cli.rfind("$$HEADERSTART", 0), 0u);
  EXPECT_NE(cli.find("$$LAYERS/160"), std::string::npos);
  const auto fill_report = nlohmann::json::parse(test::read_file(dir / "fill.json"));
  const auto slice_report = nlohmann::json::parse(test::read_file(dir / "slice.json"));
  const double lattice = fill_report["lattice_volume"];
  EXPECT_NEAR(slice_report["slice"]["volume"].get<double>(), lattice, 0.01 * lattice);
  EXPECT_EQ(slice_report["slice"]["per_layer"].size(), 160u);
  EXPECT_EQ(slice_report["lattice"]["type"], fill_report["lattice"]["type"]);
  EXPECT_FALSE(slice_report.contains("validation"));
  EXPECT_TRUE(slice_report["recipe"].is_object());
}

TEST(SliceCli, FolderFormatsAreStagedAndCarryAnIndex) {
  const fs::path dir = test::scratch_dir();
  write_mesh(dir / "box.stl", test::make_box({0, 0, 0}, {4, 4, 2}));
  std::string out;
  ASSERT_EQ(slice_cli(q(dir / "box.stl") + " " + q(dir / "masks") +
                          " --format png --pixel 0.1 --layer 0.5 --cell 1 --voxel 0.1 --quiet",
                      &out),
            0)
      << out;
  EXPECT_TRUE(out.empty()) << out;
  EXPECT_TRUE(fs::exists(dir / "masks" / "layer_00000.png"));
  EXPECT_TRUE(fs::exists(dir / "masks" / "layer_00003.png"));
  EXPECT_FALSE(fs::exists(dir / "masks" / "layer_00004.png"));
  const auto index = nlohmann::json::parse(test::read_file(dir / "masks" / "index.json"));
  EXPECT_EQ(index["slice"]["layers"], 4);
  // Running again replaces the folder it wrote; nothing is left beside it.
  ASSERT_EQ(slice_cli(q(dir / "box.stl") + " " + q(dir / "masks") +
                          " --format svg-layers --layer 1 --cell 1 --voxel 0.1 --quiet",
                      &out),
            0)
      << out;
  EXPECT_TRUE(fs::exists(dir / "masks" / "layer_00001.svg"));
  EXPECT_FALSE(fs::exists(dir / "masks" / "layer_00000.png"));
  std::size_t entries = 0;
  for (const auto& e : fs::directory_iterator(dir)) entries += 1, (void)e;
  EXPECT_EQ(entries, 2u);  // box.stl and masks
}

TEST(SliceCli, RefusesWhatItCannotWriteAndWritesNothing) {
  const fs::path dir = test::scratch_dir();
  write_mesh(dir / "box.stl", test::make_box({0, 0, 0}, {4, 4, 2}));
  fs::create_directory(dir / "photos");
  test::write_file(dir / "photos" / "holiday.jpg", "not a layer");
  const std::string base = q(dir / "box.stl") + " ";
  struct Case {
    std::string args, says;
  } cases[] = {
      {q(dir / "out.cli"), "--layer"},
      {q(dir / "out.txt") + " --layer 0.1", "unknown extension"},
      {q(dir / "out.svg") + " --layer 0.1 --binary", "--binary"},
      {q(dir / "out.cli") + " --layer 0.1 --pixel 0.05", "--pixel"},
      {q(dir / "photos") + " --layer 0.1 --format png", "other files"},
      {q(dir / "out.cli") + " --layer 0.1 --format stl", "stl"},
      {q(dir / "out.cli") + " --layer -1", "--layer"},
      {q(dir / "out.cli") + " --layer 0.1 --memory 1K", "memory budget"},
      {q(dir / "masks") + " --format png --layer 0.1 --report " + q(dir / "masks" / "r.json"),
       "inside OUT"},
      {q(dir / "out.cli") + " --layer 0.1 --start 9", "above the model's top"},
  };
  for (const Case& c : cases) {
    std::string out;
    EXPECT_EQ(slice_cli(base + c.args, &out), 2) << c.args << "\n" << out;
    EXPECT_NE(out.find(c.says), std::string::npos) << c.args << "\n" << out;
  }
  std::size_t entries = 0;
  for (const auto& e : fs::directory_iterator(dir)) entries += 1, (void)e;
  EXPECT_EQ(entries, 2u);  // box.stl and photos, untouched
  EXPECT_TRUE(fs::exists(dir / "photos" / "holiday.jpg"));
}
