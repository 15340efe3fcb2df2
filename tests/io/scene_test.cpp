// Scenes through assimp (src/io/scene.cpp): glTF written here (a box placed several times, one
// placement mirrored) read as the scene shows it, upright and in millimetres; a scene's side
// files read only from its folder; a scene that multiplies out refused; and assimp-testmodels'
// glTF, GLB, COLLADA, FBX and 3DS files read as the solids they are.
// GCC 12 reports a false -Wrestrict inside std::string concatenation here (GCC bug 105329).
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC diagnostic ignored "-Wrestrict"
#endif
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <string>
#include <vector>

#include "test_util.hpp"
#include "tpmsfill/check.hpp"
#include "tpmsfill/error.hpp"
#include "tpmsfill/io.hpp"

namespace tpmsfill {
namespace {

namespace fs = std::filesystem;

bool built_with_assimp() {
  try {
    parse_mesh("{\"asset\":{\"version\":\"2.0\"}}", "probe.gltf");
  } catch (const InputError& e) {
    return std::string(e.what()).find("lacks") == std::string::npos;
  } catch (const Error&) {
  }
  return true;
}

std::string base64(const std::string& bytes) {
  static constexpr char kAlphabet[] =
      "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  for (std::size_t i = 0; i < bytes.size(); i += 3) {
    std::uint32_t n = static_cast<unsigned char>(bytes[i]) << 16;
    if (i + 1 < bytes.size()) n |= static_cast<unsigned char>(bytes[i + 1]) << 8;
    if (i + 2 < bytes.size()) n |= static_cast<unsigned char>(bytes[i + 2]);
    out += kAlphabet[n >> 18 & 63];
    out += kAlphabet[n >> 12 & 63];
    out += i + 1 < bytes.size() ? kAlphabet[n >> 6 & 63] : '=';
    out += i + 2 < bytes.size() ? kAlphabet[n & 63] : '=';
  }
  return out;
}

// A soup as glTF's buffer: float positions, then 32-bit indices.
std::string buffer_of(const TriangleSoup& soup) {
  std::string bytes;
  for (const Vec3& p : soup.points) {
    for (const double c : {p.x, p.y, p.z}) {
      const float f = static_cast<float>(c);
      bytes.append(reinterpret_cast<const char*>(&f), 4);
    }
  }
  for (const Triangle& t : soup.triangles)
    for (const std::uint32_t v : t) bytes.append(reinterpret_cast<const char*>(&v), 4);
  return bytes;
}

// A glTF 2.0 document whose one mesh is `soup` (its buffer at `uri`, or embedded), placed by
// `nodes` (a JSON array) and the scene's roots `roots`.
std::string gltf_of(const TriangleSoup& soup, const std::string& nodes, const std::string& roots,
                    std::string uri = {}) {
  const std::string bytes = buffer_of(soup);
  if (uri.empty()) uri = "data:application/octet-stream;base64," + base64(bytes);
  const std::size_t vertex_bytes = soup.points.size() * 12;
  const Box3 box = bounding_box(soup);
  auto num = [](double v) { return std::to_string(static_cast<float>(v)); };
  return R"({"asset":{"version":"2.0"},"scene":0,"scenes":[{"nodes":)" + roots + R"(}],
"nodes":)" +
         nodes + R"(,
"meshes":[{"primitives":[{"attributes":{"POSITION":0},"indices":1,"mode":4}]}],
"buffers":[{"byteLength":)" +
         std::to_string(bytes.size()) + R"(,"uri":")" + uri + R"("}],
"bufferViews":[{"buffer":0,"byteOffset":0,"byteLength":)" +
         std::to_string(vertex_bytes) + R"(},
  {"buffer":0,"byteOffset":)" +
         std::to_string(vertex_bytes) + R"(,"byteLength":)" +
         std::to_string(bytes.size() - vertex_bytes) + R"(}],
"accessors":[{"bufferView":0,"componentType":5126,"count":)" +
         std::to_string(soup.points.size()) + R"(,"type":"VEC3","min":[)" + num(box.min.x) + "," +
         num(box.min.y) + "," + num(box.min.z) + "],\"max\":[" + num(box.max.x) + "," +
         num(box.max.y) + "," + num(box.max.z) + R"(]},
  {"bufferView":1,"componentType":5125,"count":)" +
         std::to_string(soup.triangles.size() * 3) + R"(,"type":"SCALAR"}]})";
}

// glTF's unit is the metre: a 10 × 20 × 30 mm box.
TriangleSoup metre_box() {
  return test::make_box({0, 0, 0}, {0.01, 0.02, 0.03});
}

Box3 box_of(const TriangleSoup& soup, std::size_t first_point, std::size_t count) {
  Box3 box;
  for (std::size_t i = first_point; i < first_point + count; ++i) box.extend(soup.points[i]);
  return box;
}

#define REQUIRE_ASSIMP() \
  if (!built_with_assimp()) GTEST_SKIP() << "built without assimp (libassimp-dev)"

TEST(Scene, GltfPlacesEveryInstanceUprightInMillimetres) {
  REQUIRE_ASSIMP();
  const TriangleSoup box = metre_box();
  // Three placements of one mesh: moved; mirrored in x and moved; under a parent that turns
  // it 90° about y (quaternion) and moves it.
  const std::string nodes = R"([{"mesh":0,"translation":[0.1,0,0]},
    {"mesh":0,"scale":[-1,1,1],"translation":[0.5,0,0]},
    {"children":[3],"rotation":[0,0.70710678,0,0.70710678],"translation":[0,1,0]},
    {"mesh":0}])";
  const MeshFile file = parse_mesh(gltf_of(box, nodes, "[0,1,2]"), "placed.gltf");
  EXPECT_EQ(file.format, MeshFormat::Scene);
  ASSERT_EQ(file.soup.triangles.size(), 3 * box.triangles.size());
  ASSERT_EQ(file.soup.points.size(), 3 * box.points.size());

  // glTF's +y is up: (x, y, z) in metres lands at (x, -z, y) in millimetres.
  const std::size_t n = box.points.size();
  const Box3 first = box_of(file.soup, 0, n);
  const Box3 expected{{100, -30, 0}, {110, 0, 20}};
  for (int k = 0; k < 3; ++k) {
    EXPECT_NEAR(first.min[k], expected.min[k], 1e-4) << k;
    EXPECT_NEAR(first.max[k], expected.max[k], 1e-4) << k;
  }
  const Box3 mirrored = box_of(file.soup, n, n);
  EXPECT_NEAR(mirrored.min.x, 490, 1e-4);
  EXPECT_NEAR(mirrored.max.x, 500, 1e-4);
  // The turned one: 90° about y maps z onto x, so its 30 mm side lies along x; lifted 1 m in
  // glTF's up, 1000 mm in z.
  const Box3 turned = box_of(file.soup, 2 * n, n);
  EXPECT_NEAR(turned.max.x - turned.min.x, 30, 1e-4);
  EXPECT_NEAR(turned.min.z, 1000, 1e-3);
  EXPECT_NEAR(turned.max.z, 1020, 1e-3);

  // Every placement is a closed solid facing out, the mirrored one too (its winding reversed).
  CheckOptions options;
  options.self_intersections = false;
  const MeshCheck facts = check_mesh(file.soup, options);
  EXPECT_TRUE(facts.valid()) << facts.border_edges << " border edges";
  ASSERT_TRUE(facts.volume.has_value());
  EXPECT_NEAR(*facts.volume, 3 * 6000.0, 3 * 6000.0 * 1e-5);
  EXPECT_TRUE(facts.outward.value_or(false));
  EXPECT_EQ(facts.components, 3u);
}

TEST(Scene, SideFilesAreReadOnlyFromTheScenesFolder) {
  REQUIRE_ASSIMP();
  const fs::path dir = test::scratch_dir() / "scene-side-files";
  fs::remove_all(dir);
  fs::create_directories(dir / "inner");
  const TriangleSoup box = metre_box();
  test::write_file(dir / "box.bin", buffer_of(box));
  const std::string nodes = R"([{"mesh":0}])";
  test::write_file(dir / "beside.gltf", gltf_of(box, nodes, "[0]", "box.bin"));
  test::write_file(dir / "inner" / "climbs.gltf", gltf_of(box, nodes, "[0]", "../box.bin"));

  EXPECT_EQ(read_mesh(dir / "beside.gltf").triangles.size(), box.triangles.size());
  try {
    read_mesh(dir / "inner" / "climbs.gltf");
    ADD_FAILURE() << "a buffer outside the scene's folder was read";
  } catch (const ParseError& e) {
    EXPECT_NE(std::string(e.what()).find("outside the scene's folder"), std::string::npos)
        << e.what();
  }
  // From memory there is no folder: nothing beside it is read.
  EXPECT_THROW(parse_mesh(test::read_file(dir / "beside.gltf"), "beside.gltf"), ParseError);
}

TEST(Scene, AFlattenedSceneIsHeldToTheSizeLimit) {
  REQUIRE_ASSIMP();
  std::string nodes = "[", roots = "[";
  for (int i = 0; i < 400; ++i) {
    nodes +=
        std::string(i ? "," : "") + R"({"mesh":0,"translation":[)" + std::to_string(i) + ",0,0]}";
    roots += (i ? "," : "") + std::to_string(i);
  }
  const std::string text = gltf_of(metre_box(), nodes + "]", roots + "]");
  ReadOptions options;
  EXPECT_EQ(parse_mesh(text, "many.gltf", options).soup.triangles.size(), 400u * 12);
  // 4,800 triangles are 240,000 bytes as binary STL: more than a limit of 100,000.
  options.max_bytes = 100000;
  ASSERT_LT(text.size(), options.max_bytes);
  try {
    parse_mesh(text, "many.gltf", options);
    ADD_FAILURE() << "the flattened scene passed the limit";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("4800 triangles in 400 placed meshes"), std::string::npos)
        << e.what();
  }
}

TEST(Scene, WritingASceneIsRefused) {
  const fs::path target = test::scratch_dir() / "out.glb";
  fs::remove(target);
  EXPECT_THROW(write_mesh(target, test::make_box({0, 0, 0}, {1, 1, 1})), InputError);
  EXPECT_FALSE(fs::exists(target));
}

// ---- assimp-testmodels ---------------------------------------------------------------------

fs::path model(const std::string& relative) {
  return fs::path(TPMSFILL_ASSIMP_MODELS) / relative;
}

#define REQUIRE_MODELS() \
  REQUIRE_ASSIMP();      \
  if (!fs::is_directory(TPMSFILL_ASSIMP_MODELS)) GTEST_SKIP() << "assimp-testmodels missing"

TEST(SceneRealFiles, TheCesiumBoxIsOneCubicMetreAsGltfGlbAndEmbedded) {
  REQUIRE_MODELS();
  for (const char* name :
       {"glTF2/BoxTextured-glTF/BoxTextured.gltf", "glTF2/BoxTextured-glTF-Binary/BoxTextured.glb",
        "glTF2/BoxTextured-glTF-Embedded/BoxTextured.gltf"}) {
    const MeshCheck facts = check_mesh(read_mesh(model(name)));
    EXPECT_TRUE(facts.valid()) << name;
    ASSERT_TRUE(facts.volume.has_value()) << name;
    EXPECT_NEAR(*facts.volume, 1e9, 1) << name;  // a 1 m cube in mm³
    EXPECT_NEAR(facts.bbox.max.z - facts.bbox.min.z, 1000, 1e-3) << name;
  }
}

TEST(SceneRealFiles, TheColladaDuckIsOneClosedShellWhetherZippedOrNot) {
  REQUIRE_MODELS();
  CheckOptions options;
  options.self_intersections = false;
  const MeshFile dae = read_mesh_file(model("Collada/duck.dae"));
  const MeshFile zae = read_mesh_file(model("Collada/duck.zae"));
  const MeshCheck facts = check_mesh(dae.soup, options);
  EXPECT_EQ(facts.border_edges, 0u);
  EXPECT_EQ(facts.non_manifold_edges, 0u);
  EXPECT_EQ(facts.components, 1u);
  EXPECT_EQ(facts.genus.value_or(-1), 0);
  EXPECT_TRUE(facts.outward.value_or(false));
  // Its file says centimetres, Y up: about 1.6 m long, standing on its feet (the lowest points
  // are the underside, below the head's top by more than the body's width).
  EXPECT_GT(facts.bbox.max.x - facts.bbox.min.x, 1500);
  EXPECT_LT(facts.bbox.max.x - facts.bbox.min.x, 1800);
  EXPECT_EQ(zae.soup.triangles.size(), dae.soup.triangles.size());
  EXPECT_EQ(check_mesh(zae.soup, options).volume, facts.volume);
}

TEST(SceneRealFiles, FbxPlacementsKeepTheirSolidsFacingOut) {
  REQUIRE_MODELS();
  for (const char* name :
       {"FBX/box.fbx", "FBX/cubes_with_mirroring_and_pivot.fbx", "FBX/embedded_ascii/box.FBX"}) {
    const MeshCheck facts = check_mesh(read_mesh(model(name)));
    EXPECT_TRUE(facts.valid()) << name;
    EXPECT_TRUE(facts.outward.value_or(false)) << name;
    EXPECT_GT(facts.volume.value_or(0), 0) << name;
  }
}

TEST(SceneRealFiles, BrokenScenesAreRefusedWithTheirReason) {
  REQUIRE_MODELS();
  auto reason = [](const char* name) -> std::string {
    try {
      read_mesh(model(name));
    } catch (const ParseError& e) {
      return e.what();
    }
    return "(read)";
  };
  EXPECT_NE(
      reason("glTF2/BoxWithInfinites-glTF-Binary/BoxWithInfinites.glb").find("not a finite number"),
      std::string::npos);
  EXPECT_NE(reason("glTF2/RecursiveNodes/RecursiveNodes.gltf").find("recursive"),
            std::string::npos);
  EXPECT_NE(reason("glTF2/MissingBin/BoxTextured.gltf").find("BoxTextured0.bin"),
            std::string::npos);
}

}  // namespace
}  // namespace tpmsfill

namespace tpmsfill {
namespace {

// Every file assimp-testmodels ships (its "invalid" folder included) is read or refused with one
// of our errors: nothing escapes as another exception, nothing crashes, nothing hangs.
TEST(SceneRealFiles, EveryFileOfTheTestModelsReadsOrIsRefusedWithOurError) {
  REQUIRE_MODELS();
  int read = 0, refused = 0, scenes = 0;
  for (const auto& entry : fs::recursive_directory_iterator(TPMSFILL_ASSIMP_MODELS)) {
    if (!entry.is_regular_file()) continue;
    try {
      const MeshFile file = read_mesh_file(entry.path());
      EXPECT_GE(file.soup.triangles.size(), 1u) << entry.path();
      for (const Vec3& p : file.soup.points)
        ASSERT_TRUE(std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z)) << entry.path();
      ++read;
      scenes += file.format == MeshFormat::Scene;
    } catch (const Error& e) {
      EXPECT_EQ(std::string(e.what()).find('\n'), std::string::npos) << e.what();
      ++refused;
    }
  }
  std::printf("assimp-testmodels: %d read (%d as scenes), %d refused\n", read, scenes, refused);
  EXPECT_GE(scenes, 100);  // glTF, COLLADA, FBX, 3DS, Blender, ... (5.2.5 ships about 700 files)
}

}  // namespace
}  // namespace tpmsfill
