// Stage "material" (material.hpp): a material value per tet-mesh point.
#include "tpmsfill/material.hpp"

#include <algorithm>
#include <cmath>
#include <string>

#include "solid/internal/harmonic.hpp"
#include "tpmsfill/error.hpp"

#if defined(CGAL_EIGEN3_ENABLED)
#include <CGAL/Heat_method_3/Surface_mesh_geodesic_distances_3.h>

#include "mesh/cgal_types.hpp"
#endif

namespace tpmsfill {

namespace {

// Geodesic distances on the boundary surface from `sources`, per mesh point (0 off it).
std::vector<double> boundary_geodesics(const TetMesh& mesh, const std::vector<Triangle>& faces,
                                       const std::vector<std::uint32_t>& sources);

}  // namespace

std::vector<double> distance_material(const TetMesh& mesh, Vec3 centre) {
  std::vector<double> values;
  values.reserve(mesh.points.size());
  for (const Vec3& p : mesh.points) values.push_back(norm(p - centre));
  return values;
}

std::vector<std::uint32_t> bottom_boundary_points(const TetMesh& mesh, Vec3 up, double depth) {
  const double length = norm(up);
  if (!(length > 0) || !std::isfinite(length))
    throw InputError("the up direction must be a non-zero vector");
  if (!(depth >= 0) || !std::isfinite(depth))
    throw InputError("the bottom's depth must be a number of mm >= 0");
  const Vec3 u = (1 / length) * up;
  const TriangleSoup boundary = tet_boundary(mesh);
  std::vector<char> on_boundary(mesh.points.size(), 0);
  double lowest = HUGE_VAL;
  for (const Triangle& t : boundary.triangles)
    for (std::uint32_t v : t) {
      on_boundary[v] = 1;
      lowest = std::min(lowest, dot(mesh.points[v], u));
    }
  std::vector<std::uint32_t> points;
  for (std::uint32_t v = 0; v < mesh.points.size(); ++v)
    if (on_boundary[v] && dot(mesh.points[v], u) <= lowest + depth) points.push_back(v);
  return points;
}

std::vector<double> geodesic_material(const TetMesh& mesh,
                                      const std::vector<std::uint32_t>& sources) {
  if (sources.empty()) throw InputError("the geodesic material needs at least one source point");
  const std::vector<Triangle> faces = tet_boundary(mesh).triangles;
  std::vector<char> fixed(mesh.points.size(), 0);
  for (const Triangle& t : faces)
    for (std::uint32_t v : t) fixed[v] = 1;
  for (std::uint32_t s : sources)
    if (s >= mesh.points.size() || !fixed[s])
      throw InputError("geodesic source " + std::to_string(s) + " is not a boundary point");
  std::vector<double> values = boundary_geodesics(mesh, faces, sources);
  detail::harmonic_extension(mesh, fixed, 1, values);
  return values;
}

std::vector<double> ramp_material(const TetMesh& mesh, const Ramp& ramp) {
  if (ramp.shape == RampShape::Depth)
    throw InputError("a material cannot follow depth (use a linear or radial ramp)");
  if (ramp.shape == RampShape::Linear && !(norm(ramp.axis) > 0))
    throw InputError("a linear ramp needs a non-zero direction");
  Box3 bounds;  // of the points in tets, as check_tet_mesh() gives it
  for (const Tet& t : mesh.tets)
    for (std::uint32_t v : t) bounds.extend(mesh.points[v]);
  const Ramp resolved = resolve_ramp(ramp, bounds, "material ramp");
  std::vector<double> values;
  values.reserve(mesh.points.size());
  for (const Vec3& p : mesh.points) values.push_back(ramp_value(resolved, p));
  return values;
}

std::vector<double> volume_material(const TetMesh& mesh, const ScalarVolume& volume,
                                    std::uint64_t* outside) {
  if (!volume.has_physical_size())
    throw InputError("the volume has no physical size (spacing): it cannot be placed in mm");
  if (volume.values.empty() || volume.count() != volume.values.size())
    throw InputError("the volume has no values");
  std::vector<double> values(mesh.points.size());
  std::uint64_t beyond = 0;
  for (std::size_t v = 0; v < mesh.points.size(); ++v) {
    bool out = false;
    values[v] = sample_volume(volume, mesh.points[v], &out);
    beyond += out;
  }
  if (outside) *outside = beyond;
  return values;
}

namespace {

#if defined(CGAL_EIGEN3_ENABLED)
std::vector<double> boundary_geodesics(const TetMesh& mesh, const std::vector<Triangle>& faces,
                                       const std::vector<std::uint32_t>& sources) {
  using detail::SurfaceMesh;
  SurfaceMesh surface;
  std::vector<SurfaceMesh::Vertex_index> vertex(mesh.points.size());
  std::vector<char> added(mesh.points.size(), 0);
  for (const Triangle& t : faces)
    for (std::uint32_t v : t)
      if (!added[v]) {
        added[v] = 1;
        vertex[v] = surface.add_vertex(detail::to_cgal(mesh.points[v]));
      }
  for (const Triangle& t : faces)
    if (surface.add_face(vertex[t[0]], vertex[t[1]], vertex[t[2]]) == SurfaceMesh::null_face())
      throw InputError("the boundary is not a closed 2-manifold; the geodesic material needs one");
  auto distance =
      surface.add_property_map<SurfaceMesh::Vertex_index, double>("v:distance", 0).first;
  CGAL::Heat_method_3::Surface_mesh_geodesic_distances_3<SurfaceMesh,
                                                         CGAL::Heat_method_3::Intrinsic_Delaunay>
      heat(surface);
  for (std::uint32_t s : sources) heat.add_source(vertex[s]);
  heat.estimate_geodesic_distances(distance);
  std::vector<double> values(mesh.points.size(), 0.0);
  for (std::uint32_t v = 0; v < mesh.points.size(); ++v)
    if (added[v]) values[v] = std::max(0.0, distance[vertex[v]]);
  for (std::uint32_t s : sources) values[s] = 0;
  return values;
}
#else
std::vector<double> boundary_geodesics(const TetMesh&, const std::vector<Triangle>&,
                                       const std::vector<std::uint32_t>&) {
  throw InputError("this tpmsfill was built without Eigen, which the geodesic material needs");
}
#endif

}  // namespace

}  // namespace tpmsfill
