// The whole pipeline: fill() on meshes made in code and on Debian's femur, judged by the
// geometric truths the issue names (porosity, volume, distance to the input surface) and by
// the independent checker (check_mesh).
#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <tpmsfill/check.hpp>
#include <tpmsfill/error.hpp>
#include <tpmsfill/fill.hpp>
#include <tpmsfill/io.hpp>

#include "test_util.hpp"

using namespace tpmsfill;

namespace {

FillOptions options(double voxel, TpmsType type = TpmsType::Gyroid) {
  FillOptions o;
  o.grid.voxel_size = voxel;
  o.design.type = type;
  o.design.cell = {2, 2, 2};
  return o;
}

// The independent check: CGAL PMP on the soup, bit-identical points merged.
void expect_printable(const TriangleSoup& mesh) {
  const MeshCheck c = check_mesh(mesh);
  EXPECT_TRUE(c.valid()) << (c.problems().empty() ? std::string("?") : c.problems().front());
  EXPECT_EQ(c.duplicate_points, 0u);
  EXPECT_EQ(c.self_intersecting_pairs.value_or(1), 0u);
}

TriangleSoup moved(TriangleSoup mesh, Vec3 by) {
  for (Vec3& p : mesh.points) p = p + by;
  return mesh;
}

}  // namespace

// The proof and the full search (the oracle) on fills of every kind of part and placement: the
// same mesh and the same verdict, figure for figure.
TEST(FillE2E, ProofAndFullSearchAgree) {
  struct Part {
    const char* name;
    TriangleSoup mesh;
  };
  const std::vector<Part> parts = {
      {"box at the origin", test::make_box({0, 0, 0}, {12, 9, 7})},
      {"box on a bed far out", test::make_box({250, 180, 40}, {262, 189, 47})},
      {"sphere", test::make_sphere({3, -2, 1}, 6, 3)},
      {"torus far out", moved(test::make_torus(7, 2.5, 48, 24), {-310, 95, 12})},
  };
  for (const Part& part : parts)
    for (const double voxel : {0.25, 0.4}) {
      SCOPED_TRACE(std::string(part.name) + " at voxel " + std::to_string(voxel));
      FillOptions o = options(voxel);
      o.keep_islands = voxel > 0.3;  // islands dropped and kept
      const FillResult proved = fill(part.mesh, o);
      o.validation = FillOptions::Validation::Full;
      const FillResult searched = fill(part.mesh, o);
      const MeshValidity &a = proved.report.validation, &b = searched.report.validation;
      EXPECT_EQ(a.validated_by, ValidatedBy::Construction);
      EXPECT_EQ(b.validated_by, ValidatedBy::Search);
      EXPECT_TRUE(b.searched_by_cells);
      EXPECT_TRUE(proved.mesh.points == searched.mesh.points);
      EXPECT_TRUE(proved.mesh.triangles == searched.mesh.triangles);
      EXPECT_TRUE(a.valid());
      EXPECT_EQ(a.valid(), b.valid());
      EXPECT_EQ(a.problems(), b.problems());
      EXPECT_EQ(a.triangles, b.triangles);
      EXPECT_EQ(a.vertices, b.vertices);
      EXPECT_EQ(a.components, b.components);
      EXPECT_EQ(a.volume, b.volume);
      EXPECT_EQ(a.area, b.area);
      EXPECT_EQ(a.outward, b.outward);
      EXPECT_EQ(a.self_intersecting_pairs, b.self_intersecting_pairs);
      EXPECT_EQ(a.border_edges + a.non_manifold_edges + a.non_manifold_vertices +
                    a.inconsistent_edges + a.degenerate_triangles + a.duplicate_points,
                b.border_edges + b.non_manifold_edges + b.non_manifold_vertices +
                    b.inconsistent_edges + b.degenerate_triangles + b.duplicate_points);
      expect_printable(proved.mesh);
    }
}

TEST(FillE2E, GyroidInACubeIsHalfSolid) {
  const TriangleSoup cube = test::make_box({0, 0, 0}, {20, 20, 20});
  const FillResult r = fill(cube, options(0.2));
  EXPECT_TRUE(r.report.validation.valid());
  // The whole grid held: marching cubes' construction proves the float-rounded output.
  EXPECT_EQ(r.report.validation.validated_by, ValidatedBy::Construction);
  EXPECT_NEAR(r.report.model_volume, 8000.0, 1e-6);  // faces on grid planes: exact spans
  EXPECT_NEAR(r.report.porosity(), 0.5, 0.01);
  EXPECT_NEAR(r.report.unclipped_porosity, 0.5, 0.005);
  EXPECT_EQ(r.report.components(), 1u);
  expect_printable(r.mesh);
}

TEST(FillE2E, SphereLatticeVolumeMatchesPorosity) {
  const TriangleSoup sphere = test::make_sphere({0, 0, 0}, 10.0, 5);
  for (TpmsType type : {TpmsType::Gyroid, TpmsType::Primitive, TpmsType::Diamond}) {
    const FillResult r = fill(sphere, options(0.2, type));
    const double polyhedron = test::signed_volume(sphere);
    EXPECT_NEAR(r.report.model_volume, polyhedron, 0.002 * polyhedron);
    const double expected = (1.0 - r.report.unclipped_porosity) * 4.0 / 3.0 * M_PI * 1000.0;
    EXPECT_NEAR(r.report.lattice_volume(), expected, 0.02 * expected) << tpms_type_name(type);
    EXPECT_NEAR(r.report.porosity(), r.report.unclipped_porosity, 0.02) << tpms_type_name(type);
    // The outer boundary lies within one voxel of the input surface.
    double reach = 0;
    for (const Vec3& p : r.mesh.points) {
      EXPECT_LE(norm(p), 10.0 + 0.2);
      reach = std::max(reach, norm(p));
    }
    EXPECT_GE(reach, 10.0 - 0.2 - 0.1);  // the tessellation is up to 0.1 mm inside the sphere
    expect_printable(r.mesh);
  }
}

TEST(FillE2E, SheetLatticeIsValidAndAsThickAsAsked) {
  const TriangleSoup cube = test::make_box({0, 0, 0}, {10, 10, 10});
  FillOptions o = options(0.1);
  o.design.style = TpmsStyle::Sheet;
  o.design.thickness = 0.4;
  const FillResult r = fill(cube, o);
  // A thin sheet's solid fraction is about area·t: 3.09·0.4/2 ≈ 0.62 of the cube, less the
  // curvature terms; the unclipped sample says what to expect.
  EXPECT_NEAR(1 - r.report.porosity(), 1 - r.report.unclipped_porosity, 0.02);
  expect_printable(r.mesh);
}

TEST(FillE2E, BandAndFullFieldAgree) {
  const TriangleSoup torus = test::make_torus(8, 3, 96, 48);
  FillOptions o = options(0.25);
  const FillResult band = fill(torus, o);
  o.full_field = true;
  const FillResult full = fill(torus, o);
  EXPECT_EQ(full.report.distance_queries, full.report.samples);
  EXPECT_GT(full.report.distance_queries, 4 * band.report.distance_queries);  // grows as 1/a
  EXPECT_NEAR(band.report.lattice_volume(), full.report.lattice_volume(),
              0.005 * full.report.lattice_volume());
  EXPECT_EQ(band.report.triangles(), full.report.triangles());  // same signs at every node
}

TEST(FillE2E, OrientationAndWeldingOfTheInputDoNotMatter) {
  const TriangleSoup sphere = test::make_sphere({1, 2, 3}, 6.0, 4);
  const FillResult a = fill(sphere, options(0.25));
  const FillResult b = fill(test::unshare_points(test::flip(sphere)), options(0.25));
  EXPECT_EQ(a.mesh.points, b.mesh.points);
  EXPECT_EQ(a.mesh.triangles, b.mesh.triangles);
}

TEST(FillE2E, SameBytesForAnyThreadCount) {
  const TriangleSoup torus = test::make_torus(6, 2.5, 64, 32);
  FillResult one, many;
  {
    tbb::global_control c(tbb::global_control::max_allowed_parallelism, 1);
    one = fill(torus, options(0.2));
  }
  {
    tbb::global_control c(tbb::global_control::max_allowed_parallelism, 4);
    many = fill(torus, options(0.2));
  }
  EXPECT_EQ(one.mesh.points, many.mesh.points);
  EXPECT_EQ(one.mesh.triangles, many.mesh.triangles);
  EXPECT_EQ(one.report.lattice_volume(), many.report.lattice_volume());
}

TEST(FillE2E, IslandsAreRemovedPerPartOfTheModel) {
  // Two disjoint balls: each keeps its own main body, fragments cut off by the surface go.
  const TriangleSoup two =
      test::concat(test::make_sphere({0, 0, 0}, 4.0, 4), test::make_sphere({12, 0, 0}, 3.0, 4));
  FillOptions o = options(0.2);
  const FillResult kept = [&] {
    FillOptions k = o;
    k.keep_islands = true;
    return fill(two, k);
  }();
  const FillResult cleaned = fill(two, o);
  EXPECT_EQ(cleaned.report.components(), 2u);
  EXPECT_EQ(kept.report.components(), cleaned.report.components() + cleaned.report.islands_removed);
  EXPECT_NEAR(kept.report.lattice_volume(),
              cleaned.report.lattice_volume() + cleaned.report.islands_volume, 1e-6);
  for (const Vec3& p : cleaned.mesh.points)
    EXPECT_TRUE(norm(p) <= 4.2 || norm(p - Vec3{12, 0, 0}) <= 3.2);
  expect_printable(cleaned.mesh);
}

TEST(FillE2E, OverTheMemoryBudgetIsRefusedWithAVoxelSizeThatFits) {
  const TriangleSoup cube = test::make_box({0, 0, 0}, {50, 50, 50});
  FillOptions o = options(0.01);
  o.memory_budget = 256ull << 20;
  try {
    fill(cube, o);
    FAIL() << "no ResourceError";
  } catch (const ResourceError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("voxel size of"), std::string::npos) << what;
    // The suggested voxel size does fit.
    const double suggested = std::stod(what.substr(what.find("voxel size of") + 14));
    o.grid.voxel_size = suggested;
    EXPECT_LE(estimate_fill_memory(cube, o), o.memory_budget);
  }
}

TEST(FillE2E, BadOptionsThrowInputError) {
  const TriangleSoup cube = test::make_box({0, 0, 0}, {5, 5, 5});
  FillOptions o = options(0.1);
  o.design.cell = {0, 1, 1};
  EXPECT_THROW(fill(cube, o), InputError);
  o = options(-1);
  EXPECT_THROW(fill(cube, o), InputError);
  EXPECT_THROW(fill(TriangleSoup{}, options(0.1)), InputError);
}

TEST(FillE2E, DebianFemurIsFilledAndPrintable) {
  const std::filesystem::path femur = std::filesystem::path(TPMSFILL_CGAL_MESHES) / "femur.off";
  if (!std::filesystem::exists(femur)) GTEST_SKIP() << "libcgal-demo is not installed";
  TriangleSoup soup = read_mesh(femur);
  // Scaled so the longest side is 35 mm, as in the benchmark, at a coarser voxel.
  const Box3 box = bounding_box(soup);
  const Vec3 size = box.size();
  const double scale = 35.0 / std::max({size.x, size.y, size.z});
  for (Vec3& p : soup.points) p = scale * (p - box.min);
  const FillResult r = fill(soup, options(0.2));
  EXPECT_NEAR(r.report.model_volume, test::signed_volume(soup), 0.01 * r.report.model_volume);
  EXPECT_NEAR(r.report.porosity(), r.report.unclipped_porosity, 0.02);
  EXPECT_EQ(r.report.odd_rows, 0u);
  expect_printable(r.mesh);
}
