// Stage "components": union-find over point indices (detail::triangle_components), then one
// serial pass in triangle order for sizes, volumes and areas. keep_components marks what it
// keeps in parallel and moves it down in place, in order.
#include "tpmsfill/mesh/components.hpp"

#include <atomic>

#include "core/index_limits.hpp"
#include "core/parallel.hpp"
#include "mesh/mesh_measures.hpp"
#include "mesh/soup_indices.hpp"
#include "mesh/soup_topology.hpp"
#include "tpmsfill/error.hpp"

namespace tpmsfill {
namespace {

constexpr std::size_t kChunk = 1 << 16;  // items per fixed chunk of the parallel loops

}  // namespace

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

namespace {

// Which triangles and points keep_components keeps.
struct Kept {
  std::vector<std::uint8_t> point;
  std::vector<std::size_t> point_at, triangle_at;  // compaction offsets
};

Kept kept_parts(const TriangleSoup& mesh, const Components& components,
                const std::vector<bool>& keep) {
  detail::require_indices_in_range(mesh);
  bool fits = components.triangle_component.size() == mesh.triangles.size() &&
              keep.size() == components.info.size();
  for (std::size_t t = 0; fits && t < mesh.triangles.size(); ++t)
    fits = components.triangle_component[t] < keep.size();
  if (!fits)
    throw InputError("keep_components: the components or the keep flags do not fit the mesh");
  // A point lies in one component (components join the points of each triangle): it is kept
  // when a kept triangle uses it. Every writer stores the same 1.
  const std::size_t nt = mesh.triangles.size(), np = mesh.points.size();
  auto kept_triangle = [&](std::size_t t) { return keep[components.triangle_component[t]]; };
  Kept k;
  k.point.assign(np, 0);
  detail::parallel_for(nt, kChunk, [&](std::size_t b, std::size_t e) {
    for (std::size_t t = b; t < e; ++t)
      if (kept_triangle(t))
        for (std::uint32_t v : mesh.triangles[t])
          std::atomic_ref<std::uint8_t>(k.point[v]).store(1, std::memory_order_relaxed);
  });
  k.point_at =
      detail::compaction_offsets(np, kChunk, [&](std::size_t i) { return k.point[i] != 0; });
  k.triangle_at = detail::compaction_offsets(nt, kChunk, kept_triangle);
  return k;
}

}  // namespace

TriangleSoup keep_components(const TriangleSoup& mesh, const Components& components,
                             const std::vector<bool>& keep) {
  return keep_components(TriangleSoup(mesh), components, keep);
}

TriangleSoup keep_components(TriangleSoup&& mesh, const Components& components,
                             const std::vector<bool>& keep) {
  const Kept k = kept_parts(mesh, components, keep);
  const std::size_t nt = mesh.triangles.size(), np = mesh.points.size();
  auto kept_triangle = [&](std::size_t t) { return keep[components.triangle_component[t]]; };
  auto kept = [&](std::size_t i) { return k.point[i] != 0; };
  std::vector<std::uint32_t> new_index(np, detail::kNoIndex);
  detail::for_each_kept(k.point_at, np, kChunk, kept, [&](std::size_t i, std::size_t place) {
    new_index[i] = static_cast<std::uint32_t>(place);
  });
  // In order, each kept element moves to its place at or below where it was: one pass each.
  for (std::size_t i = 0; i < np; ++i)
    if (kept(i)) mesh.points[new_index[i]] = mesh.points[i];
  std::size_t place = 0;
  for (std::size_t t = 0; t < nt; ++t)
    if (kept_triangle(t)) {
      const Triangle& tri = mesh.triangles[t];
      mesh.triangles[place++] = {new_index[tri[0]], new_index[tri[1]], new_index[tri[2]]};
    }
  mesh.points.resize(k.point_at.back());
  mesh.triangles.resize(place);
  return std::move(mesh);
}

ConstructionProof keep_components(const ConstructionProof& proof, const TriangleSoup& mesh,
                                  const Components& components, const std::vector<bool>& keep) {
  if (proof.triangles != mesh.triangles.size() || proof.points != mesh.points.size())
    throw InputError("keep_components: the proof is of another mesh");
  const Kept k = kept_parts(mesh, components, keep);
  return {k.triangle_at.back(), k.point_at.back()};
}

}  // namespace tpmsfill
