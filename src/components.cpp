// Stage "components": union-find over point indices (detail::triangle_components), then one
// serial pass in triangle order for sizes, volumes and areas.
#include "tpmsfill/components.hpp"

#include "detail/index_limits.hpp"
#include "detail/mesh_measures.hpp"
#include "detail/soup_indices.hpp"
#include "detail/soup_topology.hpp"
#include "tpmsfill/error.hpp"

namespace tpmsfill {

Components mesh_components(const TriangleSoup& mesh) {
  detail::require_32bit_mesh(mesh, "validate");
  detail::TriangleComponents labels = detail::triangle_components(mesh);
  Components c;
  c.triangle_component = std::move(labels.of_triangle);
  c.info.resize(labels.count);
  const Vec3 centre = detail::box_centre(mesh, detail::used_points(mesh));
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
    Components::Info& info = c.info[c.triangle_component[t]];
    if (info.triangles++ == 0) info.first_triangle = static_cast<std::uint32_t>(t);
    info.volume += detail::six_volume(mesh, mesh.triangles[t], centre) / 6;
    info.area += detail::double_area(mesh, mesh.triangles[t]) / 2;
  }
  return c;
}

TriangleSoup keep_components(const TriangleSoup& mesh, const Components& components,
                             const std::vector<bool>& keep) {
  detail::require_indices_in_range(mesh);
  bool fits = components.triangle_component.size() == mesh.triangles.size() &&
              keep.size() == components.info.size();
  for (std::size_t t = 0; fits && t < mesh.triangles.size(); ++t)
    fits = components.triangle_component[t] < keep.size();
  if (!fits)
    throw InputError("keep_components: the components or the keep flags do not fit the mesh");
  std::vector<std::uint32_t> new_index(mesh.points.size(), detail::kNoIndex);
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t)
    if (keep[components.triangle_component[t]])
      for (std::uint32_t v : mesh.triangles[t]) new_index[v] = 0;
  TriangleSoup out;
  for (std::size_t i = 0; i < mesh.points.size(); ++i)
    if (new_index[i] != detail::kNoIndex) {
      new_index[i] = static_cast<std::uint32_t>(out.points.size());
      out.points.push_back(mesh.points[i]);
    }
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t)
    if (keep[components.triangle_component[t]]) {
      const Triangle& tri = mesh.triangles[t];
      out.triangles.push_back({new_index[tri[0]], new_index[tri[1]], new_index[tri[2]]});
    }
  return out;
}

}  // namespace tpmsfill
