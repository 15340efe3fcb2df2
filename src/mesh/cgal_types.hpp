/// @file cgal_types.hpp
/// @brief The CGAL kernel and mesh types tpmsfill uses internally. Never include this from a
/// public header: CGAL stays behind the library's plain-data interface.
#pragma once

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Surface_mesh.h>

#include "tpmsfill/types.hpp"

namespace tpmsfill::detail {

/// Exact predicates, double constructions: every yes/no decision is exact.
using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using Point3 = Kernel::Point_3;
using SurfaceMesh = CGAL::Surface_mesh<Point3>;

inline Point3 to_cgal(Vec3 p) {
  return {p.x, p.y, p.z};
}

}  // namespace tpmsfill::detail
