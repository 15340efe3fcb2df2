/// @file harmonic.hpp
/// @brief Internal: the P1 finite-element harmonic extension over a tet mesh, shared by the
/// cube map's interior (cube_map.cpp) and the geodesic material's interior (material.cpp).
///
/// K_ij = Σ_T V_T ∇λ_i · ∇λ_j over the tets T at edge ij (∇λ_i = −S_i n_i / (3 V_T), the
/// gradient form of seed 001's eq. 4), and K_II f_I = −K_IB f_B solved by one sparse Cholesky
/// factorization (Eigen's SimplicialLDLT) for every column of values. Linear functions are
/// reproduced exactly: they are P1-harmonic.
#pragma once

#include <cstdint>
#include <vector>

#include "tpmsfill/solid/tet_mesh.hpp"

namespace tpmsfill::detail {

/// Replaces the values of the points in a tet that are not `fixed` by the harmonic extension
/// of the fixed ones. `values` holds `columns` values per point (point-major); the values of
/// fixed points are read, those of points in no tet are left as they are.
/// @pre tets positive (tets with no volume add nothing)
/// @return the number of points solved for
/// @throws InputError  the system cannot be factored (no fixed point in a piece of the mesh)
std::uint64_t harmonic_extension(const TetMesh& mesh, const std::vector<char>& fixed, int columns,
                                 std::vector<double>& values);

}  // namespace tpmsfill::detail
