// Step 7 of stage "repair": CGAL's 3D alpha wrap of a soup (see repair/internal/alpha_wrap.hpp).
// CGAL's checks stay on (as in repair.cpp): a failure is a CGAL::Failure_exception the caller
// catches, not a crash.
#define CGAL_DEBUG 1
#include <CGAL/alpha_wrap_3.h>

#include <array>
#include <vector>

#include "core/index_limits.hpp"
#include "mesh/cgal_types.hpp"
#include "mesh/soup_indices.hpp"
#include "repair/internal/alpha_wrap.hpp"

namespace tpmsfill::detail {

TriangleSoup alpha_wrap(const TriangleSoup& soup, double alpha, double offset) {
  std::vector<Point3> points;
  points.reserve(soup.points.size());
  for (const Vec3& p : soup.points) points.push_back(to_cgal(p));
  std::vector<std::array<std::size_t, 3>> faces;
  faces.reserve(soup.triangles.size());
  for (const Triangle& t : soup.triangles)
    if (!repeated_corner(t)) faces.push_back({t[0], t[1], t[2]});

  SurfaceMesh wrap;
  if (!faces.empty()) CGAL::alpha_wrap_3(points, faces, alpha, offset, wrap);

  TriangleSoup out;
  out.points.reserve(wrap.number_of_vertices());
  std::vector<std::uint32_t> index(wrap.num_vertices(), kNoIndex);
  for (SurfaceMesh::Vertex_index v : wrap.vertices()) {
    index[v.idx()] = static_cast<std::uint32_t>(out.points.size());
    const Point3& p = wrap.point(v);
    out.points.push_back({p.x(), p.y(), p.z()});
  }
  out.triangles.reserve(wrap.number_of_faces());
  for (SurfaceMesh::Face_index f : wrap.faces()) {
    Triangle t{};
    int k = 0;
    for (SurfaceMesh::Vertex_index v : CGAL::vertices_around_face(wrap.halfedge(f), wrap))
      if (k < 3) t[k++] = index[v.idx()];
    out.triangles.push_back(t);
  }
  return out;
}

}  // namespace tpmsfill::detail
