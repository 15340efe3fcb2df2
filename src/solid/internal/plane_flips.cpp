// Edge flips in the plane (plane_flips.hpp). Where det J_G > 0 a slice's turned-over triangle
// is a sliver whose chord normal the map tilts past the plane (a crossing near a leaf's
// corner), 2e-10 to 2e-9 mm² on bear's stack: with 8 split passes it kept 7, of which flips
// mended 5; 16 passes leave none, and flips are what is left where a layer needs more. Each
// flip takes at least one triangle back and turns none over, so the passes end.
#include "solid/internal/plane_flips.hpp"

#include <unordered_map>

#include "mesh/exact_orientation.hpp"

namespace tpmsfill::detail {

std::size_t flip_turned_triangles(const std::vector<Vec3>& points,
                                  std::vector<std::array<std::uint32_t, 3>>& triangles) {
  using Tri = std::array<std::uint32_t, 3>;
  const auto orientation = [&](std::uint32_t a, std::uint32_t b, std::uint32_t c) {
    return orientation_2({points[a].x, points[a].y}, {points[b].x, points[b].y},
                         {points[c].x, points[c].y});
  };
  const auto turned = [&](const Tri& t) { return orientation(t[0], t[1], t[2]) < 0; };
  std::vector<std::uint32_t> todo;
  for (std::uint32_t t = 0; t < triangles.size(); ++t)
    if (turned(triangles[t])) todo.push_back(t);
  if (todo.empty()) return 0;
  const auto directed = [](std::uint32_t a, std::uint32_t b) { return std::uint64_t{a} << 32 | b; };
  std::unordered_map<std::uint64_t, std::uint32_t> owner;  // directed edge → its triangle
  const auto is_edge = [&](std::uint32_t a, std::uint32_t b) {
    return owner.count(directed(a, b)) || owner.count(directed(b, a));
  };
  const auto place = [&](std::uint32_t t, const Tri& tri) {
    triangles[t] = tri;
    for (int k = 0; k < 3; ++k) owner[directed(tri[k], tri[(k + 1) % 3])] = t;
  };
  for (std::uint32_t t = 0; t < triangles.size(); ++t) place(t, triangles[t]);
  for (bool changed = true; changed;) {
    changed = false;
    for (std::size_t i = 0; i < todo.size(); ++i) {  // grows as flips turn neighbours
      const std::uint32_t t = todo[i];
      for (int k = 0; k < 3 && turned(triangles[t]); ++k) {
        const Tri tri = triangles[t];
        const std::uint32_t a = tri[k], b = tri[(k + 1) % 3], c = tri[(k + 2) % 3];
        const auto across = owner.find(directed(b, a));
        if (across == owner.end()) continue;  // on the border
        const std::uint32_t u = across->second;
        const Tri other = triangles[u];
        std::uint32_t d = other[0];
        for (std::uint32_t v : other)
          if (v != a && v != b) d = v;
        if (d == c || is_edge(c, d)) continue;
        // The quad a → d → b → c split on c–d instead of a–b.
        const Tri first{a, d, c}, second{d, b, c};
        const int before = 1 + turned(other);
        const int after = (orientation(a, d, c) <= 0) + (orientation(d, b, c) <= 0);
        if (after >= before) continue;
        owner.erase(directed(a, b)), owner.erase(directed(b, a));
        place(t, first), place(u, second);
        if (turned(second)) todo.push_back(u);
        changed = true;
      }
    }
  }
  std::size_t left = 0;
  for (const Tri& t : triangles) left += turned(t);
  return left;
}

}  // namespace tpmsfill::detail
