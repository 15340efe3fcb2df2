// The spline basis of seed 001 (thb_basis.hpp): THB on adaptive octrees sums to one, is
// non-negative, reproduces linear functions from Greville coefficients, holds a coarser THB
// spline exactly after refinement; the uniform basis is the tensor-product B-spline.
#include <gtest/gtest.h>

#include <cmath>
#include <tpmsfill/error.hpp>
#include <tpmsfill/scan/bspline.hpp>
#include <tpmsfill/solid/thb_basis.hpp>

#include "test_util.hpp"

namespace tpmsfill {
namespace {

using test::Random;

// An octree crowded towards the corner (0, 0, 0): levels 2 to 6, unbalanced or balanced.
CubeOctree corner_octree(bool balance) {
  Random random{7};
  std::vector<std::array<double, 3>> points;
  for (int i = 0; i < 3000; ++i) {
    const double r = std::pow(random.next(), 3);
    points.push_back({r * random.next(), r * random.next(), r * random.next()});
  }
  return build_cube_octree(
      points, {.initial_level = 2, .max_per_cell = 5, .max_level = 6, .balance = balance});
}

// Σ_f weight · local B-spline over the element's rows: every function on one element.
std::vector<double> function_values(const SplineBasis& basis, std::array<double, 3> uvw,
                                    std::vector<std::uint32_t>* support = nullptr) {
  const std::size_t e = basis_element_at(basis, uvw);
  const LocalBasis local = local_basis(basis, e, uvw, 0);
  std::vector<double> values(basis.functions.size(), 0.0);
  for (int c = 0; c < 64; ++c) {
    const std::uint32_t row = basis.element_rows[64 * e + c];
    for (std::uint32_t t = basis.row_start[row]; t < basis.row_start[row + 1]; ++t) {
      values[basis.row_function[t]] += basis.row_weight[t] * local.value[c];
      if (support) support->push_back(basis.row_function[t]);
    }
  }
  return values;
}

TEST(ThbBasis, SumsToOneAndIsNonNegativeOnAnAdaptiveOctree) {
  for (bool balance : {false, true}) {
    const CubeOctree octree = corner_octree(balance);
    ASSERT_GE(octree.deepest, 5);
    const SplineBasis basis = thb_basis(octree);
    EXPECT_EQ(basis.elements.size(), octree.leaves.size());
    Random random{11};
    for (int n = 0; n < 400; ++n) {
      const std::array<double, 3> p = n % 2 ? random.point(0.1) : random.point();
      const std::vector<double> values = function_values(basis, p);
      double sum = 0, lowest = 0;
      for (double v : values) sum += v, lowest = std::min(lowest, v);
      EXPECT_NEAR(sum, 1.0, 1e-13) << p[0] << " " << p[1] << " " << p[2];
      EXPECT_GE(lowest, -1e-15);
    }
  }
}

TEST(ThbBasis, GrevilleCoefficientsReproduceLinearFunctions) {
  const SplineBasis basis = thb_basis(corner_octree(true));
  const std::vector<std::array<double, 3>> greville = greville_points(basis);
  // f(u, v, w) = (2u − v + 3w + 1, u, −w): its values at the Greville points as coefficients.
  std::vector<double> c;
  for (const auto& g : greville) {
    c.push_back(2 * g[0] - g[1] + 3 * g[2] + 1);
    c.push_back(g[0]);
    c.push_back(-g[2]);
  }
  Random random{3};
  for (int n = 0; n < 300; ++n) {
    const std::array<double, 3> p = n % 2 ? random.point(0.05) : random.point();
    double value[3], gradient[9];
    evaluate_spline(basis, c, 3, p, value, gradient);
    EXPECT_NEAR(value[0], 2 * p[0] - p[1] + 3 * p[2] + 1, 1e-12);
    EXPECT_NEAR(value[1], p[0], 1e-12);
    EXPECT_NEAR(value[2], -p[2], 1e-12);
    EXPECT_NEAR(gradient[0], 2, 1e-10);   // ∂u of component 0
    EXPECT_NEAR(gradient[3], -1, 1e-10);  // ∂v of component 0
    EXPECT_NEAR(gradient[6], 3, 1e-10);   // ∂w of component 0
    EXPECT_NEAR(gradient[1], 1, 1e-10);
    EXPECT_NEAR(gradient[8], -1, 1e-10);
  }
}

TEST(ThbBasis, FunctionsAreLinearlyIndependent) {
  // The Gram matrix of the functions at many random points (denser where the octree is) is
  // positive definite: Cholesky finds no pivot near zero. A hierarchical basis without
  // truncation is independent too, but a wrong activity rule (a passive function kept) is not.
  CubeOctree octree = build_cube_octree({}, {.initial_level = 1, .max_level = 1});
  octree = split_octree_leaves(octree, {0}, {}, {.max_level = 3});
  octree = split_octree_leaves(octree, {0, 1}, {}, {.max_level = 3});
  const SplineBasis basis = thb_basis(octree);
  const std::size_t n = basis.functions.size();
  ASSERT_GT(n, 125u);
  std::vector<double> gram(n * n, 0.0);
  Random random{13};
  for (int k = 0; k < 20000; ++k) {
    std::vector<std::uint32_t> support;
    const std::vector<double> v =
        function_values(basis, k % 2 ? random.point(0.5) : random.point(), &support);
    std::sort(support.begin(), support.end());
    support.erase(std::unique(support.begin(), support.end()), support.end());
    for (std::uint32_t a : support)
      for (std::uint32_t b : support) gram[a * n + b] += v[a] * v[b];
  }
  double smallest = 1e300, largest = 0;
  for (std::size_t j = 0; j < n; ++j) {
    for (std::size_t k = 0; k < j; ++k) gram[j * n + j] -= gram[j * n + k] * gram[j * n + k];
    const double pivot = gram[j * n + j];
    smallest = std::min(smallest, pivot), largest = std::max(largest, pivot);
    ASSERT_GT(pivot, 0) << "function " << j;
    const double root = std::sqrt(pivot);
    gram[j * n + j] = root;
    for (std::size_t i = j + 1; i < n; ++i) {
      double s = gram[i * n + j];
      for (std::size_t k = 0; k < j; ++k) s -= gram[i * n + k] * gram[j * n + k];
      gram[i * n + j] = s / root;
    }
  }
  EXPECT_GT(smallest, 1e-9 * largest);
  // A uniform octree at level 3 is the tensor basis with 2^3 + 3 functions per axis.
  const CubeOctree uniform = build_cube_octree({}, {.initial_level = 3, .max_level = 3});
  EXPECT_EQ(thb_basis(uniform).functions.size(), 11u * 11u * 11u);
}

TEST(ThbBasis, TensorBasisIsTheTensorProductBSpline) {
  BSplineVolume volume = make_bspline_volume({9, 9, 9});
  Random random{5};
  std::vector<double> c;
  for (double& x : volume.coefficients) c.push_back(x = random.next() - 0.5);
  const SplineBasis basis = tensor_basis(9);
  ASSERT_EQ(basis.functions.size(), 729u);
  for (int n = 0; n < 200; ++n) {
    const std::array<double, 3> p = random.point();
    double value = 0, gradient[3];
    evaluate_spline(basis, c, 1, p, &value, gradient);
    EXPECT_NEAR(value, bspline_value(volume, p[0], p[1], p[2]), 1e-13);
    const std::array<double, 3> expected = bspline_gradient(volume, p[0], p[1], p[2]);
    for (int a = 0; a < 3; ++a) EXPECT_NEAR(gradient[a], expected[a], 1e-11);
  }
  EXPECT_THROW(tensor_basis(3), InputError);
}

TEST(ThbBasis, RefinedBasisHoldsTheCoarseSplineExactly) {
  const CubeOctree coarse_tree = corner_octree(true);
  const SplineBasis coarse = thb_basis(coarse_tree);
  // Split every leaf that touches the plane u = 0.5, and the first few leaves.
  std::vector<std::size_t> chosen;
  for (std::size_t l = 0; l < coarse_tree.leaves.size(); ++l) {
    const OctreeCell& c = coarse_tree.leaves[l];
    const double size = std::ldexp(1.0, -c.level);
    if ((c.index[0] * size <= 0.5 && (c.index[0] + 1) * size > 0.5) || l < 10) chosen.push_back(l);
  }
  const CubeOctree fine_tree = split_octree_leaves(coarse_tree, chosen, {}, {.max_level = 7});
  ASSERT_GT(fine_tree.leaves.size(), coarse_tree.leaves.size());
  const SplineBasis fine = thb_basis(fine_tree);
  ASSERT_GT(fine.functions.size(), coarse.functions.size());
  Random random{9};
  std::vector<double> c(coarse.functions.size() * 2);
  for (double& x : c) x = random.next();
  const std::vector<double> refined = refine_coefficients(coarse, fine, c, 2);
  ASSERT_EQ(refined.size(), fine.functions.size() * 2);
  for (int n = 0; n < 400; ++n) {
    const std::array<double, 3> p = n % 3 ? random.point() : random.point(0.1);
    double a[2], b[2];
    evaluate_spline(coarse, c, 2, p, a);
    evaluate_spline(fine, refined, 2, p, b);
    EXPECT_NEAR(a[0], b[0], 1e-12);
    EXPECT_NEAR(a[1], b[1], 1e-12);
  }
  // The other way round is not a refinement.
  EXPECT_THROW(refine_coefficients(fine, coarse, refined, 2), InputError);
}

}  // namespace
}  // namespace tpmsfill
