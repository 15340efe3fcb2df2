// The command line refuses, before any work and without touching a file, what would overwrite
// an input or could not be written; it writes the mesh and the report together; and the
// report says what ran on what (units, input hash, command line, version).
#include <gtest/gtest.h>

#include <chrono>
#include <nlohmann/json.hpp>
#include <sstream>
#include <tpmsfill/io.hpp>

#include "io/inflate.hpp"
#include "test_util.hpp"

using namespace tpmsfill;

namespace {

std::string cli() {
  return TPMSFILL_CLI;
}

int run(const std::string& args, std::string* out) {
  return test::run_command(cli() + " " + args + " 2>&1", out);
}

std::size_t lines(const std::string& s) {
  return static_cast<std::size_t>(std::count(s.begin(), s.end(), '\n'));
}

bool has(const std::string& text, const std::string& part) {
  return text.find(part) != std::string::npos;
}

}  // namespace

TEST(CliOutputs, OutputThatIsTheInputIsRefusedAndTheInputUntouched) {
  const auto dir = test::scratch_dir();
  const auto in = dir / "part.off";
  write_mesh(in, test::make_box({0, 0, 0}, {10, 10, 10}));
  const std::string before = test::read_file(in);
  std::filesystem::create_hard_link(in, dir / "alias.off");
  std::string out;
  for (const std::string& args :
       {"fill '" + in.string() + "' '" + in.string() + "'",
        "fill '" + in.string() + "' '" + (dir / "." / "part.off").string() + "'",
        "fill '" + in.string() + "' '" + (dir / "alias.off").string() + "'",
        "fill '" + in.string() + "' '" + (dir / "o.stl").string() + "' --report '" + in.string() +
            "'",
        "repair '" + in.string() + "' '" + in.string() + "'"}) {
    EXPECT_EQ(run(args, &out), 2) << args << "\n" << out;
    EXPECT_EQ(lines(out), 1u) << out;
    EXPECT_TRUE(has(out, "tpmsfill: error:") && has(out, "would be overwritten")) << out;
    EXPECT_EQ(test::read_file(in), before);
    EXPECT_FALSE(std::filesystem::exists(dir / "o.stl"));
  }
  EXPECT_EQ(run("fill '" + in.string() + "' '" + (dir / "o.stl").string() + "' --report '" +
                    (dir / "o.stl").string() + "'",
                &out),
            2)
      << out;
  EXPECT_TRUE(has(out, "--report")) << out;
}

TEST(CliOutputs, UnwritableOutputsFailBeforeAnyWorkAndWriteNothing) {
  const auto dir = test::scratch_dir();
  const auto in = dir / "part.off";
  write_mesh(in, test::make_box({0, 0, 0}, {10, 10, 10}));
  std::string out;
  // A missing folder for OUT or for the report: refused at once (the job would take
  // seconds at this voxel), and OUT is not written when only the report's folder is missing.
  const std::string job = "fill '" + in.string() + "' ";
  const auto t0 = std::chrono::steady_clock::now();
  EXPECT_EQ(run(job + "'" + (dir / "no" / "o.stl").string() + "' --voxel 0.02", &out), 2);
  EXPECT_TRUE(has(out, "does not exist")) << out;
  EXPECT_EQ(run(job + "'" + (dir / "o.stl").string() + "' --voxel 0.02 --report '" +
                    (dir / "no" / "r.json").string() + "'",
                &out),
            2);
  EXPECT_TRUE(has(out, "--report") && has(out, "does not exist")) << out;
  EXPECT_LT(test::seconds_since(t0), 5.0);
  std::filesystem::create_directory(dir / "folder.stl");
  EXPECT_EQ(run(job + "'" + (dir / "folder.stl").string() + "'", &out), 2);
  EXPECT_TRUE(has(out, "is a folder")) << out;
  EXPECT_EQ(test::files_in(dir, 1 << 30).size(), 1u) << "something was written";
}

TEST(CliOutputs, ReportRecordsProvenance) {
  const auto dir = test::scratch_dir();
  const auto in = dir / "part.off";
  write_mesh(in, test::make_box({0, 0, 0}, {1, 1, 1}));  // 1 cm in centimetres
  std::string out, sum;
  ASSERT_EQ(run("fill '" + in.string() + "' '" + (dir / "o.stl").string() +
                    "' --units cm --cell 2 --voxel 0.2 --rotate 0 0 45 --report '" +
                    (dir / "r.json").string() + "'",
                &out),
            0)
      << out;
  EXPECT_TRUE(has(out, "rotated 0 0 45 deg")) << out;
  ASSERT_EQ(test::run_command("sha256sum '" + in.string() + "'", &sum), 0);
  const auto j = nlohmann::json::parse(test::read_file(dir / "r.json"));
  EXPECT_EQ(j["provenance"]["input_sha256"], sum.substr(0, 64));
  EXPECT_EQ(j["provenance"]["input"], in.string());
  EXPECT_TRUE(has(j["provenance"]["command_line"].get<std::string>(), " fill ")) << j;
  EXPECT_TRUE(has(j["provenance"]["command_line"].get<std::string>(), "--units cm")) << j;
  EXPECT_FALSE(j["provenance"]["version"].get<std::string>().empty());
  EXPECT_EQ(j["input"]["units"], "cm");
  EXPECT_EQ(j["input"]["mm_per_unit"], 10);
  EXPECT_NEAR(j["model_volume"].get<double>(), 1000, 10);
  EXPECT_EQ(j["recipe"]["units"], "cm");
}

TEST(CliOutputs, ModelInAnotherUnitIsRefusedWithAHintAndCheckHintsToo) {
  const auto dir = test::scratch_dir();
  const auto in = dir / "part-in-metres.off";
  write_mesh(in, test::make_box({0, 0, 0}, {0.03, 0.02, 0.01}));
  std::string out;
  EXPECT_EQ(run("fill '" + in.string() + "' '" + (dir / "o.stl").string() + "' --cell 2", &out), 2);
  EXPECT_EQ(lines(out), 1u) << out;
  EXPECT_TRUE(has(out,
                  "0.03 mm across, smaller than one 2 mm cell; if it is in metres, add "
                  "--units m"))
      << out;
  EXPECT_FALSE(std::filesystem::exists(dir / "o.stl"));
  EXPECT_EQ(run("check '" + in.string() + "'", &out), 0) << out;
  EXPECT_TRUE(has(out, "hint: the mesh is 0.03 mm across") && has(out, "--units m")) << out;
  EXPECT_EQ(run("check --json --units m '" + in.string() + "'", &out), 0) << out;
  const auto j = nlohmann::json::parse(out);
  EXPECT_TRUE(j["units_hint"].is_null()) << out;
  EXPECT_NEAR(j["bbox"]["max"][0].get<double>(), 30, 1e-9);
  EXPECT_NEAR(j["volume"].get<double>(), 6000, 1e-6);
}

TEST(CliOutputs, ContradictoryOrImpossibleDesignsExitTwo) {
  const auto dir = test::scratch_dir();
  const auto in = dir / "part.off";
  write_mesh(in, test::make_box({0, 0, 0}, {20, 20, 20}));
  const std::string job = "fill '" + in.string() + "' '" + (dir / "o.stl").string() + "' ";
  std::string out;
  EXPECT_EQ(run(job + "--porosity 0.7 --grade level -0.2 0.2", &out), 2);
  EXPECT_TRUE(has(out, "grade the porosity instead")) << out;
  EXPECT_EQ(run(job + "--voxel 1.5", &out), 2);
  EXPECT_TRUE(has(out, "--voxel 0.5 or less")) << out;
  EXPECT_EQ(run(job + "--level 1.9", &out), 2);
  EXPECT_TRUE(has(out, "leaves no solid")) << out;
  EXPECT_FALSE(std::filesystem::exists(dir / "o.stl"));
  // Doubtful: written, with the warning on stderr.
  EXPECT_EQ(run(job + "--voxel 0.6 --quiet", &out), 0);
  EXPECT_TRUE(has(out, "tpmsfill: warning: the voxel (0.6 mm) is coarser than a quarter")) << out;
}

TEST(CliOutputs, RepairReadsUnitsAndWritesMillimetres) {
  const auto dir = test::scratch_dir();
  const auto in = dir / "part.off";
  write_mesh(in, test::make_box_with_hole({0, 0, 0}, {0.02, 0.01, 0.01}));  // metres
  std::string out;
  ASSERT_EQ(run("repair --units m '" + in.string() + "' '" + (dir / "o.off").string() + "'", &out),
            0)
      << out;
  const Box3 box = bounding_box(read_mesh(dir / "o.off"));
  EXPECT_NEAR(box.size().x, 20, 1e-9);
  EXPECT_NEAR(box.size().z, 10, 1e-9);
}

TEST(CliOutputs, FillWritesGzipWhenTheNameEndsInGz) {
  // OUT.stl.gz and OUT.obj.gz: inflated, the bytes of OUT.stl and OUT.obj; `check` reads the
  // compressed result back as a valid closed mesh.
  const auto dir = test::scratch_dir();
  const auto in = dir / "ball.off";
  write_mesh(in, test::make_sphere({0, 0, 0}, 6, 3));
  for (const std::string ext : {".stl", ".obj"}) {
    const auto plain = dir / ("o" + ext), packed = dir / ("o" + ext + ".gz");
    std::string out;
    for (const auto& target : {plain, packed})
      ASSERT_EQ(
          run("fill '" + in.string() + "' '" + target.string() + "' --cell 4 --voxel 0.4", &out), 0)
          << out;
    const std::string bytes = test::read_file(packed);
    EXPECT_EQ(bytes.substr(0, 2), "\x1f\x8b");
    EXPECT_TRUE(detail::inflate_bytes(bytes, packed.string(), UINT64_MAX) == test::read_file(plain))
        << ext;
    EXPECT_EQ(run("check '" + packed.string() + "'", &out), 0) << out;
  }
  std::string out;
  EXPECT_EQ(run("fill '" + in.string() + "' '" + (dir / "o.gz").string() + "' --cell 4", &out), 2);
  EXPECT_TRUE(has(
      out,
      "unknown extension (use .stl, .obj, .ply, .off or .3mf; the first four may end in .gz too)"))
      << out;
}

TEST(CliOutputs, FillAndRepairWrite3mfThatCheckCallsValid) {
  // OUT.3mf from fill (a ball) and from repair (a ball with a hole): `check` reads each back as
  // a valid closed mesh with fill's triangle count; OUT.3mf.gz is refused before any work.
  const auto dir = test::scratch_dir();
  const auto in = dir / "ball.off";
  write_mesh(in, test::make_sphere({0.5, 0, 0}, 6, 3));
  std::string out;
  ASSERT_EQ(run("fill '" + in.string() + "' '" + (dir / "l.3mf").string() +
                    "' --cell 4 --voxel 0.4 --report '" + (dir / "r.json").string() + "'",
                &out),
            0)
      << out;
  EXPECT_EQ(run("check '" + (dir / "l.3mf").string() + "'", &out), 0) << out;
  EXPECT_TRUE(has(out, "3mf")) << out;
  const auto report = nlohmann::json::parse(test::read_file(dir / "r.json"));
  EXPECT_EQ(read_mesh(dir / "l.3mf").triangles.size(),
            report["output"]["triangles"].get<std::size_t>());

  const auto holed = dir / "holed.off";
  write_mesh(holed, test::without_triangles(test::make_sphere({0, 0, 0}, 5, 3),
                                            [](const Vec3& c) { return c.z > 4.6; }));
  ASSERT_EQ(run("repair '" + holed.string() + "' '" + (dir / "fixed.3mf").string() + "'", &out), 0)
      << out;
  EXPECT_EQ(run("check '" + (dir / "fixed.3mf").string() + "'", &out), 0) << out;

  EXPECT_EQ(run("fill '" + in.string() + "' '" + (dir / "l.3mf.gz").string() + "' --cell 4", &out),
            2);
  EXPECT_TRUE(has(out, "unknown extension")) << out;
  EXPECT_FALSE(std::filesystem::exists(dir / "l.3mf.gz"));
}

TEST(CliOutputs, MinWallTurnsMeasuresOnAndTheReportHoldsTheCheck) {
  // --min-wall alone: the measures are taken, the report's printability holds the limit and
  // the counts, and a 3 mm limit on a 4 mm gyroid's struts is warned about with places.
  const auto dir = test::scratch_dir();
  const auto in = dir / "ball.off";
  write_mesh(in, test::make_sphere({0, 0, 0}, 7, 3));
  std::string out;
  ASSERT_EQ(
      run("fill '" + in.string() + "' '" + (dir / "o.stl").string() +
              "' --cell 4 --voxel 0.25 --min-wall 3 --report '" + (dir / "r.json").string() + "'",
          &out),
      0)
      << out;
  EXPECT_TRUE(has(out, "walls below --min-wall 3 mm")) << out;
  const auto report = nlohmann::json::parse(test::read_file(dir / "r.json"));
  EXPECT_FALSE(report["measures"].is_null());
  EXPECT_EQ(report["printability"]["min_wall"].get<double>(), 3.0);
  EXPECT_TRUE(report["printability"]["min_pore"].is_null());
  EXPECT_GT(report["printability"]["walls_below"]["inside"].get<int>(), 0);
  EXPECT_FALSE(report["measures"]["wall_thickness"]["smallest"].empty());
  EXPECT_EQ(
      run("fill '" + in.string() + "' '" + (dir / "p.stl").string() + "' --min-wall -1", &out), 2);
}

// The issue's own case: a 10 x 20 x 30 mm box with a corner where a printer bed puts it fills
// valid with every default, to each format (it used to fail validation: vertices rounded onto
// grid nodes). Far out with a fine voxel, STL is refused before any work with what to do.
TEST(CliOutputs, PartsAwayFromTheOriginFillWithDefaults) {
  const auto dir = test::scratch_dir();
  for (const Vec3 corner : {Vec3{150, 150, 0}, Vec3{0, 0, 1000}, Vec3{-1000, 20, 0}}) {
    write_mesh(dir / "box.off", test::make_box(corner, corner + Vec3{10, 20, 30}));
    for (const char* out_name : {"o.stl", "o.ply"}) {
      std::string out;
      ASSERT_EQ(run("fill " + (dir / "box.off").string() + " " + (dir / out_name).string() +
                        " --cell 5 --voxel 0.25 --quiet",
                    &out),
                0)
          << out;
      ASSERT_EQ(run("check " + (dir / out_name).string(), &out), 0) << out;
    }
  }
  write_mesh(dir / "far.off", test::make_box({1e5, 0, 0}, {1e5 + 1, 1, 1}));
  std::string out;
  EXPECT_EQ(run("fill " + (dir / "far.off").string() + " " + (dir / "far.stl").string() +
                    " --cell 0.4 --voxel 0.01 --quiet",
                &out),
            2);
  EXPECT_TRUE(has(out, "move the part nearer the origin")) << out;
  EXPECT_TRUE(has(out, "write PLY, OBJ or OFF, which hold doubles")) << out;
  EXPECT_FALSE(std::filesystem::exists(dir / "far.stl"));
  // The same to PLY holds the coordinates: it fills.
  EXPECT_EQ(run("fill " + (dir / "far.off").string() + " " + (dir / "far.ply").string() +
                    " --cell 0.4 --voxel 0.01 --quiet",
                &out),
            0)
      << out;
}

// Before any work: the forecast (one JSON object for scripts; a line on stderr for jobs of 5 s
// or more), and a job past the limits refused unless --yes. The forecast is near what ran.
TEST(CliOutputs, PreflightForecastsAndRefusesHugeJobs) {
  const auto dir = test::scratch_dir();
  write_mesh(dir / "box.off", test::make_box({0, 0, 0}, {10, 10, 10}));
  std::string out;
  ASSERT_EQ(run("fill " + (dir / "box.off").string() + " " + (dir / "o.stl").string() +
                    " --cell 2 --voxel 0.1 --progress json",
                &out),
            0)
      << out;
  const std::size_t at = out.find("{\"preflight\"");
  ASSERT_NE(at, std::string::npos) << out;
  const auto f = nlohmann::json::parse(out.substr(at, out.find('\n', at) - at))["preflight"];
  EXPECT_EQ(f["samples"].get<double>(), 105.0 * 105 * 105);  // 101 nodes + 2 pads a side
  const double triangles = static_cast<double>(read_mesh(dir / "o.stl").triangles.size());
  EXPECT_NEAR(f["triangles"].get<double>() / triangles, 1.0, 0.3) << out;
  EXPECT_NEAR(f["bytes"].get<double>(), 84 + 50 * f["triangles"].get<double>(), 1) << out;
  EXPECT_LT(f["seconds"][0].get<double>(), f["seconds"][1].get<double>());
  // 10 x 20 x 30 mm at 0.005 mm: 5e10 samples streamed by slabs within the memory budget, but
  // a 60 GB STL and hours of work: refused at once, nothing written.
  write_mesh(dir / "big.off", test::make_box({0, 0, 0}, {10, 20, 30}));
  const auto t0 = std::chrono::steady_clock::now();
  EXPECT_EQ(run("fill " + (dir / "big.off").string() + " " + (dir / "big.stl").string() +
                    " --voxel 0.005",
                &out),
            2);
  EXPECT_LT(test::seconds_since(t0), 20.0) << "refused before any work";
  EXPECT_TRUE(has(out, "the job would write about")) << out;
  EXPECT_TRUE(has(out, "--yes runs it as it is")) << out;
  EXPECT_FALSE(std::filesystem::exists(dir / "big.stl"));
}

// slice forecasts its layers, contour points and file before any work, near what it writes,
// and refuses a stack past the limits unless --yes.
TEST(CliOutputs, SlicePreflightForecastsTheLayers) {
  const auto dir = test::scratch_dir();
  write_mesh(dir / "ball.off", test::make_sphere({150, 150, 20}, 8, 4));
  for (const char* format : {"o.cli", "o-binary.cli --binary", "o.svg"}) {
    std::string out;
    const std::string name = std::string(format).substr(0, std::string(format).find(' '));
    ASSERT_EQ(run("slice " + (dir / "ball.off").string() + " " + (dir / format).string() +
                      " --layer 0.1 --cell 2 --voxel 0.1 --progress json --report " +
                      (dir / "r.json").string(),
                  &out),
              0)
        << out;
    const std::size_t at = out.find("{\"preflight\"");
    ASSERT_NE(at, std::string::npos) << out;
    const auto f = nlohmann::json::parse(out.substr(at, out.find('\n', at) - at))["preflight"];
    const auto r = nlohmann::json::parse(test::read_file(dir / "r.json"))["slice"];
    EXPECT_EQ(f["layers"], r["layers"]);
    EXPECT_NEAR(f["points"].get<double>() / r["points"].get<double>(), 1.0, 0.3) << out;
    EXPECT_NEAR(
        f["bytes"].get<double>() / static_cast<double>(std::filesystem::file_size(dir / name)), 1.0,
        0.3)
        << format;
  }
  std::string out;
  EXPECT_EQ(run("slice " + (dir / "ball.off").string() + " " + (dir / "huge.cli").string() +
                    " --layer 0.001 --cell 2 --voxel 0.005",
                &out),
            2);
  EXPECT_TRUE(has(out, "the job would write about")) << out;
  EXPECT_FALSE(std::filesystem::exists(dir / "huge.cli"));
}

// Off a terminal, --progress json gives one JSON object a line: every stage's start at least.
TEST(CliOutputs, ProgressAsJsonLinesForScripts) {
  const auto dir = test::scratch_dir();
  write_mesh(dir / "ball.off", test::make_sphere({0, 0, 0}, 6, 3));
  std::string out;
  ASSERT_EQ(run("fill " + (dir / "ball.off").string() + " " + (dir / "o.stl").string() +
                    " --cell 2 --voxel 0.2 --progress json",
                &out),
            0)
      << out;
  std::size_t objects = 0;
  std::istringstream lines_in(out);
  for (std::string line; std::getline(lines_in, line);)
    if (!line.empty() && line[0] == '{') {
      const auto j = nlohmann::json::parse(line);
      if (j.contains("preflight")) continue;
      EXPECT_TRUE(j.contains("stage") && j.contains("percent") && j.contains("overall")) << line;
      ++objects;
    }
  EXPECT_GE(objects, 5u) << out;
  // --progress none (and --quiet) print none; a wrong mode is refused in one sentence.
  ASSERT_EQ(run("fill " + (dir / "ball.off").string() + " " + (dir / "o.stl").string() +
                    " --cell 2 --voxel 0.2 --progress none",
                &out),
            0);
  EXPECT_FALSE(has(out, "\"stage\"")) << out;
  EXPECT_EQ(run("fill " + (dir / "ball.off").string() + " " + (dir / "o.stl").string() +
                    " --progress loud",
                &out),
            2);
}

// The memory estimate is an upper bound on the process's peak, and --memory below it is kept
// by slabs (a dragon at 0.4 mm peaked at 1.6 GB against an estimate of 0.7 GB, and with
// --memory 3G at 0.2 mm it ran in 4.5 GB). Resident memory under AddressSanitizer is not the
// program's: skipped there.
TEST(CliOutputs, MemoryEstimateBoundsThePeakAndTheBudgetIsKept) {
#if defined(__SANITIZE_ADDRESS__)
  GTEST_SKIP() << "AddressSanitizer's shadow memory is in the resident set";
#endif
  const std::filesystem::path dragon =
      std::filesystem::path(TPMSFILL_CGAL_MESHES) / "ChineseDragon-10kv.off";
  if (!std::filesystem::exists(dragon)) GTEST_SKIP() << dragon << " is missing: libcgal-demo";
  const auto dir = test::scratch_dir();
  std::string out;
  ASSERT_EQ(run("fill " + dragon.string() + " " + (dir / "d.stl").string() +
                    " --voxel 0.5 --quiet --report " + (dir / "r.json").string(),
                &out),
            0)
      << out;
  const auto r = nlohmann::json::parse(test::read_file(dir / "r.json"));
  const double estimate = r["estimated_memory_bytes"].get<double>();
  const double peak = r["peak_memory_mb"].get<double>() * 1024 * 1024;
  EXPECT_LE(peak, estimate) << "the estimate is an upper bound";
  EXPECT_GE(peak, 0.6 * estimate) << "and not far above the peak";
  // Half the whole grid's estimate: slabs, streamed, within the budget.
  const auto budget = static_cast<std::uint64_t>(estimate / 2);
  ASSERT_EQ(run("fill " + dragon.string() + " " + (dir / "s.stl").string() +
                    " --voxel 0.5 --quiet --memory " + std::to_string(budget) + " --report " +
                    (dir / "s.json").string(),
                &out),
            0)
      << out;
  const auto s = nlohmann::json::parse(test::read_file(dir / "s.json"));
  EXPECT_GT(s["slab_planes"].get<int>(), 0);
  EXPECT_LE(s["peak_memory_mb"].get<double>() * 1024 * 1024, static_cast<double>(budget));
  EXPECT_EQ(test::read_file(dir / "s.stl"), test::read_file(dir / "d.stl"));
}
