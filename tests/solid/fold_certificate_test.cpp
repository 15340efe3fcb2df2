// certify_fold_free (fold_certificate.hpp): det J_G's Bernstein bound proves an unfolded map,
// finds a fold that every sampled check misses once it halves deep enough, and says
// undecided, not proven, before that.
#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <cmath>
#include <tpmsfill/error.hpp>
#include <tpmsfill/solid/fold_certificate.hpp>
#include <tpmsfill/solid/thb_basis.hpp>

namespace tpmsfill {
namespace {

// G(u, v, w) = (ε u + (u − c)³ / 3, v, w) on one element (the four clamped cubic B-splines of
// one span are Bernstein's), so det J_G = ε + (u − c)²: positive everywhere for ε > 0 though
// its Bernstein coefficients are not all positive until halved, and for ε < 0 negative only
// on (c − √−ε, c + √−ε).
SolidSpline dipping_map(double epsilon, double c) {
  SolidSpline spline;
  spline.basis = tensor_basis(4);
  // x(u) = a0 + a1 u + a2 u² + a3 u³ in Bernstein form.
  const double a3 = 1.0 / 3, a2 = -c, a1 = epsilon + c * c, a0 = -c * c * c / 3;
  const double b[4] = {a0, a0 + a1 / 3, a0 + 2 * a1 / 3 + a2 / 3, a0 + a1 + a2 + a3};
  for (const SplineFunction& f : spline.basis.functions)
    spline.geometry.push_back({b[f.index[0]], f.index[1] / 3.0, f.index[2] / 3.0});
  return spline;
}

double det_at(double epsilon, double c, double u) {
  return epsilon + (u - c) * (u - c);
}

TEST(FoldCertificate, AnAffineMapIsProvenOnEveryElement) {
  SolidSpline spline;
  spline.basis = tensor_basis(9);
  const auto greville = greville_points(spline.basis);
  for (const auto& g : greville)  // a sheared, stretched box: det J = 2 · 3 · 0.5
    spline.geometry.push_back({2 * g[0] + 0.7 * g[1], 3 * g[1], 0.5 * g[2] - g[0]});
  const FoldCertificate certificate = certify_fold_free(spline);
  EXPECT_EQ(certificate.elements, spline.basis.elements.size());
  EXPECT_EQ(certificate.proven, certificate.elements);
  EXPECT_EQ(certificate.folded, 0u);
  EXPECT_EQ(certificate.undecided, 0u);
  EXPECT_EQ(certificate.boxes, certificate.elements);  // no halving needed
}

TEST(FoldCertificate, APositiveDipIsProvenOnceHalved) {
  const SolidSpline spline = dipping_map(0.01, 0.53);
  EXPECT_EQ(certify_fold_free(spline, {.depth = 0}).undecided, 1u);  // a coefficient < 0
  const FoldCertificate certificate = certify_fold_free(spline, {.depth = 5});
  EXPECT_EQ(certificate.proven, 1u);
  EXPECT_GT(certificate.boxes, 1u);
}

TEST(FoldCertificate, AFoldBetweenEverySampledPointIsFoundByHalving) {
  // det J_G < 0 on (0.52, 0.54) only: no Gauss point, no 5³ or 4³ check point, no eighth.
  const double epsilon = -1e-4, c = 0.53;
  for (double u : {0.11270166537925831, 0.5, 0.88729833462074169, 0.1, 0.3, 0.7, 0.9, 0.0, 1.0 / 3,
                   2.0 / 3, 1.0, 0.625, 0.5625})
    ASSERT_GT(det_at(epsilon, c, u), 0) << u;
  const SolidSpline spline = dipping_map(epsilon, c);
  const FoldCertificate shallow = certify_fold_free(spline, {.depth = 2});
  EXPECT_EQ(shallow.undecided, 1u);  // never proven
  EXPECT_EQ(shallow.proven, 0u);
  const FoldCertificate deep = certify_fold_free(spline, {.depth = 6});
  ASSERT_EQ(deep.folded, 1u);
  EXPECT_LE(deep.fold_det, 0);
  EXPECT_GT(deep.fold[0], 0.52);
  EXPECT_LT(deep.fold[0], 0.54);
  EXPECT_NEAR(deep.fold_det, det_at(epsilon, c, deep.fold[0]), 1e-12);
}

TEST(FoldCertificate, TheSameVerdictsOnOneThread) {
  SolidSpline spline;
  spline.basis = tensor_basis(12);
  for (const auto& g : greville_points(spline.basis))  // a twist: folds near one corner
    spline.geometry.push_back({g[0] + 0.6 * std::sin(3 * g[1] * g[2]), g[1] + 0.5 * g[0] * g[0],
                               g[2] - 0.8 * g[0] * g[1]});
  const FoldCertificate many = certify_fold_free(spline);
  tbb::global_control one(tbb::global_control::max_allowed_parallelism, 1);
  const FoldCertificate single = certify_fold_free(spline);
  EXPECT_GT(many.folded, 0u);
  EXPECT_EQ(many.proven + many.folded + many.undecided, many.elements);
  EXPECT_EQ(single.proven, many.proven);
  EXPECT_EQ(single.folded, many.folded);
  EXPECT_EQ(single.boxes, many.boxes);
  EXPECT_EQ(single.fold, many.fold);
}

TEST(FoldCertificate, RefusesASplineWithoutControlPoints) {
  SolidSpline spline;
  spline.basis = tensor_basis(4);
  EXPECT_THROW(certify_fold_free(spline), InputError);
}

}  // namespace
}  // namespace tpmsfill
