// The one Dirichlet solve (mesh/dirichlet.hpp) behind the surface layout, the cube map and the
// material's interior: both weightings reproduce what they must (mean-value coordinates and P1
// stiffness have linear precision), columns are independent, and an operator with a piece
// that touches no fixed point is refused.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "mesh/dirichlet.hpp"
#include "solid/internal/harmonic.hpp"
#include "test_util.hpp"
#include "tpmsfill/error.hpp"

using namespace tpmsfill;

namespace {

// A flat n x n grid of the square [0, L]^2 at height z0, interior points jittered, its
// boundary points fixed.
struct FlatDisk {
  TriangleSoup mesh;
  std::vector<char> boundary;
};

FlatDisk flat_disk(int n, double L, Vec3 offset, unsigned seed) {
  FlatDisk d;
  d.mesh = test::make_height_field(n, L, [](double, double) { return 0.0; });
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> jitter(-0.3, 0.3);
  const double h = L / n;
  for (Vec3& p : d.mesh.points) {
    const bool edge = p.x == 0 || p.y == 0 || p.x == L || p.y == L;
    d.boundary.push_back(edge);
    if (!edge) p = p + Vec3{jitter(rng) * h, jitter(rng) * h, 0};
    p = p + offset;
  }
  return d;
}

}  // namespace

// Mean-value coordinates reproduce linear functions on a flat mesh, however irregular and
// wherever it sits: the solution is exact up to rounding.
TEST(Dirichlet, MeanValueReproducesLinearFunctionsOnAFlatMesh) {
  for (const Vec3 offset : {Vec3{0, 0, 0}, Vec3{150, -80, 20}, Vec3{-1e4, 3e3, 0}}) {
    const FlatDisk d = flat_disk(12, 10.0, offset, 7);
    auto f = [&](Vec3 p, int k) {
      const Vec3 q = p - offset;
      return k == 0 ? 0.3 * q.x - 1.7 * q.y + 2 : 4.0 * q.y + 0.5 * q.x;
    };
    std::vector<double> values(2 * d.mesh.points.size(), 0.0);
    for (std::size_t v = 0; v < d.mesh.points.size(); ++v)
      if (d.boundary[v])
        for (int k = 0; k < 2; ++k) values[2 * v + k] = f(d.mesh.points[v], k);
    const std::uint64_t solved =
        detail::solve_dirichlet(detail::mean_value_operator(d.mesh.points, d.mesh.triangles),
                                detail::Symmetry::General, d.boundary, 2, values, "singular");
    EXPECT_EQ(solved, 11u * 11u);
    for (std::size_t v = 0; v < d.mesh.points.size(); ++v)
      for (int k = 0; k < 2; ++k)
        EXPECT_NEAR(values[2 * v + k], f(d.mesh.points[v], k), 1e-9) << "point " << v;
  }
}

// Columns are solved independently: two at once give what each gives alone, and values of
// points the operator does not name are left as they are.
TEST(Dirichlet, ColumnsAreIndependentAndUnnamedPointsUntouched) {
  FlatDisk d = flat_disk(8, 4.0, {0, 0, 0}, 3);
  const std::size_t np = d.mesh.points.size();
  d.mesh.points.push_back({99, 99, 99});  // in no triangle
  d.boundary.push_back(0);
  std::vector<double> both(2 * (np + 1), 0.0), first(np + 1, 0.0), second(np + 1, 0.0);
  for (std::size_t v = 0; v < np; ++v)
    if (d.boundary[v]) {
      const Vec3 p = d.mesh.points[v];
      first[v] = both[2 * v] = std::sin(p.x) * std::cos(p.y);
      second[v] = both[2 * v + 1] = p.x * p.y;
    }
  both[2 * np] = both[2 * np + 1] = first[np] = second[np] = -5;
  const detail::Operator op = detail::mean_value_operator(d.mesh.points, d.mesh.triangles);
  detail::solve_dirichlet(op, detail::Symmetry::General, d.boundary, 2, both, "singular");
  detail::solve_dirichlet(op, detail::Symmetry::General, d.boundary, 1, first, "singular");
  detail::solve_dirichlet(op, detail::Symmetry::General, d.boundary, 1, second, "singular");
  for (std::size_t v = 0; v <= np; ++v) {
    EXPECT_NEAR(both[2 * v], first[v], 1e-12);
    EXPECT_NEAR(both[2 * v + 1], second[v], 1e-12);
  }
  EXPECT_EQ(both[2 * np], -5);
  EXPECT_EQ(both[2 * np + 1], -5);
  // A maximum principle: harmonic-like values stay within the boundary's range.
  for (std::size_t v = 0; v < np; ++v) EXPECT_LE(std::fabs(first[v]), 1.0 + 1e-12);
}

// The P1 stiffness (solid/internal/harmonic) through the same solve reproduces linear
// functions on a jittered tet grid, in three columns.
TEST(Dirichlet, P1HarmonicReproducesLinearFunctionsOnTets) {
  const TetMesh mesh = test::make_tet_grid({-20, 5, 100}, {-14, 9, 105}, {6, 4, 5}, 0.25);
  std::vector<char> fixed(mesh.points.size(), 0);
  std::vector<double> values(3 * mesh.points.size(), 0.0);
  auto f = [](Vec3 p, int k) { return k == 0 ? p.x - 2 * p.z : k == 1 ? 3 * p.y + 1 : p.z; };
  for (std::size_t v = 0; v < mesh.points.size(); ++v) {
    const Vec3 p = mesh.points[v];
    fixed[v] = p.x == -20 || p.x == -14 || p.y == 5 || p.y == 9 || p.z == 100 || p.z == 105;
    if (fixed[v])
      for (int k = 0; k < 3; ++k) values[3 * v + k] = f(p, k);
  }
  EXPECT_GT(detail::harmonic_extension(mesh, fixed, 3, values), 0u);
  for (std::size_t v = 0; v < mesh.points.size(); ++v)
    for (int k = 0; k < 3; ++k) EXPECT_NEAR(values[3 * v + k], f(mesh.points[v], k), 1e-9);
}

// A piece of the mesh with no fixed point has no unique solution: refused with the caller's
// words, and nothing is written.
TEST(Dirichlet, APieceWithoutFixedPointsIsRefused) {
  const FlatDisk a = flat_disk(4, 1.0, {0, 0, 0}, 1), b = flat_disk(4, 1.0, {5, 0, 0}, 2);
  const TriangleSoup two = test::concat(a.mesh, b.mesh);
  std::vector<char> fixed = a.boundary;
  fixed.resize(two.points.size(), 0);  // the second piece: nothing fixed
  std::vector<double> values(two.points.size(), 1.0);
  const std::vector<double> before = values;
  try {
    detail::solve_dirichlet(detail::mean_value_operator(two.points, two.triangles),
                            detail::Symmetry::General, fixed, 1, values, "no fixed point here");
    FAIL() << "solved a singular system";
  } catch (const InputError& e) {
    EXPECT_STREQ(e.what(), "no fixed point here");
  }
  EXPECT_EQ(values, before);
}
