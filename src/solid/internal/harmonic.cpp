// The P1 harmonic extension (harmonic.hpp): the tets' stiffness (Eigen), solved by the one
// Dirichlet solve (mesh/dirichlet.hpp).
#define EIGEN_NO_DEBUG 1  // Eigen's checks abort() rather than throw: leave them out
#include "solid/internal/harmonic.hpp"

#include "mesh/dirichlet.hpp"
#include "tpmsfill/error.hpp"

#if defined(CGAL_EIGEN3_ENABLED)
#include <Eigen/Dense>

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
  const Operator stiffness = [&mesh](const EmitEntry& emit) {
    Eigen::Matrix4d k;
    for (const Tet& t : mesh.tets)
      if (tet_stiffness(mesh, t, k))
        for (int a = 0; a < 4; ++a)
          for (int b = 0; b < 4; ++b) emit(t[a], t[b], k(a, b));
  };
  return solve_dirichlet(stiffness, Symmetry::Symmetric, fixed, columns, values,
                         "the harmonic system of the interior could not be factored");
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
