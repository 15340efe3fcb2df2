// Seed 001's trivariate T-splines (tspline_basis.hpp): the extraction rows are the functions
// the knots define; a uniform T-mesh gives the tensor-product B-splines; across a planar
// interface between two levels they sum to one, are dual-compatible and reproduce linear
// functions; at a refined region's edge the seed's rule breaks both, and the check says so.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <tpmsfill/error.hpp>
#include <tpmsfill/solid/tspline_basis.hpp>

#include "test_util.hpp"

namespace tpmsfill {
namespace {

using test::Random;

// The cubic B-spline on knots ξ_0..ξ_4 at t, by Cox–de Boor (0/0 = 0), right-open spans but
// the last non-empty one closed, so that t = 1 belongs to the functions ending there.
double bspline(const std::array<double, 5>& xi, double t) {
  double n[4];
  for (int i = 0; i < 4; ++i) {
    const bool last = xi[i + 1] == 1 && xi[i] < 1;
    n[i] = (xi[i] <= t && (t < xi[i + 1] || (last && t == 1))) ? 1 : 0;
  }
  for (int d = 1; d <= 3; ++d)
    for (int i = 0; i < 4 - d; ++i) {
      const double a = xi[i + d] > xi[i] ? (t - xi[i]) / (xi[i + d] - xi[i]) * n[i] : 0;
      const double b = xi[i + d + 1] > xi[i + 1]
                           ? (xi[i + d + 1] - t) / (xi[i + d + 1] - xi[i + 1]) * n[i + 1]
                           : 0;
      n[i] = a + b;
    }
  return n[0];
}

// φ_f(uvw) from its knots alone.
double direct(const SplineBasis& basis, std::size_t f, std::array<double, 3> uvw) {
  double x = 1;
  for (int a = 0; a < 3; ++a) x *= bspline(basis.knots[f][a], uvw[a]);
  return x;
}

// Every function at uvw through the element's extraction rows.
std::vector<double> row_values(const SplineBasis& basis, std::array<double, 3> uvw) {
  const std::size_t e = basis_element_at(basis, uvw);
  const LocalBasis local = local_basis(basis, e, uvw, 0);
  std::vector<double> values(basis.functions.size(), 0.0);
  for (int c = 0; c < 64; ++c) {
    const std::uint32_t row = basis.element_rows[64 * e + c];
    for (std::uint32_t t = basis.row_start[row]; t < basis.row_start[row + 1]; ++t)
      values[basis.row_function[t]] += basis.row_weight[t] * local.value[c];
  }
  return values;
}

CubeOctree refined_where(bool (*inside)(const std::array<double, 3>&), int levels) {
  std::vector<std::array<double, 3>> points;
  Random random{3};
  while (points.size() < 20000) {
    const std::array<double, 3> p = random.point();
    if (inside(p)) points.push_back(p);
  }
  return build_cube_octree(points,
                           {.initial_level = 2, .max_per_cell = 5, .max_level = 2 + levels});
}

// A refined slab x < 1/2 (a planar interface), a refined quarter x, y < 1/2 (an edge), and a
// corner crowded through five levels.
CubeOctree slab() {
  return refined_where([](const std::array<double, 3>& p) { return p[0] < 0.5; }, 1);
}
CubeOctree quarter() {
  return refined_where([](const std::array<double, 3>& p) { return p[0] < 0.5 && p[1] < 0.5; }, 1);
}
CubeOctree crowded_corner() {
  Random random{7};
  std::vector<std::array<double, 3>> points;
  for (int i = 0; i < 3000; ++i) {
    const double r = std::pow(random.next(), 3);
    points.push_back({r * random.next(), r * random.next(), r * random.next()});
  }
  return build_cube_octree(points, {.initial_level = 2, .max_per_cell = 5, .max_level = 7});
}

TEST(TSplineBasis, RowsAreTheFunctionsTheKnotsDefine) {
  for (const CubeOctree& octree : {slab(), quarter(), crowded_corner()}) {
    const SplineBasis basis = tspline_basis(octree);
    ASSERT_EQ(basis.kind, SplineKind::tspline);
    ASSERT_EQ(basis.knots.size(), basis.functions.size());
    ASSERT_EQ(basis.tmesh.size(), octree.leaves.size());
    EXPECT_GE(basis.elements.size(), octree.leaves.size());  // split where knots cut cells
    Random random{11};
    double worst = 0;
    for (int n = 0; n < 150; ++n) {
      const std::array<double, 3> p = random.point();
      const std::vector<double> values = row_values(basis, p);
      for (std::size_t f = 0; f < values.size(); ++f)
        worst = std::max(worst, std::abs(values[f] - direct(basis, f, p)));
    }
    EXPECT_LT(worst, 1e-12);
  }
}

TEST(TSplineBasis, UniformTMeshIsTheTensorBasis) {
  for (int level : {0, 1, 2, 3}) {
    const SplineBasis basis =
        tspline_basis(build_cube_octree({}, {.initial_level = level, .max_level = level}));
    const int n = (1 << level) + 3;
    const SplineBasis tensor = tensor_basis(n);
    ASSERT_EQ(basis.functions.size(), tensor.functions.size());
    EXPECT_TRUE(check_tspline(basis).suitable());
    // The same functions: matched by their Greville points, equal values everywhere.
    const auto ga = greville_points(basis), gb = greville_points(tensor);
    std::vector<std::size_t> a(ga.size()), b(gb.size());
    for (std::size_t i = 0; i < a.size(); ++i) a[i] = b[i] = i;
    std::sort(a.begin(), a.end(), [&](auto x, auto y) { return ga[x] < ga[y]; });
    std::sort(b.begin(), b.end(), [&](auto x, auto y) { return gb[x] < gb[y]; });
    Random random{5};
    for (int k = 0; k < 50; ++k) {
      const std::array<double, 3> p = random.point();
      const std::vector<double> va = row_values(basis, p), vb = row_values(tensor, p);
      for (std::size_t i = 0; i < a.size(); ++i) {
        ASSERT_EQ(ga[a[i]], gb[b[i]]);
        EXPECT_NEAR(va[a[i]], vb[b[i]], 1e-14);
      }
    }
  }
}

TEST(TSplineBasis, PlanarInterfaceSumsToOneAndReproducesLinearFunctions) {
  const CubeOctree octree = slab();
  ASSERT_EQ(octree.deepest, 3);
  const SplineBasis basis = tspline_basis(octree);
  const TSplineCheck check = check_tspline(basis);
  EXPECT_TRUE(check.suitable()) << check.unity_error << " " << check.incompatible_pairs;
  EXPECT_TRUE(check.cells.empty());
  EXPECT_NEAR(check.sum_range[0], 1, 1e-12);
  EXPECT_NEAR(check.sum_range[1], 1, 1e-12);
  const auto greville = greville_points(basis);
  Random random{13};
  for (int n = 0; n < 300; ++n) {
    const std::array<double, 3> p = random.point();
    const std::vector<double> values = row_values(basis, p);
    double sum = 0;
    std::array<double, 3> linear{};
    for (std::size_t f = 0; f < values.size(); ++f) {
      EXPECT_GE(values[f], -1e-15);
      sum += values[f];
      for (int a = 0; a < 3; ++a) linear[a] += values[f] * greville[f][a];
    }
    EXPECT_NEAR(sum, 1, 1e-12);
    for (int a = 0; a < 3; ++a) EXPECT_NEAR(linear[a], p[a], 1e-12);
  }
}

TEST(TSplineBasis, RefinedRegionsEdgeBreaksTheSeedsRuleAndTheCheckSaysWhere) {
  for (const CubeOctree& octree : {quarter(), crowded_corner()}) {
    const SplineBasis basis = tspline_basis(octree);
    const TSplineCheck check = check_tspline(basis);
    EXPECT_FALSE(check.suitable());
    EXPECT_GT(check.incompatible_pairs, 0u);
    EXPECT_EQ(check.duplicates, 0u);
    ASSERT_FALSE(check.cells.empty());
    // The bound is met: Σ φ − 1 sampled is non-zero, and never beyond it.
    Random random{17};
    double off = 0;
    for (int n = 0; n < 2000; ++n) {
      const std::vector<double> values = row_values(basis, random.point());
      double sum = 0;
      for (double v : values) sum += v;
      off = std::max(off, std::abs(sum - 1));
    }
    EXPECT_GT(off, 1e-4);
    EXPECT_LE(off, check.unity_error + 1e-12);
    EXPECT_GT(std::max(1 - check.sum_range[0], check.sum_range[1] - 1), 1e-4);
    EXPECT_LE(std::max(1 - check.sum_range[0], check.sum_range[1] - 1), check.unity_error + 1e-12);
  }
}

TEST(TSplineBasis, RefusesCellsThatDoNotTileTheCube) {
  CubeOctree octree = build_cube_octree({}, {.initial_level = 1, .max_level = 1});
  octree.leaves.pop_back();
  EXPECT_THROW(tspline_basis(octree), InputError);
  octree.leaves.push_back({1, {2, 0, 0}});
  EXPECT_THROW(tspline_basis(octree), InputError);
}

}  // namespace
}  // namespace tpmsfill
