/// @file dirichlet.hpp
/// @brief The one linear solve behind every map made by harmonic or mean-value coordinates: a
/// surface onto the unit square (surface/parameterize), a cube map's boundary patches onto the
/// cube's faces and its interior (solid/cube_map), a material's interior (solid/material).
/// Each builds its operator (mean_value_operator() here, the P1 stiffness in
/// solid/internal/harmonic); this solves it.
///
/// The discrete Dirichlet problem: Σ_j L_ij f_j = 0 at every free point i, f given at the fixed
/// points, for several columns of f at once. Rows of fixed points are ignored; the columns of
/// fixed points move to the right-hand side. Unknowns are numbered in order of first appearance
/// (as row or column) in the operator's entries, so one assembly order gives one answer. A
/// symmetric operator is factored by sparse Cholesky (Eigen's SimplicialLDLT, lower half), any
/// other by sparse LU.
#pragma once

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "tpmsfill/types.hpp"

namespace tpmsfill::detail {

/// Called with one entry L_row,col of an operator (point numbers); entries at one position add.
using EmitEntry = std::function<void(std::uint32_t row, std::uint32_t col, double value)>;
/// Calls its argument for every entry of the operator, in one fixed order each time it runs.
using Operator = std::function<void(const EmitEntry&)>;

enum class Symmetry { Symmetric, General };

/// Solves the Dirichlet problem of `op` (run twice: once to number the unknowns, once to
/// assemble).
/// @param[in]     fixed    per point: its values are given
/// @param[in,out] values   `columns` values per point (point-major): read at fixed points,
///                         written at the free points the entries name; others are left as
///                         they are
/// @param[in]     singular what is wrong, for the InputError thrown when L cannot be factored
/// @return the number of points solved for
/// @throws InputError  L cannot be factored (a piece of the mesh has no fixed point, or its
///                     triangles are degenerate), or tpmsfill was built without Eigen
std::uint64_t solve_dirichlet(const Operator& op, Symmetry symmetry, const std::vector<char>& fixed,
                              int columns, std::vector<double>& values,
                              const std::string& singular);

/// The mean-value coordinates (Floater 2003) of a triangle mesh as an operator: for every
/// corner i of a listed triangle and its other corners j, k, with θ the angle at i,
/// L_ij += w, L_ii −= w for w = tan(θ/2) / |x_j − x_i| (and likewise for k), so row i sums
/// (tan(α/2) + tan(β/2)) / r_ij over the triangles at edge ij. Asymmetric.
/// @param[in] which  indices into `triangles` to use (copied); all when empty
/// @pre points and triangles outlive the operator
Operator mean_value_operator(const std::vector<Vec3>& points,
                             const std::vector<Triangle>& triangles,
                             const std::vector<std::uint32_t>& which = {});

}  // namespace tpmsfill::detail
