// The Dirichlet solve and the mean-value operator (dirichlet.hpp), with Eigen.
#define EIGEN_NO_DEBUG 1  // Eigen's checks abort() rather than throw: leave them out
#include "mesh/dirichlet.hpp"

#include <algorithm>

#include "core/disjoint_sets.hpp"
#include "tpmsfill/error.hpp"

#if defined(CGAL_EIGEN3_ENABLED)
#include <Eigen/Dense>
#include <Eigen/SparseCholesky>
#include <Eigen/SparseLU>
#endif

namespace tpmsfill::detail {

namespace {

// tan(θ/2) for the angle θ between e1 and e2, as |e1 × e2| / (|e1||e2| + e1 · e2).
double half_angle_tangent(Vec3 e1, Vec3 e2) {
  const double scale = norm(e1) * norm(e2);
  return norm(cross(e1, e2)) / std::max(scale + dot(e1, e2), 1e-30 * scale);
}

}  // namespace

Operator mean_value_operator(const std::vector<Vec3>& points,
                             const std::vector<Triangle>& triangles,
                             const std::vector<std::uint32_t>& which) {
  return [&points, &triangles, which](const EmitEntry& emit) {
    auto corners = [&](const Triangle& t) {
      for (int i = 0; i < 3; ++i) {
        const Vec3 xi = points[t[i]];
        const std::uint32_t j = t[(i + 1) % 3], k = t[(i + 2) % 3];
        const double tangent = half_angle_tangent(points[j] - xi, points[k] - xi);
        for (std::uint32_t other : {j, k}) {
          const double w = tangent / norm(points[other] - xi);
          emit(t[i], t[i], -w);
          emit(t[i], other, w);
        }
      }
    };
    if (which.empty())
      for (const Triangle& t : triangles) corners(t);
    else
      for (std::uint32_t f : which) corners(triangles[f]);
  };
}

#if defined(CGAL_EIGEN3_ENABLED)

std::uint64_t solve_dirichlet(const Operator& op, Symmetry symmetry, const std::vector<char>& fixed,
                              int columns, std::vector<double>& values,
                              const std::string& singular) {
  std::vector<std::int64_t> unknown(fixed.size(), -1);
  std::vector<std::uint32_t> points;  // of the unknowns, in their order
  // Pieces of free points joined by entries, and whether an entry ties each to a fixed point:
  // one that is not has no unique solution (the pivot a factorization finds there is only
  // rounding, so it would not say).
  DisjointSets pieces(fixed.size());
  std::vector<char> anchored(fixed.size(), 0);
  op([&](std::uint32_t row, std::uint32_t col, double) {
    for (std::uint32_t v : {row, col})
      if (!fixed[v] && unknown[v] < 0) {
        unknown[v] = static_cast<std::int64_t>(points.size());
        points.push_back(v);
      }
    if (!fixed[row] && !fixed[col])
      pieces.unite(row, col);
    else if (fixed[row] != fixed[col])
      anchored[fixed[row] ? col : row] = 1;
  });
  const auto n = static_cast<Eigen::Index>(points.size());
  if (n == 0) return 0;
  for (std::uint32_t v : points)
    if (anchored[v]) anchored[pieces.find(v)] = 1;
  for (std::uint32_t v : points)
    if (!anchored[pieces.find(v)]) throw InputError(singular);
  std::vector<Eigen::Triplet<double>> entries;
  Eigen::MatrixXd rhs = Eigen::MatrixXd::Zero(n, columns);
  op([&](std::uint32_t row, std::uint32_t col, double value) {
    const std::int64_t r = unknown[row], c = unknown[col];
    if (r < 0) return;
    if (c < 0) {
      for (int k = 0; k < columns; ++k) rhs(r, k) -= value * values[std::size_t(col) * columns + k];
    } else if (symmetry == Symmetry::General || c <= r) {  // symmetric: the lower half
      entries.emplace_back(r, c, value);
    }
  });
  Eigen::SparseMatrix<double> matrix(n, n);
  matrix.setFromTriplets(entries.begin(), entries.end());
  entries = {};
  auto solved = [&](auto& solver) {
    solver.compute(matrix);
    if (solver.info() != Eigen::Success) throw InputError(singular);
    const Eigen::MatrixXd solution = solver.solve(rhs);
    for (Eigen::Index i = 0; i < n; ++i)
      for (int k = 0; k < columns; ++k)
        values[std::size_t(points[i]) * columns + k] = solution(i, k);
    return static_cast<std::uint64_t>(n);
  };
  if (symmetry == Symmetry::Symmetric) {
    Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>, Eigen::Lower> solver;
    return solved(solver);
  }
  Eigen::SparseLU<Eigen::SparseMatrix<double>> solver;
  return solved(solver);
}

#else

std::uint64_t solve_dirichlet(const Operator&, Symmetry, const std::vector<char>&, int,
                              std::vector<double>&, const std::string&) {
  throw InputError(
      "this tpmsfill was built without Eigen, which harmonic and mean-value maps need");
}

#endif

}  // namespace tpmsfill::detail
