// OpenVDB interop (src/io/vdb.cpp), judged by OpenVDB itself: a level set tpmsfill writes opens
// in OpenVDB's own file reader as a level set whose values are the distances to the mesh; a
// field tpmsfill writes as .vdb reads back the same; a level set OpenVDB writes is read as a
// signed field, and fills.
// GCC 12 reports a false -Wrestrict inside std::string concatenation here (GCC bug 105329).
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC diagnostic ignored "-Wrestrict"
#endif
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "test_util.hpp"
#include "tpmsfill/check.hpp"
#include "tpmsfill/error.hpp"
#include "tpmsfill/fill.hpp"
#include "tpmsfill/io.hpp"
#include "tpmsfill/io/volume.hpp"
#include "tpmsfill/scan/itdf.hpp"

#ifdef TPMSFILL_TEST_OPENVDB
#include <openvdb/io/File.h>
#include <openvdb/openvdb.h>
#include <openvdb/tools/LevelSetSphere.h>
#endif

namespace tpmsfill {
namespace {

namespace fs = std::filesystem;

TEST(Vdb, WithoutOpenVdbEveryUseIsRefusedWithASentence) {
  if (vdb_available()) GTEST_SKIP() << "this build has OpenVDB";
  const fs::path file = test::scratch_dir() / "nothing.vdb";
  EXPECT_THROW(write_level_set(file, test::make_box({0, 0, 0}, {1, 1, 1}), {.voxel = 0.1}),
               InputError);
  EXPECT_FALSE(fs::exists(file));
}

#ifdef TPMSFILL_TEST_OPENVDB

openvdb::FloatGrid::Ptr read_with_openvdb(const fs::path& path) {
  openvdb::initialize();
  openvdb::io::File file(path.string());
  file.open();
  const openvdb::GridPtrVecPtr grids = file.getGrids();
  file.close();
  EXPECT_EQ(grids->size(), 1u);
  return openvdb::gridPtrCast<openvdb::FloatGrid>(grids->front());
}

TEST(Vdb, ALevelSetWrittenHereOpensInOpenVdbAsTheMeshsDistance) {
  ASSERT_TRUE(vdb_available());
  const double r = 10, voxel = 0.5;
  const Vec3 c{150, -40, 7};  // off the origin: index space must not shift it
  const TriangleSoup sphere = test::make_sphere(c, r, 5);
  const fs::path path = test::scratch_dir() / "sphere-level-set.vdb";
  write_level_set(path, sphere, {.voxel = voxel, .half_width = 3});

  const openvdb::FloatGrid::Ptr grid = read_with_openvdb(path);
  ASSERT_TRUE(grid);
  EXPECT_EQ(grid->getGridClass(), openvdb::GRID_LEVEL_SET);
  EXPECT_EQ(grid->getName(), "surface");
  EXPECT_NEAR(grid->voxelSize()[0], voxel, 1e-12);
  EXPECT_NEAR(grid->background(), 3 * voxel, 1e-6);
  // Every active voxel holds the distance to the (faceted) sphere, negative inside: within a
  // voxel of the surface the exact one (to the facets' sag of the round sphere's), further out
  // OpenVDB's expansion of the band from there (within a quarter of a voxel); all in the band.
  const double sag = r * (1 - std::cos(M_PI / 5 / 16));  // 5 subdivisions: edges ~ 2πr/80
  std::size_t active = 0;
  double near = 0, far = 0;  // the largest errors within a voxel of the surface, and beyond
  for (auto v = grid->cbeginValueOn(); v; ++v) {
    const openvdb::Vec3d p = grid->indexToWorld(v.getCoord());
    const double exact = std::hypot(p.x() - c.x, p.y() - c.y, p.z() - c.z) - r;
    const double error = std::abs(*v - exact);
    (std::abs(exact) < voxel ? near : far) = std::max(std::abs(exact) < voxel ? near : far, error);
    EXPECT_LE(std::abs(*v), 3 * voxel + 1e-6);
    ++active;
  }
  EXPECT_LT(near, sag + 1e-3);
  EXPECT_LT(far, 0.25 * voxel);
  std::printf("distance error: %.4g mm within a voxel of the surface, %.4g mm beyond\n", near, far);
  // The band: about 6 voxels thick over the sphere's area.
  const double shell = 4 * M_PI * r * r * 6 * voxel / (voxel * voxel * voxel);
  EXPECT_GT(static_cast<double>(active), 0.8 * shell);
  EXPECT_LT(static_cast<double>(active), 1.2 * shell);
  // Deep inside, OpenVDB's inside value; far outside, its background.
  auto at = grid->getConstAccessor();
  EXPECT_LT(at.getValue(grid->transform().worldToIndexCellCentered({c.x, c.y, c.z})), 0);
  EXPECT_GT(at.getValue(grid->transform().worldToIndexCellCentered({c.x + 2 * r, c.y, c.z})), 0);
}

TEST(Vdb, AFieldWrittenAsVdbReadsBackAndOpenVdbSeesItsPlacement) {
  ScalarVolume v;
  v.dims = {13, 9, 7};
  v.spacing = {0.7, 0.7, 1.3};
  v.origin = {100, -50, 3};
  v.sign = FieldSign::Signed;
  for (int k = 0; k < v.dims[2]; ++k)
    for (int j = 0; j < v.dims[1]; ++j)
      for (int i = 0; i < v.dims[0]; ++i) v.values.push_back(std::sin(i + 2.0 * j) - 0.1 * k);
  const fs::path path = test::scratch_dir() / "field.vdb";
  write_volume(path, v);
  const VolumeFile back = read_volume_file(path);
  EXPECT_EQ(back.format, VolumeFormat::Vdb);
  EXPECT_EQ(back.volume.dims, v.dims);
  EXPECT_EQ(back.volume.sign, FieldSign::Signed);
  for (int a = 0; a < 3; ++a) {
    EXPECT_NEAR(back.volume.spacing[a], v.spacing[a], 1e-14);
    EXPECT_NEAR(back.volume.origin[a], v.origin[a], 1e-9);
  }
  ASSERT_EQ(back.volume.values.size(), v.values.size());
  for (std::size_t n = 0; n < v.values.size(); ++n)
    EXPECT_EQ(back.volume.values[n], static_cast<float>(v.values[n])) << n;

  const openvdb::FloatGrid::Ptr grid = read_with_openvdb(path);
  ASSERT_TRUE(grid);
  EXPECT_EQ(grid->activeVoxelCount(), static_cast<openvdb::Index64>(v.count()));
  const openvdb::Vec3d first = grid->indexToWorld(openvdb::Coord(0, 0, 0));
  EXPECT_NEAR(first.x(), 100, 1e-9);
  EXPECT_NEAR(first.z(), 3, 1e-9);
  EXPECT_NEAR(grid->voxelSize()[2], 1.3, 1e-12);
}

TEST(Vdb, ALevelSetFromOpenVdbIsASignedFieldAndFills) {
  openvdb::initialize();
  // OpenVDB's own sphere, written by its own file writer: radius 8 mm about (1, 2, 3).
  const float radius = 8, voxel = 0.5f;
  auto sphere = openvdb::tools::createLevelSetSphere<openvdb::FloatGrid>(
      radius, openvdb::Vec3f(1, 2, 3), voxel, 3.0f);
  sphere->setName("ball");
  const fs::path path = test::scratch_dir() / "openvdb-sphere.vdb";
  {
    openvdb::io::File file(path.string());
    file.write({sphere});
    file.close();
  }
  const VolumeFile read = read_volume_file(path);
  EXPECT_EQ(read.volume.sign, FieldSign::Signed);
  EXPECT_DOUBLE_EQ(read.volume.spacing[0], voxel);
  // The box of the active voxels: the sphere and its band (3 voxels) on each side.
  for (int a = 0; a < 3; ++a)
    EXPECT_NEAR(read.volume.dims[a] * voxel, 2 * (radius + 3 * voxel), 2 * voxel) << a;
  const double centre = sample_volume(read.volume, {1, 2, 3});
  EXPECT_LT(centre, 0);  // OpenVDB's inside value (−background): negative, as tpmsfill's

  // Fitted on reading and stretched over a 10 mm cube: a ball of radius 8 / 19 of the cube's
  // side, the box being the sphere and its band.
  FillOptions o = test::gyroid_options(5, 0.2);
  o.design.structure = read_structure(path).structure;
  const FillResult filled = fill(test::make_box({0, 0, 0}, {10, 10, 10}), o);
  const MeshCheck facts = check_mesh(filled.mesh);
  EXPECT_TRUE(facts.valid());
  const double box_side = read.volume.dims[0] * voxel;
  const double ball = 4.0 / 3 * M_PI * std::pow(radius / box_side * 10, 3);
  EXPECT_NEAR(facts.volume.value_or(0), ball, 0.1 * ball);
  EXPECT_EQ(facts.components, 1u);
}

TEST(Vdb, BrokenAndForeignVdbFilesAreRefusedWithTheirReason) {
  openvdb::initialize();
  const fs::path dir = test::scratch_dir();
  // Only an integer grid: nothing to read as a field, and the message says what it holds.
  auto ints = openvdb::Int32Grid::create(0);
  ints->setName("labels");
  ints->tree().setValue(openvdb::Coord(1, 2, 3), 7);
  {
    openvdb::io::File file((dir / "labels.vdb").string());
    file.write({ints});
    file.close();
  }
  try {
    read_volume_file(dir / "labels.vdb");
    ADD_FAILURE() << "an integer grid was read";
  } catch (const ParseError& e) {
    EXPECT_NE(std::string(e.what()).find("labels (int32)"), std::string::npos) << e.what();
  }
  // The magic and then nonsense: OpenVDB's reason, one line, no crash.
  const std::string good = test::read_file(dir / "labels.vdb");
  for (std::size_t cut : {8u, 16u, 40u, 200u}) {
    if (cut >= good.size()) continue;
    test::write_file(dir / "cut.vdb", good.substr(0, cut));
    EXPECT_THROW(read_volume_file(dir / "cut.vdb"), Error) << cut;
  }
  // Cut inside its metadata, OpenVDB's reader went on for 31 s reading past the end (a count
  // read from garbage); the end of the bytes stops it now, and says where.
  test::write_file(dir / "cut.vdb", good.substr(0, 200));
  try {
    read_volume_file(dir / "cut.vdb");
    ADD_FAILURE() << "a cut file was read";
  } catch (const ParseError& e) {
    EXPECT_NE(std::string(e.what()).find("byte 200: the file ends early"), std::string::npos)
        << e.what();
  }
  // A grid with no active voxel.
  auto empty = openvdb::FloatGrid::create(1.0f);
  {
    openvdb::io::File file((dir / "empty.vdb").string());
    file.write({empty});
    file.close();
  }
  EXPECT_THROW(read_volume_file(dir / "empty.vdb"), InputError);
}

#endif

}  // namespace
}  // namespace tpmsfill
