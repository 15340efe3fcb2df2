/// @file exact_orientation.hpp
/// @brief Internal: the signs of the 2D and 3D orientation determinants, exact (CGAL Epick's
/// filtered predicates) behind a plain-data interface, so the stages that only need these
/// decisions (tet checks, parameterization flips) do not compile CGAL.
#pragma once

#include <array>

#include "tpmsfill/types.hpp"

namespace tpmsfill::detail {

/// sign((b − a) · ((c − a) × (d − a))): +1 when d sees a, b, c counter-clockwise, 0 when the
/// four points are coplanar, −1 otherwise. Exact for the doubles given.
int orientation_3(Vec3 a, Vec3 b, Vec3 c, Vec3 d);

/// sign((b − a) × (c − a)) in the plane: +1 counter-clockwise, 0 collinear, −1 clockwise.
int orientation_2(std::array<double, 2> a, std::array<double, 2> b, std::array<double, 2> c);

}  // namespace tpmsfill::detail
