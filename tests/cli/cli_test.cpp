// The `tpmsfill` program as a user runs it: exit codes, one-line errors, JSON that parses,
// and docs/cli.md naming every option --help lists.
#include <gtest/gtest.h>
#include <sys/resource.h>

// GCC 12 reports a false -Wrestrict inside std::string concatenation here (GCC bug 105329).
#pragma GCC diagnostic ignored "-Wrestrict"

#include <cctype>
#include <nlohmann/json.hpp>
#include <set>
#include <tpmsfill/io.hpp>

#include "test_util.hpp"

using namespace tpmsfill;

namespace {

std::string cli() {
  return TPMSFILL_CLI;
}

int check(const std::filesystem::path& file, const std::string& flags, std::string* out) {
  return test::run_command(cli() + " check " + flags + " '" + file.string() + "'", out);
}

std::size_t count_lines(const std::string& s) {
  return static_cast<std::size_t>(std::count(s.begin(), s.end(), '\n'));
}

}  // namespace

TEST(Cli, ValidMeshExitsZero) {
  auto dir = test::scratch_dir();
  write_mesh(dir / "box.stl", test::make_box({0, 0, 0}, {10, 20, 30}));
  std::string out;
  EXPECT_EQ(check(dir / "box.stl", "", &out), 0) << out;
  EXPECT_NE(out.find("verdict: VALID"), std::string::npos) << out;
  EXPECT_NE(out.find("6000"), std::string::npos) << "volume missing:\n" << out;
}

// Scenes through assimp: COLLADA checked, a GLB filled and the lattice checked valid.
TEST(Cli, ChecksTheColladaDuckAndFillsAGlb) {
  const std::filesystem::path models(TPMSFILL_ASSIMP_MODELS);
  if (!std::filesystem::is_directory(models)) GTEST_SKIP() << "assimp-testmodels missing";
  std::string out;
  const int status = check(models / "Collada/duck.dae", "--no-self-intersections", &out);
  if (out.find("lacks") != std::string::npos) GTEST_SKIP() << "built without assimp";
  EXPECT_EQ(status, 0) << out;
  EXPECT_NE(out.find(": scene, 4212 triangles"), std::string::npos) << out;
  EXPECT_NE(out.find("verdict: VALID"), std::string::npos) << out;

  const auto lattice = test::scratch_dir() / "cesium-box-gyroid.stl";
  std::filesystem::remove(lattice);
  ASSERT_EQ(
      test::run_command(cli() + " fill --quiet --cell 250 --voxel 20 '" +
                            (models / "glTF2/BoxTextured-glTF-Binary/BoxTextured.glb").string() +
                            "' '" + lattice.string() + "'",
                        &out),
      0)
      << out;
  EXPECT_EQ(check(lattice, "", &out), 0) << out;
  const Box3 box = bounding_box(read_mesh(lattice));  // the 1 m cube, in mm, up to a voxel
  EXPECT_NEAR(box.min.z, -500, 20);
  EXPECT_NEAR(box.max.z, 500, 20);
}

TEST(Cli, OpenMeshExitsOneAndSaysWhere) {
  auto dir = test::scratch_dir();
  write_mesh(dir / "open.obj", test::make_box_with_hole({0, 0, 0}, {1, 1, 1}));
  std::string out;
  EXPECT_EQ(check(dir / "open.obj", "", &out), 1) << out;
  EXPECT_NE(out.find("NOT VALID"), std::string::npos) << out;
  EXPECT_NE(out.find("border edges"), std::string::npos) << out;
  EXPECT_NE(out.find("at edge ("), std::string::npos) << "no location given:\n" << out;
}

TEST(Cli, JsonParsesAndAgreesWithExitCode) {
  auto dir = test::scratch_dir();
  write_mesh(dir / "torus.ply", test::make_torus(3, 1, 48, 24));
  write_mesh(dir / "bowtie.off", test::make_bow_tie());
  std::string out;
  ASSERT_EQ(check(dir / "torus.ply", "--json", &out), 0) << out;
  auto j = nlohmann::json::parse(out);
  EXPECT_EQ(j["valid"], true);
  EXPECT_EQ(j["format"], "ply");
  EXPECT_EQ(j["triangles"], 48 * 24 * 2);
  EXPECT_EQ(j["genus"], 1);
  EXPECT_EQ(j["border_edges"], 0);

  ASSERT_EQ(check(dir / "bowtie.off", "--json", &out), 1) << out;
  j = nlohmann::json::parse(out);
  EXPECT_EQ(j["valid"], false);
  EXPECT_EQ(j["non_manifold_vertices"], 1);
  EXPECT_FALSE(j["problems"].empty());
}

TEST(Cli, UnreadableInputExitsTwoWithOneLine) {
  auto dir = test::scratch_dir();
  test::write_file(dir / "bad.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 7\n");
  test::write_file(dir / "empty.stl", "");
  for (const char* name : {"bad.obj", "empty.stl", "missing.off"}) {
    std::string out;
    EXPECT_EQ(check(dir / name, "", &out), 2) << name << ": " << out;
    EXPECT_EQ(count_lines(out), 1u) << name << ": " << out;
    EXPECT_NE(out.find(name), std::string::npos) << "message does not name the file: " << out;
  }
  std::string out;
  EXPECT_EQ(check(dir / "bad.obj", "", &out), 2);
  EXPECT_NE(out.find(":4:"), std::string::npos) << "message does not name line 4: " << out;
}

TEST(Cli, HugeDeclaredCountsFailCleanlyUnderAMemoryLimit) {
#if defined(__SANITIZE_ADDRESS__)
  GTEST_SKIP() << "AddressSanitizer reserves more address space than the limit allows";
#else
  auto dir = test::scratch_dir();
  test::write_file(dir / "huge.ply",
                   "ply\nformat binary_little_endian 1.0\nelement vertex 4000000000\n"
                   "property float x\nproperty float y\nproperty float z\nelement face 1\n"
                   "property list uchar int vertex_indices\nend_header\n0123456789");
  test::write_file(dir / "huge.off", "OFF\n2000000000 2000000000 0\n0 0 0\n");
  std::string stl(84, ' ');
  stl[80] = '\xff', stl[81] = '\xff', stl[82] = '\xff', stl[83] = '\x7f';
  test::write_file(dir / "huge.stl", stl + std::string(100, '\0'));
  for (const char* name : {"huge.ply", "huge.off", "huge.stl"}) {
    std::string out;
    // 512 MiB of address space: a reader that trusted the header would die of bad_alloc (3).
    EXPECT_EQ(
        test::run_command("ulimit -v 524288; " + cli() + " check " + (dir / name).string(), &out),
        2)
        << name << ": " << out;
  }
#endif
}

TEST(Cli, UsageErrorsExitTwoAndHelpExitsZero) {
  std::string out;
  EXPECT_EQ(test::run_command(cli(), &out), 2) << out;
  EXPECT_EQ(test::run_command(cli() + " check", &out), 2) << out;
  EXPECT_EQ(test::run_command(cli() + " check a.stl --no-such-flag", &out), 2) << out;
  EXPECT_EQ(test::run_command(cli() + " --help", &out), 0) << out;
  EXPECT_EQ(test::run_command(cli() + " --version", &out), 0) << out;
}

TEST(Cli, DocsNameEveryOptionOfHelp) {
  const std::string docs =
      test::read_file(std::filesystem::path(TPMSFILL_SOURCE_DIR) / "docs/cli.md");
  ASSERT_FALSE(docs.empty());
  for (const std::string command :
       {"", "check", "fill", "repair", "decimate", "field", "field fit", "field edit", "field info",
        "field mesh", "field from-mesh", "field from-points", "field from-ct"}) {
    std::string help;
    ASSERT_EQ(test::run_command(cli() + " " + command + " --help", &help), 0);
    // Every "--word" in the help text (no std::regex: GCC 12 warns inside it under ASan).
    std::set<std::string> options;
    for (std::size_t at = help.find("--"); at != std::string::npos; at = help.find("--", at + 2)) {
      std::size_t end = at + 2;
      while (end < help.size() &&
             (std::islower(static_cast<unsigned char>(help[end])) || help[end] == '-'))
        ++end;
      if (end > at + 2) options.insert(help.substr(at, end - at));
    }
    for (const std::string& o : options) {
      if (o == "--help") continue;
      EXPECT_NE(docs.find("`" + o), std::string::npos) << o << " missing from docs/cli.md";
    }
  }
}

TEST(Cli, FillWritesAValidLatticeAndReport) {
  const auto dir = test::scratch_dir();
  write_mesh(dir / "ball.stl", test::make_sphere({0, 0, 0}, 5.0, 4));
  std::string out;
  ASSERT_EQ(
      test::run_command(cli() + " fill '" + (dir / "ball.stl").string() + "' '" +
                            (dir / "lattice.stl").string() + "' --cell 2 --voxel 0.25 --report '" +
                            (dir / "r.json").string() + "'",
                        &out),
      0)
      << out;
  EXPECT_NE(out.find("porosity"), std::string::npos) << out;
  const auto report = nlohmann::json::parse(test::read_file(dir / "r.json"));
  EXPECT_TRUE(report["valid"].get<bool>());
  EXPECT_GT(report["output"]["triangles"].get<double>(), 1000);
  EXPECT_GT(report["band_nodes"].get<double>(), 0);
  EXPECT_FALSE(report["stages"].empty());
  // What was written is what `check` calls valid.
  EXPECT_EQ(check(dir / "lattice.stl", "", &out), 0) << out;
}

TEST(Cli, FillFailuresExitTwoAndWriteNothing) {
  const auto dir = test::scratch_dir();
  write_mesh(dir / "ball.stl", test::make_sphere({0, 0, 0}, 5.0, 3));
  const std::string in = "'" + (dir / "ball.stl").string() + "' ";
  const std::string lattice = "'" + (dir / "lattice.stl").string() + "'";
  test::write_file(dir / "bad.json", "{\n  \"lattice\": {\"tpye\": \"gyroid\"}\n}\n");
  std::string out;
  const std::vector<std::string> cases = {
      in + lattice + " --lattice kelvin",
      in + lattice + " --inside majority",
      in + lattice + " --voxel 0",
      in + lattice + " --cell 1 2",
      in + lattice + " --thickness 0.2",
      in + lattice + " --voxel 0.001 --memory 64M",
      in + lattice + " --porosity 0.7 --level 0.1",
      in + lattice + " --porosity 1.2",
      in + lattice + " --grade porosity 0.8 0.5 --grade-along w",
      in + lattice + " --grade-along depth",
      in + lattice + " --grade cell 0 4 --grade-along depth",
      in + lattice + " --grade level 0 0.2 --sheet",
      in + lattice + " --skin-windows",
      in + lattice + " --recipe '" + (dir / "bad.json").string() + "'",
      in + "'" + (dir / "x.xyz").string() + "'",
      "'" + (dir / "missing.stl").string() + "' " + lattice};
  for (const std::string& args : cases) {
    EXPECT_EQ(test::run_command(cli() + " fill " + args, &out), 2) << args << "\n" << out;
    EXPECT_EQ(count_lines(out), 1u) << out;
    EXPECT_FALSE(std::filesystem::exists(dir / "lattice.stl")) << args;
  }
  EXPECT_EQ(
      test::run_command(cli() + " fill " + in + lattice + " --voxel 0.001 --memory 128M", &out), 2);
  EXPECT_NE(out.find("voxel size of"), std::string::npos) << out;
  EXPECT_EQ(test::run_command(
                cli() + " fill " + in + lattice + " --recipe '" + (dir / "bad.json").string() + "'",
                &out),
            2);
  EXPECT_NE(out.find("lattice.tpye: unknown key"), std::string::npos) << out;
}

TEST(Cli, FillOverTheBudgetStreamsTheSameBytes) {
  // A budget under the whole grid's estimate: the job goes in slabs and its output is streamed
  // into OUT, the same bytes as the held path writes, and nothing else is left in the folder.
  const auto dir = test::scratch_dir();
  write_mesh(dir / "ball.stl", test::make_sphere({0, 0, 0}, 5.0, 3));
  const std::string job = cli() + " fill '" + (dir / "ball.stl").string() + "' ";
  const std::string flags = " --cell 2 --voxel 0.04 --quiet --report ";
  std::string out;
  ASSERT_EQ(test::run_command(job + "'" + (dir / "held.stl").string() + "'" + flags + "'" +
                                  (dir / "held.json").string() + "'",
                              &out),
            0)
      << out;
  const auto held = nlohmann::json::parse(test::read_file(dir / "held.json"));
  ASSERT_TRUE(held["slab_planes"].is_null());
  const auto budget = held["estimated_memory_bytes"].get<std::uint64_t>() - 1;
  ASSERT_EQ(test::run_command(job + "'" + (dir / "streamed.stl").string() + "'" + flags + "'" +
                                  (dir / "streamed.json").string() + "' --memory " +
                                  std::to_string(budget),
                              &out),
            0)
      << out;
  const auto streamed = nlohmann::json::parse(test::read_file(dir / "streamed.json"));
  EXPECT_GT(streamed["slab_planes"].get<int>(), 0);
  EXPECT_LE(streamed["estimated_memory_bytes"].get<std::uint64_t>(), budget);
  EXPECT_TRUE(streamed["valid"].get<bool>());
  bool streamed_stage = false;
  for (const auto& stage : streamed["stages"])
    streamed_stage = streamed_stage || stage["name"] == "validate and write";
  EXPECT_TRUE(streamed_stage);
  EXPECT_TRUE(test::read_file(dir / "streamed.stl") == test::read_file(dir / "held.stl"));
  std::vector<std::string> names;
  for (const auto& entry : std::filesystem::directory_iterator(dir))
    names.push_back(entry.path().filename().string());
  std::sort(names.begin(), names.end());
  EXPECT_EQ(names, (std::vector<std::string>{"ball.stl", "held.json", "held.stl", "streamed.json",
                                             "streamed.stl"}));
}

TEST(Cli, FillTakesTheLatticeDesignFlagsAndEchoesTheRecipe) {
  // Every design flag at once on a ball; the report's recipe, given back as --recipe, writes
  // the same bytes.
  const auto dir = test::scratch_dir();
  write_mesh(dir / "ball.stl", test::make_sphere({0, 0, 0}, 5.0, 3));
  const std::string in = "'" + (dir / "ball.stl").string() + "' ";
  std::string out;
  ASSERT_EQ(test::run_command(cli() + " fill " + in + "'" + (dir / "a.stl").string() +
                                  "' --lattice splitp --cell 3 --porosity 0.6 --rotate 10 20 30 "
                                  "--origin 0.5 0 0 --grade porosity 0.7 0.5 --grade-along "
                                  "radial --skin 0.3 --skin-windows --measure --voxel 0.2 "
                                  "--report '" +
                                  (dir / "r.json").string() + "'",
                              &out),
            0)
      << out;
  const auto report = nlohmann::json::parse(test::read_file(dir / "r.json"));
  EXPECT_EQ(report["lattice"]["porosity_target"], 0.6);
  EXPECT_EQ(report["measures"]["labyrinths"], 1);
  test::write_file(dir / "echo.json", report["recipe"].dump());
  ASSERT_EQ(test::run_command(cli() + " fill " + in + "'" + (dir / "b.stl").string() +
                                  "' --quiet --recipe '" + (dir / "echo.json").string() + "'",
                              &out),
            0)
      << out;
  EXPECT_EQ(test::read_file(dir / "a.stl"), test::read_file(dir / "b.stl"));
}

TEST(Cli, FillHandlesHolesAndRefusesASheetInOneLine) {
  const auto dir = test::scratch_dir();
  // A ball with its cap beyond x = 4.5 cut away (written as STL: unwelded points); the grid's
  // rows run along x, so some of them pass through the hole.
  const TriangleSoup ball = test::make_sphere({0, 0, 0}, 5.0, 4);
  TriangleSoup open;
  open.points = ball.points;
  for (const Triangle& t : ball.triangles)
    if (ball.points[t[0]].x < 4.5 && ball.points[t[1]].x < 4.5 && ball.points[t[2]].x < 4.5)
      open.triangles.push_back(t);
  write_mesh(dir / "open.stl", open);
  const std::string in = "'" + (dir / "open.stl").string() + "' ";
  const std::string lattice = "'" + (dir / "lattice.stl").string() + "'";
  const std::string report = " --report '" + (dir / "r.json").string() + "'";
  std::string out;
  ASSERT_EQ(test::run_command(cli() + " fill " + in + lattice + " --voxel 0.25" + report, &out), 0)
      << out;
  EXPECT_NE(out.find("winding number (1 hole(s) capped"), std::string::npos) << out;
  auto r = nlohmann::json::parse(test::read_file(dir / "r.json"));
  EXPECT_EQ(r["inside"]["rule"], "winding");
  EXPECT_EQ(r["inside"]["holes"].get<int>(), 1);
  EXPECT_EQ(check(dir / "lattice.stl", "", &out), 0) << out;
  // Parity says what it cannot do.
  ASSERT_EQ(test::run_command(
                cli() + " fill " + in + lattice + " --voxel 0.25 --inside parity" + report, &out),
            0)
      << out;
  EXPECT_NE(out.find("odd number of times"), std::string::npos) << out;
  // A flat sheet: one sentence, exit 2, nothing written.
  std::filesystem::remove(dir / "lattice.stl");
  TriangleSoup sheet;
  // Planar, and through no grid node (on the sheet w is ½).
  auto z = [](double x, double y) { return 0.3137 + 0.12345 * x + 0.0567 * y; };
  sheet.points = {{0, 0, z(0, 0)}, {10, 0, z(10, 0)}, {10, 10, z(10, 10)}, {0, 10, z(0, 10)}};
  sheet.triangles = {{0, 1, 2}, {0, 2, 3}};
  write_mesh(dir / "sheet.stl", sheet);
  EXPECT_EQ(test::run_command(
                cli() + " fill '" + (dir / "sheet.stl").string() + "' " + lattice + " --voxel 0.25",
                &out),
            2);
  EXPECT_EQ(count_lines(out), 1u) << out;
  EXPECT_NE(out.find("encloses no volume"), std::string::npos) << out;
  EXPECT_FALSE(std::filesystem::exists(dir / "lattice.stl"));
}

// Usage errors read like the tool's own: one line, exit 2, no parser library's wording, and
// a did-you-mean for misspelt options and commands.
TEST(CliUsage, EveryUsageErrorIsOneSentenceOfOurs) {
  auto dir = test::scratch_dir();
  const std::string in = (dir / "box.off").string(), out = (dir / "o.stl").string();
  write_mesh(in, test::make_box({0, 0, 0}, {10, 10, 10}));
  const std::string job = "fill '" + in + "' '" + out + "' ";
  const std::pair<std::string, std::string> cases[] = {
      {"",
       "a command is needed: check, fill, repair, decimate, field, conformal, slice, render, "
       "material or serve"},
      {"serve --listen localhost", "--listen: 'localhost' is not ADDRESS:PORT"},
      {"serve --jobs 0", "--jobs must be 1 to 64"},
      {"serve --listen 127.0.0.1:70000", "the port in '127.0.0.1:70000' must be 0 to 65535"},
      {"field", "field needs a command: fit, edit, info, mesh, from-mesh, from-points or from-ct"},
      {"field fitt a b", "unknown command 'fitt' for field (did you mean fit?)"},
      {"field fit", "field fit needs IN and OUT"},
      {"material", "material needs a command: info, fit, slice or iso"},
      {"material slice m.tsm o.cli", "material slice needs --layer"},
      {"material iso m.tsm o.ply", "material iso needs --values"},
      {"material fit a.mesh", "material fit needs OUT"},
      {"material fit a.mesh b.tsm --step 2", "--step must be 0.01 to 1"},
      {"material inf x", "unknown command 'inf' for material (did you mean info?)"},
      {"material info", "material info needs IN"},
      {"material info a.mesh --cell 0", "--cell must be > 0"},
      {"material info a.mesh --corners 1 2", "--corners takes 8 values"},
      {"field fit a b --methd lspia",
       "unknown option --methd for field fit (did you mean --method?)"},
      {"fil a b", "unknown command 'fil' (did you mean fill?)"},
      {"fill", "fill needs IN and OUT"},
      {"check", "check needs FILE"},
      {"slice a.stl b.cli", "slice needs --layer"},
      {job + "--scale 0", "--scale must be > 0"},
      {job + "--poro 0.7", "unknown option --poro for fill (did you mean --porosity?)"},
      {job + "--porosity 0.7 extra", "unexpected argument 'extra'"},
      {job + "--cell 1 2 3 4", "--cell takes 1 to 3 values"},
      {job + "--rotate 1 2", "--rotate takes 3 values"},
      {job + "--voxel abc", "--voxel: 'abc' is not a number"},
      {job + "--band 2.5", "--band: '2.5' is not a whole number"},
      {job + "--band 0", "--band must be 1 to 64"},
      {job + "--threads 0", "--threads must be 1 to 1024"},
      {job + "--voxel", "--voxel needs a value"},
      {job + "--grade porosity 0.5", "--grade takes three values each time"},
      {job + "--recipe '" + (dir / "none.json").string() + "'", "--recipe: no such file"},
      {job + "--units furlong", "unknown unit 'furlong'"},
      {"repair --alpah 2 '" + in + "' '" + out + "'",
       "unknown option --alpah for repair (did you mean --alpha?)"},
      {"repair '" + in + "' '" + out + "' --min-component 1",
       "--min-component must be at least 0 and below 1"},
      {"check --max-examples -1 '" + in + "'", "--max-examples must be 0 to 1000000"},
      {"conformal '" + in + "' '" + out + "'", "conformal needs --height"},
      {"conformal '" + in + "' '" + out + "' --hieght 2",
       "unknown option --hieght for conformal (did you mean --height?)"},
  };
  for (const auto& [args, sentence] : cases) {
    std::string output;
    EXPECT_EQ(test::run_command(cli() + " " + args + " 2>&1", &output), 2) << args;
    EXPECT_EQ(count_lines(output), 1u) << args << "\n" << output;
    EXPECT_EQ(output.rfind("tpmsfill: error: ", 0), 0u) << output;
    EXPECT_NE(output.find(sentence), std::string::npos) << args << "\n" << output;
    for (const char* leak : {"required", "not expected", "not in range", "Could not convert",
                             "At Most", "At least", "FLOAT", "TEXT"})
      EXPECT_EQ(output.find(leak), std::string::npos) << args << "\n" << output;
  }
  EXPECT_FALSE(std::filesystem::exists(out));
  // --help and --version still exit 0.
  std::string help;
  EXPECT_EQ(test::run_command(cli() + " fill --help", &help), 0);
  EXPECT_NE(help.find("--units"), std::string::npos);
  EXPECT_EQ(test::run_command(cli() + " --version", &help), 0);
  EXPECT_NE(help.find("tpmsfill "), std::string::npos);
}

TEST(Cli, FillTakesASheetBetweenTwoLevels) {
  // --levels C1 C2: walls where C1 <= f̃ <= C2, named in the summary; the echoed recipe keeps
  // the level and rebuilds the same lattice.
  const auto dir = test::scratch_dir();
  write_mesh(dir / "box.off", test::make_box({0, 0, 0}, {8, 8, 8}));
  const std::string job = "fill '" + (dir / "box.off").string() + "' '" + (dir / "o.stl").string() +
                          "' --cell 4 --voxel 0.2 ";
  std::string out;
  ASSERT_EQ(test::run_command(cli() + " " + job + "--levels 0.2 0.8 --report '" +
                                  (dir / "r.json").string() + "' 2>&1",
                              &out),
            0)
      << out;
  EXPECT_NE(out.find("gyroid sheet between levels 0.2 and 0.8 mm"), std::string::npos) << out;
  const auto report = nlohmann::json::parse(test::read_file(dir / "r.json"));
  EXPECT_DOUBLE_EQ(report["recipe"]["lattice"]["level"].get<double>(), -0.5);
  EXPECT_EQ(test::run_command(cli() + " " + job + "--levels 0.8 0.2 2>&1", &out), 2);
  EXPECT_NE(out.find("--levels C1 C2 needs C1 < C2"), std::string::npos) << out;
  EXPECT_EQ(test::run_command(cli() + " " + job + "--levels 0 0.4 --porosity 0.7 2>&1", &out), 2);
  EXPECT_NE(out.find("--levels sets the sheet's walls"), std::string::npos) << out;
}

TEST(Cli, FillTakesAFourierLatticeAndRawLevels) {
  // Issue 41: --lattice fourier with the primitive's three terms writes the primitive's bytes;
  // raw levels (the seeds' C on f) are named in the summary, echoed as {"c": ...} in the
  // recipe, and the echo writes the same bytes; mixing units, a term without fourier and a
  // fractional wave are one-line usage errors.
  const auto dir = test::scratch_dir();
  write_mesh(dir / "box.off", test::make_box({0, 0, 0}, {8, 8, 8}));
  auto out_file = [&](const std::string& name) { return "'" + (dir / name).string() + "' "; };
  auto job = [&](const std::string& out) {
    return "fill " + out_file("box.off") + out_file(out) + "--cell 4 --voxel 0.2 ";
  };
  std::string out;
  ASSERT_EQ(
      test::run_command(cli() + " " + job("named.stl") + "--lattice primitive --quiet 2>&1", &out),
      0)
      << out;
  ASSERT_EQ(test::run_command(cli() + " " + job("fourier.stl") +
                                  "--lattice fourier --term 1 1 0 0 0 --term 1 0 1 0 0 "
                                  "--term 1 0 0 1 0 2>&1",
                              &out),
            0)
      << out;
  EXPECT_NE(out.find("fourier (3 terms) network"), std::string::npos) << out;
  EXPECT_EQ(test::read_file(dir / "named.stl"), test::read_file(dir / "fourier.stl"));
  ASSERT_EQ(test::run_command(cli() + " " + job("raw.stl") +
                                  "--lattice diamond --levels -0.4c 0.2c --report " +
                                  out_file("r.json") + "2>&1",
                              &out),
            0)
      << out;
  EXPECT_NE(out.find("diamond sheet between levels -0.4 and 0.2 (raw C)"), std::string::npos)
      << out;
  const auto report = nlohmann::json::parse(test::read_file(dir / "r.json"));
  EXPECT_EQ(report["lattice"]["level_unit"], "c");
  EXPECT_DOUBLE_EQ(report["recipe"]["lattice"]["level"]["c"].get<double>(), 0.1);
  EXPECT_DOUBLE_EQ(report["recipe"]["lattice"]["thickness"]["c"].get<double>(), 0.6);
  test::write_file(dir / "echo.json", report["recipe"].dump());
  ASSERT_EQ(
      test::run_command(cli() + " fill '" + (dir / "box.off").string() + "' " +
                            out_file("echo.stl") + "--quiet --recipe " + out_file("echo.json"),
                        &out),
      0)
      << out;
  EXPECT_EQ(test::read_file(dir / "raw.stl"), test::read_file(dir / "echo.stl"));
  EXPECT_EQ(test::run_command(cli() + " " + job("x.stl") + "--sheet --levels 0 0.4c 2>&1", &out),
            2);
  EXPECT_NE(out.find("mixes mm and raw C"), std::string::npos) << out;
  EXPECT_EQ(test::run_command(cli() + " " + job("x.stl") + "--term 1 1 0 0 0 2>&1", &out), 2);
  EXPECT_NE(out.find("--term needs --lattice fourier"), std::string::npos) << out;
  EXPECT_EQ(test::run_command(
                cli() + " " + job("x.stl") + "--lattice fourier --term 1 0.5 0 0 0 2>&1", &out),
            2);
  EXPECT_NE(out.find("whole periods per cell"), std::string::npos) << out;
  EXPECT_EQ(test::run_command(cli() + " " + job("x.stl") + "--level 0.3x 2>&1", &out), 2);
  EXPECT_NE(out.find("not a number of mm (0.3) or a raw level C"), std::string::npos) << out;
  EXPECT_FALSE(std::filesystem::exists(dir / "x.stl"));
}
