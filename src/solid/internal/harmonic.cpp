// The P1 harmonic extension (harmonic.hpp), with Eigen.
#define EIGEN_NO_DEBUG 1  // Eigen's checks abort() rather than throw: leave them out
#include "solid/internal/harmonic.hpp"

#include "tpmsfill/error.hpp"

#if defined(CGAL_EIGEN3_ENABLED)
#include <Eigen/Dense>
#include <Eigen/SparseCholesky>

namespace tpmsfill::detail {

namespace {

// The P1 stiffness of one tet: V ∇λ_a · ∇λ_b. False when the tet has no volume.
bool tet_stiffness(const TetMesh& mesh, const Tet& t, Eigen::Matrix4d& k) {
  Eigen::Matrix3d edges;
  for (int r = 0; r < 3; ++r) {
    const Vec3 e = mesh.points[t[r + 1]] - mesh.points[t[0]];
    edges.row(r) << e.x, e.y, e.z;
  }
  const double det = edges.determinant();
  if (!(det > 0)) return false;
  const Eigen::Matrix3d inverse = edges.inverse();  // column r: ∇λ_{r+1}
  Eigen::Matrix<double, 3, 4> grad;
  grad.rightCols<3>() = inverse;
  grad.col(0) = -inverse.rowwise().sum();
  k = (det / 6) * grad.transpose() * grad;
  return true;
}

}  // namespace

std::uint64_t harmonic_extension(const TetMesh& mesh, const std::vector<char>& fixed, int columns,
                                 std::vector<double>& values) {
  std::vector<std::int64_t> unknown(mesh.points.size(), -1);
  std::int64_t n = 0;
  for (const Tet& t : mesh.tets)
    for (std::uint32_t v : t)
      if (!fixed[v] && unknown[v] < 0) unknown[v] = n++;
  if (n == 0) return 0;
  std::vector<Eigen::Triplet<double>> entries;
  entries.reserve(mesh.tets.size() * 10);
  Eigen::MatrixXd rhs = Eigen::MatrixXd::Zero(n, columns);
  Eigen::Matrix4d k;
  for (const Tet& t : mesh.tets) {
    if (!tet_stiffness(mesh, t, k)) continue;
    for (int a = 0; a < 4; ++a) {
      const std::int64_t row = unknown[t[a]];
      if (row < 0) continue;
      for (int b = 0; b < 4; ++b) {
        const std::int64_t col = unknown[t[b]];
        if (col >= 0) {
          if (col <= row) entries.emplace_back(row, col, k(a, b));  // the lower half
        } else {
          for (int c = 0; c < columns; ++c)
            rhs(row, c) -= k(a, b) * values[std::size_t(t[b]) * columns + c];
        }
      }
    }
  }
  Eigen::SparseMatrix<double> matrix(n, n);
  matrix.setFromTriplets(entries.begin(), entries.end());
  Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>, Eigen::Lower> solver;
  solver.compute(matrix);
  if (solver.info() != Eigen::Success)
    throw InputError("the harmonic system of the interior could not be factored");
  const Eigen::MatrixXd solution = solver.solve(rhs);
  for (std::size_t v = 0; v < unknown.size(); ++v)
    if (unknown[v] >= 0)
      for (int c = 0; c < columns; ++c) values[v * columns + c] = solution(unknown[v], c);
  return static_cast<std::uint64_t>(n);
}

}  // namespace tpmsfill::detail

#else

namespace tpmsfill::detail {

std::uint64_t harmonic_extension(const TetMesh&, const std::vector<char>&, int,
                                 std::vector<double>&) {
  throw InputError("this tpmsfill was built without Eigen, which harmonic maps need");
}

}  // namespace tpmsfill::detail

#endif
