// Stage "grid": the grid covers the box with the padding on every side.
#include <gtest/gtest.h>

#include <cmath>
#include <tpmsfill/error.hpp>
#include <tpmsfill/grid.hpp>

using namespace tpmsfill;

TEST(Grid, CoversTheBoxWithPaddingOnEverySide) {
  for (double a : {0.1, 0.25, 0.7, 1.0}) {
    Box3 box;
    box.extend({-3.3, 0.05, 10.0});
    box.extend({4.1, 7.77, 10.0 + 3 * a});  // an extent that is an exact multiple of a
    for (int pad : {2, 3}) {
      const Grid g = make_grid(box, {.voxel_size = a, .padding = pad});
      EXPECT_EQ(g.spacing, a);
      EXPECT_EQ(g.node_count(), grid_node_count(box, {.voxel_size = a, .padding = pad}));
      for (int axis = 0; axis < 3; ++axis) {
        // `pad` nodes strictly below the box and `pad` strictly above it.
        EXPECT_LT(g.coordinate(axis, pad - 1), box.min[axis]);
        EXPECT_NEAR(g.coordinate(axis, pad), box.min[axis], 1e-12);
        EXPECT_GT(g.coordinate(axis, g.dims[axis] - pad), box.max[axis]);
        EXPECT_GE(g.coordinate(axis, g.dims[axis] - pad - 1), box.max[axis] - 1e-12);
      }
    }
  }
}

TEST(Grid, IndexIsXFastest) {
  Grid g;
  g.dims = {4, 5, 6};
  EXPECT_EQ(g.index(1, 0, 0), 1u);
  EXPECT_EQ(g.index(0, 1, 0), 4u);
  EXPECT_EQ(g.index(0, 0, 1), 20u);
  EXPECT_EQ(g.index(3, 4, 5), g.node_count() - 1);
}

TEST(Grid, RejectsBadOptionsAndBoxes) {
  Box3 box;
  box.extend({0, 0, 0});
  box.extend({1, 1, 1});
  EXPECT_THROW(make_grid(box, {.voxel_size = 0}), InputError);
  EXPECT_THROW(make_grid(box, {.voxel_size = -1}), InputError);
  EXPECT_THROW(make_grid(box, {.voxel_size = std::nan("")}), InputError);
  EXPECT_THROW(make_grid(box, {.voxel_size = 0.1, .padding = -1}), InputError);
  EXPECT_THROW(make_grid(Box3{}, {}), InputError);
  EXPECT_THROW(make_grid(box, {.voxel_size = 1e-12}), InputError);     // > 2^31 nodes per axis
  EXPECT_EQ(grid_node_count(box, {.voxel_size = 1e-12}), UINT64_MAX);  // saturates
}

// A box a whole number of voxels long gets that many cells, whatever the quotient's rounding:
// without padding its first and last nodes sit on its faces, on a printer's bed or a CAD
// assembly's position (where the box's own coordinates round by far less than 10⁻⁹ voxels).
TEST(Grid, AWholeNumberOfVoxelsIsThatManyCells) {
  for (const double origin : {0.0, 150.0, -1000.0, 350.0})
    for (int cells = 1; cells <= 40; ++cells)
      for (const double voxel : {0.1, 0.05, 0.3, 0.7, 0.01}) {
        const Box3 box{{origin, origin, origin},
                       {origin + cells * voxel, origin + 1, origin + cells * voxel}};
        const Grid g = make_grid(box, {.voxel_size = voxel, .padding = 0});
        EXPECT_EQ(g.dims[0], cells + 1) << cells << " x " << voxel << " at " << origin;
        EXPECT_NEAR(g.node(g.dims[0] - 1, 0, 0).x, box.max.x, 1e-9 * voxel);
        EXPECT_EQ(make_grid(box, {.voxel_size = voxel}).dims[2], cells + 5);
      }
}
