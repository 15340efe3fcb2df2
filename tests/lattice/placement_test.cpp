// Wherever a part sits: the written file, read back as any reader would, is a valid closed
// 2-manifold, or the job is refused before any work with a sentence that names the limit.
// Printer beds are 200-400 mm wide and CAD keeps assembly positions, so parts at 150 mm or
// 1000 mm are the ordinary case; at those coordinates a float holds a value only every
// 1.5e-5 to 6.1e-5 mm, and marching-cubes vertices near grid nodes used to round onto them.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <tpmsfill/check.hpp>
#include <tpmsfill/error.hpp>
#include <tpmsfill/fill.hpp>
#include <tpmsfill/io.hpp>
#include <tpmsfill/sampling/marching_cubes.hpp>

#include "test_util.hpp"

using namespace tpmsfill;

namespace {

constexpr double kOffsets[] = {0, 100, 150, 1000, -1000, 1e4, 1e5};
constexpr double kVoxels[] = {0.2, 0.1, 0.05, 0.02, 0.01, 0.005};
constexpr const char* kFormats[] = {"stl", "obj", "ply", "off", "3mf"};

// The finest voxel a file holds at |x| <= magnitude, written out here rather than taken from
// the library: four steps of the format's coordinates (a float's, or 3MF's micrometre).
double finest_voxel(const std::string& format, double magnitude) {
  if (format != "stl" && format != "3mf") return 0;
  const float f = static_cast<float>(magnitude);
  double step = static_cast<double>(std::nextafter(f, std::numeric_limits<float>::infinity())) -
                static_cast<double>(f);
  if (format == "3mf") step = std::max(step, 1e-3);
  return 4 * step;
}

struct Case {
  Vec3 offset;
  double voxel;
  std::string format;
  int variant;  // picks type, style, skin, grading and slabs, so every combination is met
};

// A sphere of 2.6 cells, cells of 10 voxels: about 30³ nodes whatever the voxel.
FillOptions options_for(const Case& c, Box3& box) {
  const double cell = 10 * c.voxel, radius = 1.3 * cell;
  box = {c.offset - Vec3{radius, radius, radius}, c.offset + Vec3{radius, radius, radius}};
  FillOptions o;
  o.grid.voxel_size = c.voxel;
  o.design.type = test::kAllTpmsTypes[c.variant % 8];
  o.design.style = (c.variant / 8) % 2 ? TpmsStyle::Sheet : TpmsStyle::Network;
  o.design.cell = {cell, cell, cell};
  o.design.porosity = 0.6;
  o.design.thickness = 0.1 * cell;  // what a porosity grading starts from
  if (c.variant % 3 == 1) o.skin = 2 * c.voxel;
  if (c.variant % 5 == 2) {
    Grading g;
    g.what = Graded::Porosity;
    g.ramp.shape = RampShape::Linear;
    g.ramp.start = 0.5;
    g.ramp.end = 0.7;
    o.design.grading.push_back(g);
    o.design.porosity.reset();
  }
  if (c.variant % 4 == 3) o.slab_planes = 7;  // slab by slab, streamed to the file
  o.rounding = rounding_for(format_from_extension("x." + c.format));
  return o;
}

class Placement : public ::testing::TestWithParam<int> {};

// One axis and one offset per instance; every voxel and format, with the design rotating
// through types, styles, skin, grading and the slab path.
TEST_P(Placement, WrittenFileIsValidOrRefusedBeforeWork) {
  const int axis = GetParam() / 7;
  const double offset = kOffsets[GetParam() % 7];
  const TriangleSoup unit = test::make_sphere({0, 0, 0}, 1, 3);
  const auto dir = test::scratch_dir();
  int variant = GetParam() * 11, filled = 0;
  for (const double voxel : kVoxels)
    for (const char* format : kFormats) {
      Case c{{0, 0, 0}, voxel, format, variant++};
      (axis == 0 ? c.offset.x : axis == 1 ? c.offset.y : c.offset.z) = offset;
      Box3 box;
      const FillOptions o = options_for(c, box);
      TriangleSoup model = unit;
      const double radius = 0.5 * box.size().x;
      for (Vec3& p : model.points) p = c.offset + radius * p;
      const auto path = dir / ("lattice." + c.format);
      const std::string label = "offset " + std::to_string(offset) + " on axis " +
                                std::to_string(axis) + ", voxel " + std::to_string(voxel) + ", " +
                                c.format + ", variant " + std::to_string(c.variant);
      // The grid reaches 3 voxels past the sphere (padding 2, rounded up).
      const double reach = std::fabs(offset) + radius + 4 * voxel;
      const bool holdable = voxel >= finest_voxel(c.format, reach);
      try {
        fill_to_file(model, o, path);
      } catch (const InputError& e) {
        EXPECT_FALSE(holdable) << label << ": refused although the file holds it: " << e.what();
        EXPECT_NE(std::string(e.what()).find("hold doubles"), std::string::npos) << e.what();
        EXPECT_FALSE(std::filesystem::exists(path)) << label;
        continue;
      }
      EXPECT_TRUE(holdable) << label << ": filled although the file cannot hold it";
      const MeshCheck check = check_mesh(read_mesh(path));
      std::string problems;
      for (const std::string& p : check.problems()) problems += p + "; ";
      EXPECT_TRUE(check.valid()) << label << ": " << problems;
      EXPECT_GT(check.triangles, 100u) << label;
      ++filled;
      std::filesystem::remove(path);
    }
  EXPECT_GE(filled, 20) << "most cases must fill";
  EXPECT_EQ(test::files_in(dir, std::numeric_limits<std::uintmax_t>::max()).size(), 0u)
      << "temporaries left behind";
}

INSTANTIATE_TEST_SUITE_P(OffsetsOnEachAxis, Placement, ::testing::Range(0, 21));

// Marching cubes alone, with a field that crosses zero right next to nodes (the worst case for
// rounding): every point is as the file holds it, and strictly inside its rounded edge.
TEST(PlacementMarchingCubes, VerticesNearNodesStayInsideTheirEdges) {
  for (const double offset : {150.0, 1000.0, -1000.0, 1e4})
    for (const CoordinateRounding rounding :
         {CoordinateRounding::Float, CoordinateRounding::ThreeMf}) {
      Grid grid;
      grid.spacing = 0.05;
      grid.origin = {offset, offset + 0.01, -offset};
      grid.dims = {24, 20, 22};
      Field f = test::wavy_field(grid);
      // Push each value near zero towards its node: crossings then sit within 1e-4 of nodes.
      for (float& v : f.values)
        if (std::fabs(v) < 0.5f) v = v < 0 ? -1e-6f : 1e-6f + 1e-5f * std::fabs(v);
      const TriangleSoup mesh = marching_cubes(f, {.rounding = rounding});
      ASSERT_GT(mesh.triangles.size(), 100u);
      for (const Vec3& p : mesh.points) ASSERT_EQ(round_coordinates(rounding, p), p);
      const MeshCheck check = check_mesh(mesh);
      std::string problems;
      for (const std::string& p : check.problems()) problems += p + "; ";
      EXPECT_TRUE(check.valid()) << "offset " << offset << ": " << problems;
    }
}

// A grid finer than the format holds where it sits is refused before any work.
TEST(PlacementMarchingCubes, TooFineForTheFormatIsRefused) {
  Grid grid;
  grid.spacing = 0.005;
  grid.origin = {1e5, 0, 0};
  grid.dims = {4, 4, 4};
  const Field f = test::wavy_field(grid);
  EXPECT_THROW(marching_cubes(f, {.rounding = CoordinateRounding::Float}), InputError);
  EXPECT_NO_THROW(marching_cubes(f, {.rounding = CoordinateRounding::None}));
}

}  // namespace
