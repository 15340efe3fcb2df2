// fill()'s slab path: a job split into slabs gives the whole grid's mesh bit for bit, and its
// report the same figures, whatever the designs and inside rules; marching cubes fed slab by
// slab numbers its points as on the whole field; fill_to_file streaming the slabs writes the
// bytes write_mesh writes of the held mesh.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <limits>
#include <string>
#include <tpmsfill/error.hpp>
#include <tpmsfill/fill.hpp>
#include <tpmsfill/io.hpp>
#include <tpmsfill/recipe.hpp>
#include <tpmsfill/sampling/marching_cubes.hpp>

#include "test_util.hpp"

using namespace tpmsfill;

namespace {

// The whole grid's result and slabs of each thickness give the same mesh and figures.
void expect_same_in_slabs(const TriangleSoup& model, FillOptions o,
                          std::initializer_list<int> thicknesses) {
  o.slab_planes = 0;
  const FillResult whole = fill(model, o);
  ASSERT_EQ(whole.report.slab_planes, 0);
  for (int planes : thicknesses) {
    o.slab_planes = planes;
    const FillResult slabs = fill(model, o);
    SCOPED_TRACE("slabs of " + std::to_string(planes) + " planes");
    EXPECT_EQ(slabs.report.slab_planes, std::min(planes, whole.report.grid.dims[2]));
    ASSERT_EQ(slabs.mesh.points.size(), whole.mesh.points.size());
    ASSERT_EQ(slabs.mesh.triangles.size(), whole.mesh.triangles.size());
    EXPECT_TRUE(slabs.mesh.points == whole.mesh.points);
    EXPECT_TRUE(slabs.mesh.triangles == whole.mesh.triangles);
    const FillReport &a = whole.report, &b = slabs.report;
    EXPECT_EQ(a.model_volume, b.model_volume);
    EXPECT_EQ(a.band_nodes, b.band_nodes);
    EXPECT_EQ(a.distance_queries, b.distance_queries);
    EXPECT_EQ(a.rows, b.rows);
    EXPECT_EQ(a.crossings, b.crossings);
    EXPECT_EQ(a.islands_removed, b.islands_removed);
    EXPECT_EQ(a.islands_volume, b.islands_volume);
    EXPECT_EQ(a.cavities, b.cavities);
    EXPECT_EQ(a.cleaned(), b.cleaned());
    EXPECT_EQ(a.lattice_volume(), b.lattice_volume());
    EXPECT_EQ(a.warnings, b.warnings);
    // Slabs are proved as the whole grid is (the proof's checks run slab by slab).
    EXPECT_EQ(b.validation.validated_by, a.validation.validated_by);
    EXPECT_EQ(b.validation.valid(), a.validation.valid());
    EXPECT_EQ(b.validation.vertices, a.validation.vertices);
    EXPECT_EQ(b.validation.volume, a.validation.volume);
    EXPECT_EQ(b.validation.self_intersecting_pairs, a.validation.self_intersecting_pairs);
  }
}

}  // namespace

namespace {

// f's mesh made by SlabMarchingCubes, `per` planes a slab; what it left unproved in `unproved`.
TriangleSoup mesh_in_slabs_of(const Field& f, int per, std::string& unproved) {
  const Grid& grid = f.grid;
  const int nz = grid.dims[2];
  const std::size_t layer = static_cast<std::size_t>(grid.dims[0]) * grid.dims[1];
  SlabMarchingCubes mc(grid);
  TriangleSoup mesh;
  while (!mc.done()) {
    const int first = mc.next_plane(), owned = std::min(per, nz - first);
    const int last = std::min(first + owned + 1, nz - 1);
    Grid g = grid;
    g.z_offset = first;
    g.dims[2] = last - first + 1;
    Field slab{g, std::vector<float>(f.values.begin() + first * layer,
                                     f.values.begin() + (last + 1) * layer)};
    mc.add(slab, owned, mesh);
  }
  unproved = mc.unproved();
  return mesh;
}

}  // namespace

TEST(SlabMarchingCubes, SlabsNumberPointsAsTheWholeField) {
  const Grid grid{{-1, -1, -1}, 0.1, {23, 21, 27}};
  const Field f = test::wavy_field(grid);
  const TriangleSoup whole = marching_cubes(f);
  ASSERT_GT(whole.triangles.size(), 100u);
  for (int per : {1, 2, 5, 26, 40}) {
    std::string unproved;
    const TriangleSoup mesh = mesh_in_slabs_of(f, per, unproved);
    EXPECT_TRUE(mesh.points == whole.points) << per;
    EXPECT_TRUE(mesh.triangles == whole.triangles) << per;
  }
  // Planes out of turn are refused.
  SlabMarchingCubes mc(grid);
  TriangleSoup mesh;
  Grid g = grid;
  g.z_offset = 1;
  g.dims[2] = 4;
  EXPECT_THROW(mc.add(Field{g, std::vector<float>(g.node_count(), 1.0f)}, 2, mesh), InputError);
}

// Slab by slab, the proof's checks give marching_cubes_proved()'s verdict on the whole field:
// proved, a node inside on a side face or the top (the surface open there), a NaN vertex.
TEST(SlabMarchingCubes, SlabsAreProvedAsTheWholeField) {
  const Grid grid{{-1, -1, -1}, 0.5, {9, 8, 11}};
  Field closed{grid, std::vector<float>(grid.node_count(), 1.0f)};
  for (int k = 2; k < 9; ++k) closed.values[grid.index(4, 4, k)] = -1.0f;
  Field side = closed, top = closed, nan = closed;
  side.values[grid.index(0, 3, 6)] = -1.0f;
  top.values[grid.index(4, 4, 10)] = -1.0f;
  nan.values[grid.index(5, 4, 5)] = std::numeric_limits<float>::quiet_NaN();
  for (const Field* f : {&closed, &side, &top, &nan}) {
    const ProvedMesh whole = marching_cubes_proved(*f);
    for (int per : {1, 3, 11}) {
      std::string unproved;
      const TriangleSoup mesh = mesh_in_slabs_of(*f, per, unproved);
      EXPECT_TRUE(mesh.triangles == whole.mesh.triangles);
      EXPECT_EQ(unproved, whole.unproved) << per;
    }
  }
  EXPECT_TRUE(marching_cubes_proved(closed).unproved.empty());
  EXPECT_NE(marching_cubes_proved(side).unproved.find("border"), std::string::npos);
  EXPECT_NE(marching_cubes_proved(top).unproved.find("border"), std::string::npos);
  EXPECT_NE(marching_cubes_proved(nan).unproved.find("vertex"), std::string::npos);
}

TEST(FillSlabs, GyroidInASphereIsTheSameInSlabs) {
  expect_same_in_slabs(test::make_sphere({0, 0, 0}, 4, 4), test::gyroid_options(2, 0.12),
                       {1, 3, 7, 1000});
}

TEST(FillSlabs, SheetWithSkinAndWindowsIsTheSameInSlabs) {
  FillOptions o = test::gyroid_options(2.5, 0.1);
  o.design.style = TpmsStyle::Sheet;
  o.design.thickness = 0.3;
  o.skin = 0.4;
  o.skin_windows = true;
  expect_same_in_slabs(test::make_torus(5, 2, 64, 32), o, {4, 9});
}

TEST(FillSlabs, DepthGradingAndBlendsAreTheSameInSlabs) {
  FillOptions o = test::gyroid_options(2, 0.1);
  o.design.porosity = 0.6;
  o.design.grading.push_back(
      {Graded::Porosity,
       Ramp{.shape = RampShape::Depth, .from = 0, .to = 1.5, .start = 0.4, .end = 0.8}});
  Blend b;
  b.tpms.type = TpmsType::Diamond;
  b.tpms.cell = {2, 2, 2};
  b.region.point = {0, 0, 1};
  o.design.blends.push_back(b);
  expect_same_in_slabs(test::make_box({-3, -3, -3}, {3, 3, 3}), o, {5});
}

TEST(FillSlabs, OpenScanParityAndFullFieldAreTheSameInSlabs) {
  const TriangleSoup open = test::make_box_with_hole({0, 0, 0}, {5, 5, 5});
  expect_same_in_slabs(open, test::gyroid_options(2, 0.12), {6});  // auto: cleaned in both
  FillOptions parity = test::gyroid_options(2, 0.12);
  parity.inside = InsideRule::Parity;
  expect_same_in_slabs(test::make_torus(4, 1.5, 48, 24), parity, {6});
  FillOptions full = test::gyroid_options(2, 0.15);
  full.full_field = true;
  expect_same_in_slabs(test::make_sphere({0, 0, 0}, 3, 3), full, {8});
}

TEST(FillSlabs, IslandsAndCavitiesAreJudgedAsOnTheWholeGrid) {
  // Two balls (one piece each, several islands at the rims) and a closed skin sealing voids.
  const TriangleSoup two =
      test::concat(test::make_sphere({0, 0, 0}, 3, 4), test::make_sphere({8, 0, 0}, 2, 4));
  FillOptions o = test::gyroid_options(1.5, 0.1);
  o.design.level = 0.3;
  expect_same_in_slabs(two, o, {5});
  FillOptions skin = test::gyroid_options(2, 0.1);
  skin.skin = 0.3;
  expect_same_in_slabs(test::make_sphere({0, 0, 0}, 3, 4), skin, {5});
}

TEST(FillSlabs, AJobOverTheBudgetGoesInSlabsOnItsOwn) {
  // Validation holds the whole mesh, so a job written to a file goes in slabs and streams its
  // output when the whole grid and mesh would not fit: the same bytes within the budget.
  const TriangleSoup ball = test::make_sphere({0, 0, 0}, 6, 4);
  FillOptions o = test::gyroid_options(3, 0.1);
  // Searched in full, validation needs more than the field stages: more than thin slabs do.
  o.validation = FillOptions::Validation::Full;
  const auto dir = test::scratch_dir();
  const FillResult whole = fill_to_file(ball, o, dir / "whole.stl");
  ASSERT_EQ(whole.report.slab_planes, 0);
  // A budget between the whole job's forecast and that of the thinnest slabs.
  FillOptions thin = o;
  thin.slab_planes = 4;
  const std::uint64_t least = forecast_fill(ball, thin).memory_bytes;
  ASSERT_LT(least, whole.report.estimated_memory_bytes);
  o.memory_budget = (least + whole.report.estimated_memory_bytes) / 2;
  const FillResult slabs = fill_to_file(ball, o, dir / "slabs.stl");
  EXPECT_GT(slabs.report.slab_planes, 3);
  EXPECT_LT(slabs.report.slab_planes, whole.report.grid.dims[2]);
  EXPECT_LE(slabs.report.estimated_memory_bytes, o.memory_budget);
  EXPECT_EQ(test::read_file(dir / "slabs.stl"), test::read_file(dir / "whole.stl"));
  // --measure needs the whole grid: refused with the numbers, not silently dropped.
  o.measure = true;
  try {
    fill_to_file(ball, o, dir / "measured.stl");
    FAIL() << "no ResourceError";
  } catch (const ResourceError& e) {
    EXPECT_NE(std::string(e.what()).find("--measure needs the whole grid"), std::string::npos)
        << e.what();
  }
  EXPECT_FALSE(std::filesystem::exists(dir / "measured.stl"));
}

TEST(FillParts, ThreePartsJoinIntoTheWholeGridsMesh) {
  // As three processes would split it (MPI): each part alone, the auto rule agreed across
  // them, joined in plane order.
  for (const TriangleSoup& model :
       {test::make_torus(5, 2, 64, 32), test::make_box_with_hole({0, 0, 0}, {5, 5, 5})}) {
    FillOptions o = test::gyroid_options(2, 0.12);
    const FillResult whole = fill(model, o);
    const int nz = fill_grid(model, o).dims[2];
    ASSERT_EQ(nz, whole.report.grid.dims[2]);
    const int cut[4] = {0, nz / 3, 2 * nz / 3 + 1, nz};
    // The agreement: any part that finds the input open makes every part clean it.
    bool any = false;
    for (int pass = 0; pass < 2; ++pass) {
      std::vector<FillPart> parts;
      for (int r = 0; r < 3; ++r)
        parts.push_back(fill_part(
            model, o,
            {.first_plane = cut[r], .end_plane = cut[r + 1], .any_unbalanced = [&](bool mine) {
               any = any || mine;
               return pass == 0 ? mine : any;
             }}));
      if (pass == 0) continue;  // the first pass only learns whether any part is unbalanced
      const FillResult joined = fill_parts(model, o, std::move(parts));
      EXPECT_EQ(joined.report.ranks, 3);
      EXPECT_TRUE(joined.mesh.points == whole.mesh.points);
      EXPECT_TRUE(joined.mesh.triangles == whole.mesh.triangles);
      EXPECT_EQ(joined.report.model_volume, whole.report.model_volume);
      EXPECT_EQ(joined.report.band_nodes, whole.report.band_nodes);
      EXPECT_EQ(joined.report.cleaned(), whole.report.cleaned());
      EXPECT_EQ(joined.report.islands_removed, whole.report.islands_removed);
    }
  }
  // A porosity with a skin is the part's: each part solves the lattice's level for the whole
  // part, and the joined report (rank 0's under mpirun) carries that level, the lattice's own
  // porosity and the skin's warning, as the one-process job's does.
  const TriangleSoup plate = test::make_box({0, 0, 0}, {30, 24, 6});
  for (const double skin : {0.5, 2.5}) {
    FillOptions o = test::gyroid_options(3, 0.3);
    o.design.porosity = 0.7;
    o.skin = skin;
    const FillResult whole = fill(plate, o);
    const int nz = fill_grid(plate, o).dims[2];
    std::vector<FillPart> parts;
    parts.push_back(fill_part(plate, o, {.first_plane = 0, .end_plane = nz / 2}));
    parts.push_back(fill_part(plate, o, {.first_plane = nz / 2, .end_plane = nz}));
    const FillResult joined = fill_parts(plate, o, std::move(parts));
    EXPECT_TRUE(joined.mesh.triangles == whole.mesh.triangles) << "skin " << skin;
    EXPECT_EQ(joined.report.level, whole.report.level) << "skin " << skin;
    EXPECT_EQ(joined.report.unclipped_porosity, whole.report.unclipped_porosity);
    EXPECT_EQ(joined.resolved.design.level, whole.resolved.design.level);
    EXPECT_EQ(recipe_json(joined.resolved), recipe_json(whole.resolved))
        << "the echoed recipe holds the solved level";
    EXPECT_EQ(joined.report.warnings, whole.report.warnings) << "skin " << skin;
  }
  // Parts that leave a gap are refused.
  const TriangleSoup ball = test::make_sphere({0, 0, 0}, 3, 3);
  const FillOptions o = test::gyroid_options(2, 0.2);
  const int nz = fill_grid(ball, o).dims[2];
  std::vector<FillPart> gap;
  gap.push_back(fill_part(ball, o, {.first_plane = 0, .end_plane = 5}));
  gap.push_back(fill_part(ball, o, {.first_plane = 6, .end_plane = nz}));
  EXPECT_THROW(fill_parts(ball, o, std::move(gap)), InputError);
}

namespace {

// fill_to_file in slabs writes what write_mesh writes of fill()'s mesh, byte for byte, in every
// format, with the same validation figures, and leaves nothing else in the folder.
void expect_streamed_as_held(const TriangleSoup& model, FillOptions o, int planes,
                             const std::string& name) {
  const std::filesystem::path dir = test::scratch_dir() / name;
  std::filesystem::create_directories(dir);
  o.slab_planes = 0;
  const FillResult held = fill(model, o);
  o.slab_planes = planes;
  for (const char* ext : {".stl", ".ply", ".obj", ".off"}) {
    SCOPED_TRACE(std::string("streamed to ") + ext);
    const std::filesystem::path expected = dir / (std::string("held") + ext),
                                streamed = dir / (std::string("streamed") + ext);
    write_mesh(expected, held.mesh);
    const FillResult s = fill_to_file(model, o, streamed);
    EXPECT_TRUE(s.mesh.triangles.empty());
    EXPECT_EQ(s.report.slab_planes, std::min(planes, held.report.grid.dims[2]));
    EXPECT_TRUE(test::read_file(streamed) == test::read_file(expected));
    const MeshValidity &a = held.report.validation, &b = s.report.validation;
    EXPECT_TRUE(b.valid());
    EXPECT_EQ(a.vertices, b.vertices);
    EXPECT_EQ(a.triangles, b.triangles);
    EXPECT_EQ(a.components, b.components);
    EXPECT_EQ(a.volume, b.volume);  // the same sums in the same order
    EXPECT_EQ(a.area, b.area);
    EXPECT_EQ(a.outward, b.outward);
    EXPECT_EQ(a.self_intersecting_pairs, b.self_intersecting_pairs);
    // Proved by marching cubes' construction on both paths, or searched on both (--validate
    // full, the oracle).
    const ValidatedBy by = o.validation == FillOptions::Validation::Full
                               ? ValidatedBy::Search
                               : ValidatedBy::Construction;
    EXPECT_EQ(a.validated_by, by);
    EXPECT_EQ(b.validated_by, by);
    EXPECT_EQ(held.report.islands_removed, s.report.islands_removed);
    EXPECT_EQ(held.report.islands_volume, s.report.islands_volume);
    EXPECT_EQ(held.report.cavities, s.report.cavities);
    EXPECT_EQ(held.report.warnings, s.report.warnings);
    ASSERT_EQ(held.report.largest_islands.size(), s.report.largest_islands.size());
    for (std::size_t i = 0; i < held.report.largest_islands.size(); ++i) {
      EXPECT_EQ(held.report.largest_islands[i].volume, s.report.largest_islands[i].volume);
      EXPECT_TRUE(held.report.largest_islands[i].bbox.min == s.report.largest_islands[i].bbox.min);
      EXPECT_TRUE(held.report.largest_islands[i].bbox.max == s.report.largest_islands[i].bbox.max);
    }
  }
  // The spill file and the writer's temporaries are gone: only the outputs remain.
  std::size_t files = 0;
  for (const auto& entry : std::filesystem::directory_iterator(dir)) {
    ++files;
    EXPECT_NE(entry.path().filename().string()[0], '.') << entry.path();
  }
  EXPECT_EQ(files, 8u);
}

}  // namespace

TEST(FillToFile, StreamedSlabsWriteTheHeldMeshByteForByte) {
  expect_streamed_as_held(test::make_sphere({0, 0, 0}, 4, 4), test::gyroid_options(2, 0.12), 3,
                          "stream_sphere");
  // One plane a slab: every record is one cell layer, every seam a slab's.
  expect_streamed_as_held(test::make_torus(5, 2, 64, 32), test::gyroid_options(2.5, 0.15), 1,
                          "stream_torus");
  // Coordinates kept as doubles, no intersection search: the same on both paths too.
  FillOptions doubles = test::gyroid_options(2, 0.15);
  doubles.rounding = CoordinateRounding::None;
  doubles.check_self_intersections = false;
  expect_streamed_as_held(test::make_box({-3, -3, -3}, {3, 3, 3}), doubles, 6, "stream_doubles");
  // Searched instead of proved, window by window: the same verdict and figures.
  FillOptions full = test::gyroid_options(2, 0.12);
  full.validation = FillOptions::Validation::Full;
  expect_streamed_as_held(test::make_sphere({0, 0, 0}, 4, 4), full, 3, "stream_full");
}

TEST(FillToFile, IslandsAndCavitiesAreJudgedAsWhenHeld) {
  const TriangleSoup two =
      test::concat(test::make_sphere({0, 0, 0}, 3, 4), test::make_sphere({8, 0, 0}, 2, 4));
  FillOptions o = test::gyroid_options(1.5, 0.1);
  o.design.level = 0.3;
  expect_streamed_as_held(two, o, 5, "stream_islands");
  FillOptions skin = test::gyroid_options(2, 0.1);
  skin.skin = 0.3;
  expect_streamed_as_held(test::make_sphere({0, 0, 0}, 3, 4), skin, 4, "stream_skin");
}

TEST(FillToFile, AJobThatFitsIsWrittenWhole) {
  const TriangleSoup ball = test::make_sphere({0, 0, 0}, 3, 3);
  const FillOptions o = test::gyroid_options(2, 0.15);
  const std::filesystem::path dir = test::scratch_dir();
  const FillResult held = fill(ball, o);
  write_mesh(dir / "held.stl", held.mesh);
  const FillResult s = fill_to_file(ball, o, dir / "out.stl");
  EXPECT_EQ(s.report.slab_planes, 0);
  EXPECT_TRUE(test::read_file(dir / "out.stl") == test::read_file(dir / "held.stl"));
  // A name without a format is refused before any work, and nothing is written.
  EXPECT_THROW(fill_to_file(ball, o, dir / "out.xyz"), InputError);
  EXPECT_FALSE(std::filesystem::exists(dir / "out.xyz"));
}

TEST(FillToFile, PartsTakenOneAtATimeWriteTheWholeMesh) {
  // As rank 0 under mpirun: three parts arrive in plane order and are spilled as they come
  // (slabs forced: the streamed path), or joined and held (the whole grid fits).
  const TriangleSoup model = test::make_torus(5, 2, 64, 32);
  const std::filesystem::path dir = test::scratch_dir();
  for (int planes : {0, 4}) {
    SCOPED_TRACE("slab_planes " + std::to_string(planes));
    FillOptions o = test::gyroid_options(2, 0.12);
    o.slab_planes = planes;
    const FillResult whole = fill(model, o);
    const int nz = fill_grid(model, o).dims[2];
    const int cut[4] = {0, nz / 3, 2 * nz / 3 + 1, nz};
    for (const char* ext : {".stl", ".ply"}) {
      write_mesh(dir / (std::string("whole") + ext), whole.mesh);
      int next = 0;
      const FillResult joined = fill_parts_to_file(
          model, o, 3,
          [&] {
            const int r = next++;
            return fill_part(model, o, {.first_plane = cut[r], .end_plane = cut[r + 1]});
          },
          dir / (std::string("parts") + ext));
      EXPECT_EQ(joined.report.ranks, 3);
      EXPECT_TRUE(joined.report.validation.valid());
      EXPECT_EQ(joined.report.validation.volume, whole.report.validation.volume);
      EXPECT_EQ(joined.report.islands_removed, whole.report.islands_removed);
      EXPECT_TRUE(test::read_file(dir / (std::string("parts") + ext)) ==
                  test::read_file(dir / (std::string("whole") + ext)))
          << ext;
    }
  }
  // Parts out of order are refused, and nothing is written.
  FillOptions o = test::gyroid_options(2, 0.12);
  o.slab_planes = 4;
  const int nz = fill_grid(model, o).dims[2];
  int next = 0;
  EXPECT_THROW(fill_parts_to_file(
                   model, o, 2,
                   [&] {
                     return next++ == 0
                                ? fill_part(model, o, {.first_plane = nz / 2, .end_plane = nz})
                                : fill_part(model, o, {.first_plane = 0, .end_plane = nz / 2});
                   },
                   dir / "bad.stl"),
               InputError);
  EXPECT_FALSE(std::filesystem::exists(dir / "bad.stl"));
}
