// to_json(MeshCheck): the object `tpmsfill check --json` prints (fields in check.hpp).
#include <nlohmann/json.hpp>

#include "tpmsfill/check.hpp"

namespace tpmsfill {
namespace {

// ordered_json keeps the keys in the documented order (valid and problems first).
using json = nlohmann::ordered_json;

json point(Vec3 p) {
  return json::array({p.x, p.y, p.z});
}

json edges(const std::vector<EdgeLocation>& locations) {
  json a = json::array();
  for (const EdgeLocation& e : locations)
    a.push_back({{"a", point(e.ends[0])}, {"b", point(e.ends[1])}, {"triangle", e.triangle}});
  return a;
}

template <typename T>
json optional(const std::optional<T>& value) {
  return value ? json(*value) : json(nullptr);
}

}  // namespace

std::string to_json(const MeshCheck& c) {
  json examples = {
      {"border_edges", edges(c.border_edge_examples)},
      {"non_manifold_edges", edges(c.non_manifold_edge_examples)},
      {"inconsistent_edges", edges(c.inconsistent_edge_examples)},
      {"non_manifold_vertices", json::array()},
      {"degenerate_triangles", c.degenerate_triangle_examples},
      {"duplicate_triangles", c.duplicate_triangle_examples},
      {"self_intersections", json::array()},
  };
  for (Vec3 p : c.non_manifold_vertex_examples)
    examples["non_manifold_vertices"].push_back(point(p));
  for (const auto& pair : c.self_intersection_examples)
    examples["self_intersections"].push_back({pair[0], pair[1]});

  json j = {
      {"valid", c.valid()},
      {"problems", c.problems()},
      {"points", c.points},
      {"triangles", c.triangles},
      {"vertices", c.vertices},
      {"duplicate_points", c.duplicate_points},
      {"unreferenced_points", c.unreferenced_points},
      {"bbox", c.bbox.empty() ? json(nullptr)
                              : json{{"min", point(c.bbox.min)}, {"max", point(c.bbox.max)}}},
      {"degenerate_triangles", c.degenerate_triangles},
      {"duplicate_triangles", c.duplicate_triangles},
      {"edges", c.edges},
      {"border_edges", c.border_edges},
      {"holes", c.holes.value_or(0)},
      {"non_manifold_edges", c.non_manifold_edges},
      {"non_manifold_vertices", c.non_manifold_vertices},
      {"inconsistent_edges", c.inconsistent_edges},
      {"consistently_oriented", c.consistently_oriented()},
      {"closed", c.closed()},
      {"manifold", c.manifold()},
      {"components", c.components},
      {"edge_components", c.edge_components},
      {"self_intersecting_pairs", optional(c.self_intersecting_pairs)},
      {"area", c.area},
      {"volume", optional(c.volume)},
      {"outward", optional(c.outward)},
      {"genus", optional(c.genus)},
      {"examples", std::move(examples)},
  };
  return j.dump(2);
}

}  // namespace tpmsfill
