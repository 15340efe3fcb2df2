// The field seam: sources bound to a grid and evaluated by blocks of rows give every node one
// value, whatever the blocks, the thread count or the consumer.
#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <atomic>
#include <cmath>
#include <tpmsfill/error.hpp>
#include <tpmsfill/field.hpp>
#include <tpmsfill/lattice/design.hpp>
#include <tpmsfill/lattice/tpms.hpp>
#include <tpmsfill/sampling/marching_cubes.hpp>

#include "test_util.hpp"

using namespace tpmsfill;

namespace {

Grid small_grid() {
  Grid g;
  g.origin = {-1.3, 0.2, 5.0};
  g.spacing = 0.17;
  g.dims = {13, 9, 7};
  return g;
}

// Every row of `grid` asked in blocks of `block` rows, serially.
std::vector<float> by_blocks(const FieldSource& source, const Grid& grid, std::size_t block) {
  const RowFunction rows = source.on_grid(grid);
  std::vector<float> values(grid.node_count());
  const std::size_t nx = static_cast<std::size_t>(grid.dims[0]);
  for (std::size_t first = 0; first < grid.row_count(); first += block)
    rows(first, std::min(block, grid.row_count() - first), values.data() + first * nx, nullptr);
  return values;
}

// A graded, rotated, blended design: every path of the design's evaluator.
LatticeDesign busy_design() {
  LatticeDesign d;
  d.type = TpmsType::Diamond;
  d.style = TpmsStyle::Sheet;
  d.porosity = 0.7;
  d.rotation = rotation_from_euler({10, 20, 30});
  d.grading.push_back(
      {Graded::Cell,
       {.point = Vec3{0, 0, 0}, .axis = {0, 0, 1}, .from = 5, .to = 6, .start = 1.5, .end = 2.5}});
  d.blends.push_back({.tpms = {.type = TpmsType::Iwp, .level = 0.1},
                      .region = {.shape = RegionShape::Sphere, .point = {0, 1, 5.5}, .size = 0.6},
                      .width = 0.5});
  return d;
}

}  // namespace

TEST(Field, SampleEqualsPointValuesForEveryTypeAndDesign) {
  const Grid g = small_grid();
  std::vector<FieldSource> sources;
  for (TpmsType type : test::kAllTpmsTypes)
    sources.push_back(tpms_source({.type = type, .cell = {1.5, 2, 2.5}, .level = 0.1}));
  sources.push_back(tpms_source({.rotation = rotation_from_euler({0, 30, 0})}));
  sources.push_back(design_source(busy_design()));
  for (const FieldSource& source : sources) {
    const Field f = sample_field(source, g);
    ASSERT_EQ(f.values.size(), g.node_count());
    for (int k = 0; k < g.dims[2]; ++k)
      for (int j = 0; j < g.dims[1]; ++j)
        for (int i = 0; i < g.dims[0]; ++i)
          ASSERT_EQ(f.values[g.index(i, j, k)], field_value(source, g.node(i, j, k)));
  }
}

TEST(Field, BlocksAndThreadsDoNotChangeAValue) {
  const Grid g = small_grid();
  for (const FieldSource& source : {design_source(busy_design()), tpms_source({})}) {
    const std::vector<float> one_row = by_blocks(source, g, 1);
    for (std::size_t block : {2u, 5u, 9u, 63u}) EXPECT_EQ(by_blocks(source, g, block), one_row);
    for (int threads : {1, 2, 4}) {
      tbb::global_control limit(tbb::global_control::max_allowed_parallelism, threads);
      EXPECT_EQ(sample_field(source, g).values, one_row) << threads << " threads";
    }
  }
}

TEST(Field, FunctionSourceEvaluatesOnlyWhatIsNeeded) {
  const Grid g = small_grid();
  std::atomic<int> calls{0};
  const FieldSource plane = function_source([&](Vec3 p) {
    ++calls;
    return static_cast<float>(p.x + 2 * p.y - p.z);
  });
  const RowFunction rows = plane.on_grid(g);
  const std::size_t nx = static_cast<std::size_t>(g.dims[0]);
  std::vector<float> values(3 * nx, 42.0f);
  std::vector<std::uint8_t> need(3 * nx, 0);
  for (std::size_t n = 0; n < need.size(); n += 4) need[n] = 1;
  rows(10, 3, values.data(), need.data());
  int asked = 0;
  for (std::size_t n = 0; n < need.size(); ++n) {
    const std::size_t row = 10 + n / nx;
    const Vec3 p = g.node(static_cast<int>(n % nx), static_cast<int>(row % g.dims[1]),
                          static_cast<int>(row / g.dims[1]));
    if (need[n]) {
      ++asked;
      EXPECT_EQ(values[n], static_cast<float>(p.x + 2 * p.y - p.z));
    } else {
      EXPECT_EQ(values[n], 42.0f);  // left as it was
    }
  }
  EXPECT_EQ(calls.load(), asked);
}

TEST(Field, EmptySourcesAndBadDepthAreRefused) {
  EXPECT_THROW(sample_field(FieldSource{}, small_grid()), InputError);
  EXPECT_THROW(field_value(function_source({}), {0, 0, 0}), InputError);
  // A bound that is no distance, or on_grid giving nothing, is refused by every consumer.
  FieldSource bad = function_source([](Vec3 p) { return static_cast<float>(p.x); });
  for (double bound : {-1.0, std::nan("")}) {
    bad.bound = bound;
    EXPECT_THROW(sample_field(bad, small_grid()), InputError);
  }
  bad = {.on_grid = [](const Grid&) { return RowFunction{}; }};
  EXPECT_THROW(sample_field(bad, small_grid()), InputError);
  EXPECT_THROW(marching_cubes(bad, small_grid()), InputError);
  LatticeDesign custom;
  custom.custom = bad;
  EXPECT_THROW(sample_field(design_source(custom), small_grid()), InputError);
  // A depth ramp needs a depth field on the grid it is evaluated on.
  LatticeDesign d;
  d.grading.push_back({Graded::Porosity,
                       {.shape = RampShape::Depth, .from = 0, .to = 1, .start = 0.5, .end = 0.8}});
  EXPECT_THROW(sample_field(design_source(d), small_grid()), InputError);
  Field other{test::grid_around({{0, 0, 0}, {1, 1, 1}}, 0.5, 0), {}};
  other.values.assign(other.grid.node_count(), 0.0f);
  EXPECT_THROW(sample_field(design_source(d, &other), small_grid()), InputError);
}
