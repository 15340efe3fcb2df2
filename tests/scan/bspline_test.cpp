// Stage "bspline" (issue 13's first increment): a cubic B-spline reproduces cubic data, the
// gradient is the derivative, LSPIA reaches the direct least-squares solution.
#include <gtest/gtest.h>

#include <cmath>
#include <tpmsfill/error.hpp>
#include <tpmsfill/scan/bspline.hpp>

using namespace tpmsfill;

namespace {

// A cubic polynomial in each coordinate (total degree up to 3 per axis).
double cubic(double x, double y, double z) {
  return 0.3 + x - 2 * y * y + 0.5 * z * z * z + x * y * z - 0.7 * x * x * y;
}

std::vector<double> sample(std::array<int, 3> d, double (*f)(double, double, double)) {
  std::vector<double> v;
  for (int k = 0; k < d[2]; ++k)
    for (int j = 0; j < d[1]; ++j)
      for (int i = 0; i < d[0]; ++i)
        v.push_back(f((i + 0.5) / d[0], (j + 0.5) / d[1], (k + 0.5) / d[2]));
  return v;
}

double wavy(double x, double y, double z) {
  return std::sin(7 * x) * std::cos(5 * y) + 0.3 * std::sin(11 * z + x);
}

}  // namespace

TEST(BSpline, KnotsAreClampedAndUniform) {
  const std::vector<double> k = clamped_uniform_knots(6, 3);
  const std::vector<double> expected{0, 0, 0, 0, 1.0 / 3, 2.0 / 3, 1, 1, 1, 1};
  ASSERT_EQ(k.size(), expected.size());
  for (std::size_t i = 0; i < k.size(); ++i) EXPECT_DOUBLE_EQ(k[i], expected[i]);
  EXPECT_THROW(clamped_uniform_knots(3, 3), InputError);
}

TEST(BSpline, CubicDataIsReproducedToRoundOff) {
  // Cubic polynomials lie in the spline space: plain least squares recovers them exactly,
  // between the samples too.
  const std::array<int, 3> d{20, 17, 15};
  FitOptions o;
  o.smoothing = 0;
  const FitResult r = fit_bspline(sample(d, cubic), d, {8, 7, 6}, o);
  EXPECT_LT(r.report.max_error, 1e-10);
  for (double u : {0.0, 0.13, 0.5, 0.77, 1.0})
    EXPECT_NEAR(bspline_value(r.volume, u, 1 - u, 0.4), cubic(u, 1 - u, 0.4), 1e-10) << u;
  // And the separable grid evaluation agrees with point evaluation.
  const std::vector<double> grid = evaluate_bspline_grid(r.volume, {5, 4, 3});
  EXPECT_NEAR(grid[1 + 5 * (2 + 4 * 1)], bspline_value(r.volume, 0.3, 0.625, 0.5), 1e-12);
}

TEST(BSpline, GradientMatchesFiniteDifferences) {
  const std::array<int, 3> d{24, 24, 24};
  const FitResult r = fit_bspline(sample(d, wavy), d, {10, 9, 11});
  const double h = 1e-6;
  for (const auto& p :
       {std::array<double, 3>{0.2, 0.3, 0.4}, {0.71, 0.05, 0.93}, {0.5, 0.5, 0.5}}) {
    const std::array<double, 3> g = bspline_gradient(r.volume, p[0], p[1], p[2]);
    for (int a = 0; a < 3; ++a) {
      std::array<double, 3> hi = p, lo = p;
      hi[a] += h, lo[a] -= h;
      const double fd = (bspline_value(r.volume, hi[0], hi[1], hi[2]) -
                         bspline_value(r.volume, lo[0], lo[1], lo[2])) /
                        (2 * h);
      EXPECT_NEAR(g[a], fd, 1e-5 * (1 + std::fabs(fd))) << a;
    }
  }
}

TEST(BSpline, LspiaConvergesToTheDirectSolution) {
  const std::array<int, 3> d{16, 14, 12};
  const std::vector<double> x = sample(d, wavy);
  FitOptions direct;
  direct.smoothing = 0;
  FitOptions lspia = direct;
  lspia.method = FitMethod::Lspia;
  lspia.max_iterations = 20000;
  lspia.relative_change = 1e-14;
  const FitResult a = fit_bspline(x, d, {7, 6, 6}, direct);
  const FitResult b = fit_bspline(x, d, {7, 6, 6}, lspia);
  EXPECT_GT(b.report.iterations, 1);
  EXPECT_NEAR(b.report.rms, a.report.rms, 1e-6 * (1 + a.report.rms));
  // The fitted fields agree at the samples (coefficients converge more slowly along the
  // least-determined directions, which the samples barely see).
  const std::vector<double> fa = evaluate_bspline_grid(a.volume, d);
  const std::vector<double> fb = evaluate_bspline_grid(b.volume, d);
  double largest = 0;
  for (std::size_t i = 0; i < fa.size(); ++i) largest = std::max(largest, std::fabs(fa[i] - fb[i]));
  EXPECT_LT(largest, 1e-3);
  // More coefficients than samples along an axis cannot be fitted.
  EXPECT_THROW(fit_bspline(x, d, {17, 6, 6}), InputError);
}
