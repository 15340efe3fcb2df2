// check_mesh on real meshes that Debian ships (libcgal-demo's data, assimp-testmodels). The
// tests skip when the packages are absent; scripts/test.sh installs them.
#include <gtest/gtest.h>

#include <filesystem>
#include <tpmsfill/check.hpp>
#include <tpmsfill/error.hpp>
#include <tpmsfill/io.hpp>

#include "test_util.hpp"

using namespace tpmsfill;
namespace fs = std::filesystem;

namespace {

fs::path cgal_mesh(const std::string& name) {
  return fs::path(TPMSFILL_CGAL_MESHES) / name;
}

#define REQUIRE_FILE(path) \
  if (!fs::exists(path)) GTEST_SKIP() << (path) << " is missing: install libcgal-demo"

}  // namespace

TEST(RealMeshes, FemurIsAValidClosedManifold) {
  const fs::path femur = cgal_mesh("femur.off");
  REQUIRE_FILE(femur);
  const MeshCheck c = check_mesh(read_mesh(femur));
  EXPECT_TRUE(c.valid()) << testing::PrintToString(c.problems());
  EXPECT_EQ(c.triangles, 7798u);
  EXPECT_EQ(c.vertices, 3897u);
  EXPECT_EQ(c.components, 1u);
  ASSERT_TRUE(c.genus.has_value());
  // Euler on a closed triangle mesh (E = 3F/2): F = 2V - 4 + 4g.
  EXPECT_EQ(static_cast<std::int64_t>(c.triangles),
            2 * static_cast<std::int64_t>(c.vertices) - 4 + 4 * *c.genus);
  ASSERT_TRUE(c.volume.has_value());
  EXPECT_GT(*c.volume, 0.0);
}

TEST(RealMeshes, ElephantWithHolesReportsItsHoles) {
  const fs::path elephant = cgal_mesh("elephant-with-holes.off");
  REQUIRE_FILE(elephant);
  const MeshCheck c = check_mesh(read_mesh(elephant));
  EXPECT_FALSE(c.valid());
  EXPECT_FALSE(c.closed());
  ASSERT_TRUE(c.holes.has_value());
  EXPECT_GE(*c.holes, 2u);
  EXPECT_GE(c.border_edges, 3 * *c.holes);  // every hole is a cycle of at least three edges
  EXPECT_FALSE(c.border_edge_examples.empty());
  EXPECT_FALSE(c.volume.has_value());
}

TEST(RealMeshes, SameSpiderInThreeEncodingsGivesTheSameFacts) {
  const fs::path models = TPMSFILL_ASSIMP_MODELS;
  if (!fs::exists(models / "STL/Spider_ascii.stl")) GTEST_SKIP() << "install assimp-testmodels";
  const MeshCheck ascii = check_mesh(read_mesh(models / "STL/Spider_ascii.stl"));
  const MeshCheck binary = check_mesh(read_mesh(models / "STL/Spider_binary.stl"));
  const MeshCheck obj = check_mesh(read_mesh(models / "OBJ/spider.obj"));
  for (const MeshCheck* c : {&ascii, &binary, &obj}) {
    EXPECT_EQ(c->triangles, 1368u);
    EXPECT_FALSE(c->valid());
    EXPECT_GT(c->border_edges, 0u);
    EXPECT_GT(c->degenerate_triangles, 0u);
  }
  EXPECT_EQ(ascii.holes, binary.holes);
  EXPECT_EQ(ascii.border_edges, binary.border_edges);
  EXPECT_EQ(ascii.components, binary.components);
  EXPECT_EQ(ascii.self_intersecting_pairs, binary.self_intersecting_pairs);
}

// Every mesh CGAL ships: reading either succeeds or throws a tpmsfill::Error, and check_mesh's
// facts are consistent with each other. Nothing may crash or throw anything else.
TEST(RealMeshes, EveryCgalDemoMeshReadsAndChecksConsistently) {
  const fs::path dir = TPMSFILL_CGAL_MESHES;
  if (!fs::exists(dir)) GTEST_SKIP() << dir << " is missing: install libcgal-demo";
  std::size_t read = 0;
  const std::vector<fs::path> files = test::files_in(dir, 4'000'000);
  for (const fs::path& file : files) {
    SCOPED_TRACE(file.filename().string());
    TriangleSoup soup;
    try {
      soup = read_mesh(file);
    } catch (const Error&) {
      continue;
    }
    ++read;
    CheckOptions options;
    options.self_intersections = soup.triangles.size() < 200'000;
    const MeshCheck c = check_mesh(soup, options);
    EXPECT_EQ(c.triangles, soup.triangles.size());
    EXPECT_LE(c.vertices, c.points);
    EXPECT_EQ(c.closed(), c.border_edges == 0);
    if (c.border_edges > 0) {
      EXPECT_GT(c.holes, 0u);
    }
    if (c.holes > 0 && c.border_edges == 0) {  // holes opened by splitting non-manifold edges
      EXPECT_GT(c.non_manifold_edges + c.non_manifold_vertices, 0u);
    }
    EXPECT_EQ(c.valid(), c.problems().empty());
    if (c.volume) {
      EXPECT_TRUE(c.closed() && c.manifold() && c.consistently_oriented());
    }
    if (c.valid()) {
      EXPECT_GT(c.volume.value_or(0.0), 0.0);
    }
  }
  EXPECT_GT(read, files.size() * 9 / 10) << "most CGAL demo meshes should read";
}
