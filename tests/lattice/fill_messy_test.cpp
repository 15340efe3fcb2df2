// fill() on broken input: meshes made in code with each defect, and every mesh Debian's
// libcgal-demo ships. The output must be a validated closed 2-manifold, or the job must be
// refused with a tpmsfill::Error (one sentence); nothing may crash or fail validation.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <tpmsfill/check.hpp>
#include <tpmsfill/error.hpp>
#include <tpmsfill/fill.hpp>
#include <tpmsfill/io.hpp>

#include "test_util.hpp"

using namespace tpmsfill;
namespace fs = std::filesystem;

namespace {

FillOptions options_for(const TriangleSoup& soup, double cells_across, double voxels_per_cell) {
  const Vec3 size = bounding_box(soup).size();
  const double longest = std::max({size.x, size.y, size.z});
  FillOptions o;
  const double cell = longest / cells_across;
  o.design.cell = {cell, cell, cell};
  o.grid.voxel_size = cell / voxels_per_cell;
  return o;
}

void expect_printable(const TriangleSoup& mesh) {
  const MeshCheck c = check_mesh(mesh);
  EXPECT_TRUE(c.valid()) << (c.problems().empty() ? std::string("?") : c.problems().front());
}

}  // namespace

TEST(FillMessy, SphereWithHolesFlipsAndUnweldedPointsIsFilledLikeTheSphere) {
  const TriangleSoup sphere = test::make_sphere({0, 0, 0}, 10.0, 4);
  TriangleSoup broken = test::unshare_points(test::without_triangles(sphere, [](const Vec3& c) {
    return c.x > 9.7 || c.z < -9.7;  // two holes about 5 mm across
  }));
  for (long t : {1L, 100L, 2000L}) broken = test::flip(broken, t);
  FillOptions o;
  o.grid.voxel_size = 0.25;
  const FillResult clean = fill(sphere, o);
  const FillResult r = fill(broken, o);
  EXPECT_EQ(r.report.inside_rule, "winding");
  EXPECT_EQ(r.report.clean.holes, 2u);
  EXPECT_EQ(r.report.clean.flipped_triangles, 3u);
  // The holes' caps are flat where the sphere bulges: about 2 x 1.2 mm^3 less model.
  EXPECT_NEAR(r.report.model_volume, clean.report.model_volume, 0.005 * clean.report.model_volume);
  EXPECT_NEAR(r.report.porosity(), clean.report.porosity(), 0.01);
  expect_printable(r.mesh);
  // Parity on the same input reports its holes and loses the rows through them.
  o.inside = InsideRule::Parity;
  const FillResult parity = fill(broken, o);
  EXPECT_GT(parity.report.odd_rows, 0u);
  EXPECT_FALSE(parity.report.warnings.empty());
}

TEST(FillMessy, OverlappingShellsAreFilledAsTheirUnion) {
  const TriangleSoup a = test::make_box({0, 0, 0}, {10, 10, 10});
  const TriangleSoup b = test::make_box({5, 5, 5}, {15, 15, 15});
  FillOptions o;
  o.grid.voxel_size = 0.25;
  const FillResult r = fill(test::concat(a, b), o);
  EXPECT_NEAR(r.report.model_volume, 2000.0 - 125.0, 1e-6);  // union, faces on grid planes
  EXPECT_GT(r.report.overlap_rows, 0u);
  EXPECT_NEAR(r.report.porosity(), 0.5, 0.02);
  expect_printable(r.mesh);
}

TEST(FillMessy, AnOpenSheetEnclosesNoVolume) {
  TriangleSoup sheet;
  // Flat: a folded sheet encloses a thin sliver on its concave side, by the winding number.
  auto z = [](double x, double y) { return 0.31 + 0.1234 * x + 0.0567 * y; };
  sheet.points = {{0, 0, z(0, 0)}, {10, 0, z(10, 0)}, {10, 10, z(10, 10)}, {0, 10, z(0, 10)}};
  sheet.triangles = {{0, 1, 2}, {0, 2, 3}};
  FillOptions o;
  o.grid.voxel_size = 0.25;
  try {
    fill(sheet, o);
    FAIL() << "an open sheet was filled";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("encloses no volume"), std::string::npos) << e.what();
  }
}

TEST(FillMessy, InsideOutTorusWithASlit) {
  const TriangleSoup torus = test::make_torus(10, 3, 48, 24);
  const TriangleSoup slit = test::flip(test::without_triangles(
      torus, [](const Vec3& c) { return c.x > 0 && std::fabs(std::atan2(c.y, c.x)) < 0.06; }));
  FillOptions o;
  o.grid.voxel_size = 0.25;
  const FillResult r = fill(slit, o);
  const FillResult ref = fill(torus, o);
  EXPECT_EQ(r.report.clean.holes, 2u);
  EXPECT_EQ(r.report.clean.reversed_pieces, 1u);
  EXPECT_NEAR(r.report.model_volume, ref.report.model_volume, 0.005 * ref.report.model_volume);
  expect_printable(r.mesh);
}

// Every mesh of libcgal-demo (up to 2 MB): filled into a valid mesh, or refused with a
// tpmsfill::Error that is not a failed validation.
TEST(FillMessy, EveryCgalDemoMeshIsFilledOrRefusedInOneSentence) {
  const fs::path dir = TPMSFILL_CGAL_MESHES;
  if (!fs::exists(dir)) GTEST_SKIP() << dir << " is missing: install libcgal-demo";
  const std::vector<fs::path> files = test::files_in(dir, 2'000'000);
  std::size_t filled = 0, refused = 0;
  for (const fs::path& file : files) {
    SCOPED_TRACE(file.filename().string());
    TriangleSoup soup;
    try {
      soup = read_mesh(file);
    } catch (const Error&) {
      continue;  // unreadable files are the readers' tests' business
    }
    if (soup.triangles.empty()) continue;
    try {
      const FillResult r = fill(soup, options_for(soup, 6, 8));
      EXPECT_TRUE(r.report.validation.valid());
      ++filled;
    } catch (const ValidationError& e) {
      ADD_FAILURE() << e.what();
    } catch (const Error& e) {
      ++refused;
      const std::string what = e.what();
      EXPECT_EQ(what.find('\n'), std::string::npos) << what;
    }
  }
  EXPECT_GT(filled, 50u);
  std::printf("filled %zu, refused %zu of %zu files\n", filled, refused, files.size());
}
