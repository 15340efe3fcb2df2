/// @file material.hpp
/// @brief Stage "material" of the material pipeline (Li & Fu 2021, §4): a material value
/// for every point of a tet mesh, from the functions of Li & Fu 2021 and others users define
/// it by.
///
///  - distance_material: the Euclidean distance to a point (e.g. a material that grows from
///    one point);
///  - geodesic_material: the geodesic distance to a set of boundary points (e.g. a femur's
///    distance to its bottom face), by the heat method on the boundary surface (Crane et al.
///    2013, CGAL's Heat_method_3) and the P1 harmonic extension inside (the same system as the
///    cube map's interior);
///  - ramp_material: a Ramp (design.hpp: linear along a direction or radial from an axis);
///  - volume_material: a CT or any scalar volume (volume.hpp), sampled trilinearly.
///
/// Every function returns one finite value per point of the mesh (points in no tet included),
/// to be stored as TetMesh::material.
#pragma once

#include <cstdint>
#include <vector>

#include "tpmsfill/io/volume.hpp"
#include "tpmsfill/lattice/design.hpp"
#include "tpmsfill/solid/tet_mesh.hpp"

namespace tpmsfill {

/// |p − centre| per point, mm.
std::vector<double> distance_material(const TetMesh& mesh, Vec3 centre);

/// The boundary points within `depth` mm of the mesh's lowest point along `up` (its bottom
/// face when `up` points away from it): the source set for geodesic_material when a part is
/// graded from its bottom face (as Li & Fu 2021 grade a femur).
/// @throws InputError  `up` is zero or not finite, depth < 0
std::vector<std::uint32_t> bottom_boundary_points(const TetMesh& mesh, Vec3 up, double depth);

/// The geodesic distance to `sources` (boundary point ids), mm: the heat method on the
/// boundary surface (on its intrinsic Delaunay triangulation, which keeps it accurate on thin
/// triangles), the sources at exactly 0 and nothing below 0, then the harmonic extension of
/// the boundary values into the interior.
/// @pre tets positive, boundary a closed 2-manifold (check_tet_mesh, ball_problem)
/// @throws InputError  no sources, a source that is not a boundary point, a boundary that is
///                     not a closed 2-manifold
std::vector<double> geodesic_material(const TetMesh& mesh,
                                      const std::vector<std::uint32_t>& sources);

/// The ramp's value at each point (start at ramp coordinate `from`, end at `to`, constant
/// beyond). Unset from / to / point are taken from the mesh's bounding box as fill's designs
/// take them from the model's (linear: the box's extent along the axis; radial: 0 at the box
/// centre to the farthest corner).
/// @throws InputError  a Depth ramp (tets have no occupancy grid), a zero linear axis,
///                     from == to
std::vector<double> ramp_material(const TetMesh& mesh, const Ramp& ramp);

/// The volume's values interpolated trilinearly between its cell centres at each point;
/// points beyond the outermost centres take the nearest border value.
/// @param[out] outside  when given: how many points lie outside the volume's box (their
///                      values are extrapolated as constant; a caller should say so)
/// @throws InputError  the volume has no physical size (spacing), or no values
std::vector<double> volume_material(const TetMesh& mesh, const ScalarVolume& volume,
                                    std::uint64_t* outside = nullptr);

}  // namespace tpmsfill
