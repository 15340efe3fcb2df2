// The tet mesh's checks and boundary (tet_mesh.hpp). The readers and the writer are in src/io.
#include "tpmsfill/solid/tet_mesh.hpp"

#include <tbb/parallel_sort.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <tuple>
#include <utility>

#include "core/disjoint_sets.hpp"
#include "core/parallel.hpp"
#include "mesh/edge_key.hpp"
#include "mesh/exact_orientation.hpp"

namespace tpmsfill {

namespace {

// The face of a positive tet opposite corner k, oriented outward (its normal points away from
// corner k): for (a, b, c, d) that is (a, c, b), (a, b, d), (a, d, c), (b, c, d) opposite d, c,
// b, a. Indexed by the opposite corner.
constexpr int kOutwardFace[4][3] = {{1, 2, 3}, {0, 3, 2}, {0, 1, 3}, {0, 2, 1}};

struct FaceUse {
  std::array<std::uint32_t, 3> key;  // corners sorted
  std::uint32_t tet;
  std::uint8_t opposite;
  friend bool operator<(const FaceUse& a, const FaceUse& b) {
    return std::tie(a.key, a.tet, a.opposite) < std::tie(b.key, b.tet, b.opposite);
  }
};

// Every face of every tet, sorted so that the uses of one face are adjacent.
std::vector<FaceUse> sorted_face_uses(const TetMesh& mesh) {
  std::vector<FaceUse> uses(mesh.tets.size() * 4);
  detail::parallel_for(mesh.tets.size(), 4096, [&](std::size_t begin, std::size_t end) {
    for (std::size_t t = begin; t < end; ++t)
      for (int k = 0; k < 4; ++k) {
        const auto& f = kOutwardFace[k];
        std::array<std::uint32_t, 3> key{mesh.tets[t][f[0]], mesh.tets[t][f[1]],
                                         mesh.tets[t][f[2]]};
        std::sort(key.begin(), key.end());
        uses[4 * t + k] = {key, static_cast<std::uint32_t>(t), static_cast<std::uint8_t>(k)};
      }
  });
  tbb::parallel_sort(uses.begin(), uses.end());
  return uses;
}

bool repeats_a_corner(const Tet& t) {
  return t[0] == t[1] || t[0] == t[2] || t[0] == t[3] || t[1] == t[2] || t[1] == t[3] ||
         t[2] == t[3];
}

void check_orientation(const TetMesh& mesh, TetMeshReport& report) {
  std::vector<int> sign(mesh.tets.size(), 0);
  detail::parallel_for(mesh.tets.size(), 4096, [&](std::size_t begin, std::size_t end) {
    for (std::size_t t = begin; t < end; ++t) {
      const Tet& c = mesh.tets[t];
      sign[t] = repeats_a_corner(c) ? 2
                                    : detail::orientation_3(mesh.points[c[0]], mesh.points[c[1]],
                                                            mesh.points[c[2]], mesh.points[c[3]]);
    }
  });
  report.volume = detail::deterministic_sum(mesh.tets.size(), 4096, [&](std::size_t t) {
    const Tet& c = mesh.tets[t];
    const Vec3 a = mesh.points[c[0]];
    return dot(mesh.points[c[1]] - a, cross(mesh.points[c[2]] - a, mesh.points[c[3]] - a)) / 6;
  });
  for (std::size_t t = 0; t < sign.size(); ++t) {
    if (sign[t] == 2) {
      ++report.repeated_corner_tets;
    } else if (sign[t] == 0) {
      if (report.flat_tets++ == 0) report.first_flat_tet = t;
    } else if (sign[t] < 0) {
      if (report.negative_tets++ == 0) report.first_negative_tet = t;
    }
  }
}

// The boundary surface's edges, its pinched vertices and its shells, from its faces.
void check_boundary_surface(const TetMesh& mesh, const std::vector<Triangle>& faces,
                            TetMeshReport& report) {
  std::vector<std::pair<std::uint32_t, std::uint32_t>> edges;  // (low, high) per face side
  edges.reserve(faces.size() * 3);
  for (const Triangle& f : faces)
    for (int i = 0; i < 3; ++i) edges.emplace_back(std::minmax(f[i], f[(i + 1) % 3]));
  std::sort(edges.begin(), edges.end());
  for (std::size_t i = 0; i < edges.size();) {
    std::size_t j = i;
    while (j < edges.size() && edges[j] == edges[i]) ++j;
    ++report.boundary_edges;
    if (j - i != 2) ++report.open_edges;
    i = j;
  }
  // Fans: faces around a vertex joined when they share an edge at it. Shells: faces joined
  // by any shared edge.
  std::vector<std::vector<std::uint32_t>> around(mesh.points.size());
  for (std::uint32_t f = 0; f < faces.size(); ++f)
    for (std::uint32_t v : faces[f]) around[v].push_back(f);
  detail::DisjointSets shells(faces.size());
  for (std::uint32_t v = 0; v < around.size(); ++v) {
    const auto& fan = around[v];
    if (fan.empty()) continue;
    ++report.boundary_vertices;
    detail::DisjointSets local(fan.size());
    for (std::size_t a = 0; a < fan.size(); ++a)
      for (std::size_t b = a + 1; b < fan.size(); ++b) {
        int shared = 0;
        for (std::uint32_t p : faces[fan[a]])
          for (std::uint32_t q : faces[fan[b]]) shared += p == q;
        if (shared < 2) continue;  // only v
        local.unite(static_cast<std::uint32_t>(a), static_cast<std::uint32_t>(b));
        shells.unite(fan[a], fan[b]);
      }
    std::size_t fans = 0;
    for (std::uint32_t a = 0; a < fan.size(); ++a) fans += local.find(a) == a;
    if (fans > 1) ++report.pinched_vertices;
  }
  for (std::uint32_t f = 0; f < faces.size(); ++f) report.boundary_shells += shells.find(f) == f;
  report.euler_characteristic = static_cast<std::int64_t>(report.boundary_vertices) -
                                static_cast<std::int64_t>(report.boundary_edges) +
                                static_cast<std::int64_t>(faces.size());
}

void check_material(const TetMesh& mesh, TetMeshReport& report) {
  report.has_material = !mesh.material.empty();
  bool first = true;
  for (double m : mesh.material) {
    if (!std::isfinite(m)) {
      ++report.non_finite_material;
      continue;
    }
    report.material_min = first ? m : std::min(report.material_min, m);
    report.material_max = first ? m : std::max(report.material_max, m);
    first = false;
  }
}

std::string plural(std::uint64_t n, const std::string& one, const std::string& many) {
  return std::to_string(n) + " " + (n == 1 ? one : many);
}

// The faces in one tet, outward, from the sorted face uses.
std::vector<Triangle> boundary_faces(const TetMesh& mesh, const std::vector<FaceUse>& uses) {
  std::vector<std::pair<std::uint32_t, std::uint8_t>> single;  // (tet, opposite corner)
  for (std::size_t i = 0; i < uses.size();) {
    std::size_t j = i + 1;
    while (j < uses.size() && uses[j].key == uses[i].key) ++j;
    if (j - i == 1) single.emplace_back(uses[i].tet, uses[i].opposite);
    i = j;
  }
  std::sort(single.begin(), single.end());
  std::vector<Triangle> faces;
  faces.reserve(single.size());
  for (const auto& [t, k] : single) {
    const auto& f = kOutwardFace[k];
    faces.push_back({mesh.tets[t][f[0]], mesh.tets[t][f[1]], mesh.tets[t][f[2]]});
  }
  return faces;
}

}  // namespace

TriangleSoup tet_boundary(const TetMesh& mesh) {
  return {mesh.points, boundary_faces(mesh, sorted_face_uses(mesh))};
}

TetMeshReport check_tet_mesh(const TetMesh& mesh) {
  TetMeshReport report;
  report.points = mesh.points.size();
  report.tets = mesh.tets.size();
  std::vector<char> used(mesh.points.size(), 0);
  for (const Tet& t : mesh.tets)
    for (std::uint32_t v : t) used[v] = 1;
  for (std::size_t v = 0; v < used.size(); ++v) {
    if (used[v])
      report.bounds.extend(mesh.points[v]);
    else
      ++report.unused_points;
  }
  check_orientation(mesh, report);
  check_material(mesh, report);

  // Faces: in one tet (boundary), two (inside) or more (overfull); tets joined by faces.
  const std::vector<FaceUse> uses = sorted_face_uses(mesh);
  detail::DisjointSets pieces(mesh.tets.size());
  for (std::size_t i = 0; i < uses.size();) {
    std::size_t j = i + 1;
    while (j < uses.size() && uses[j].key == uses[i].key) ++j;
    if (j - i == 1) ++report.boundary_faces;
    if (j - i > 2) ++report.overfull_faces;
    for (std::size_t k = i + 1; k < j; ++k) pieces.unite(uses[i].tet, uses[k].tet);
    i = j;
  }
  for (std::uint32_t t = 0; t < mesh.tets.size(); ++t) report.components += pieces.find(t) == t;

  // With a repeated corner a "face" is an edge: the surface checks would only repeat that.
  if (report.repeated_corner_tets == 0)
    check_boundary_surface(mesh, boundary_faces(mesh, uses), report);
  if (report.open_edges == 0 && report.pinched_vertices == 0 && report.boundary_shells == 1 &&
      report.overfull_faces == 0 && report.euler_characteristic % 2 == 0)
    report.genus = (2 - report.euler_characteristic) / 2;
  return report;
}

std::optional<std::string> ball_problem(const TetMeshReport& r) {
  if (r.tets == 0) return "the mesh has no tets";
  if (r.repeated_corner_tets > 0)
    return plural(r.repeated_corner_tets, "tet repeats", "tets repeat") + " a corner";
  if (r.flat_tets > 0)
    return plural(r.flat_tets, "tet has", "tets have") + " no volume, the first is tet " +
           std::to_string(*r.first_flat_tet);
  if (r.negative_tets > 0 && r.negative_tets < r.tets)
    return plural(r.negative_tets, "tet is", "tets are") + " inverted (negative volume) among " +
           std::to_string(r.tets) + ", the first is tet " + std::to_string(*r.first_negative_tet);
  if (r.overfull_faces > 0)
    return plural(r.overfull_faces, "face is", "faces are") + " shared by more than two tets";
  if (r.components > 1)
    return "the mesh has " + std::to_string(r.components) +
           " pieces (tets joined by faces); one solid maps onto the cube";
  if (r.open_edges > 0)
    return "the boundary is not a closed 2-manifold: " +
           plural(r.open_edges, "edge is", "edges are") + " not in exactly two boundary faces";
  if (r.pinched_vertices > 0)
    return "the boundary is pinched at " + plural(r.pinched_vertices, "vertex", "vertices") +
           " (several fans of faces meet there)";
  if (r.boundary_shells > 1)
    return "the boundary has " + std::to_string(r.boundary_shells) +
           " shells (a cavity inside the solid); the cube map needs one";
  if (r.genus && *r.genus != 0)
    return "the boundary has genus " + std::to_string(*r.genus) +
           " (handles or through holes); the cube map needs genus 0 (cut the handles, or "
           "split the part)";
  if (!r.genus) return "the boundary's Euler characteristic is odd";
  if (r.non_finite_material > 0)
    return plural(r.non_finite_material, "material value is", "material values are") +
           " not finite";
  return std::nullopt;
}

TetMesh with_positive_tets(TetMesh mesh, const TetMeshReport& report) {
  if (report.tets > 0 && report.negative_tets == report.tets)
    for (Tet& t : mesh.tets) std::swap(t[2], t[3]);
  return mesh;
}

TetMesh with_chords_split(TetMesh mesh) {
  using detail::edge_key;
  std::vector<char> on_boundary(mesh.points.size(), 0);
  std::vector<std::uint64_t> boundary_edges;
  for (const Triangle& f : tet_boundary(mesh).triangles)
    for (int i = 0; i < 3; ++i) {
      on_boundary[f[i]] = 1;
      boundary_edges.push_back(edge_key(f[i], f[(i + 1) % 3]));
    }
  std::sort(boundary_edges.begin(), boundary_edges.end());
  // The chords, each with its midpoint's index, in the order tets first meet them.
  std::vector<std::pair<std::uint64_t, std::uint32_t>> chords;
  for (const Tet& t : mesh.tets)
    for (int i = 0; i < 4; ++i)
      for (int j = i + 1; j < 4; ++j)
        if (on_boundary[t[i]] && on_boundary[t[j]] &&
            !std::binary_search(boundary_edges.begin(), boundary_edges.end(), edge_key(t[i], t[j])))
          chords.emplace_back(edge_key(t[i], t[j]), 0);
  std::sort(chords.begin(), chords.end());
  chords.erase(std::unique(chords.begin(), chords.end()), chords.end());
  for (auto& [edge, middle] : chords) {
    const auto a = static_cast<std::uint32_t>(edge >> 32), b = static_cast<std::uint32_t>(edge);
    middle = static_cast<std::uint32_t>(mesh.points.size());
    mesh.points.push_back(0.5 * (mesh.points[a] + mesh.points[b]));
    if (!mesh.material.empty())
      mesh.material.push_back(0.5 * (mesh.material[a] + mesh.material[b]));
  }
  auto midpoint_of = [&](std::uint64_t edge) -> const std::uint32_t* {
    const auto it = std::lower_bound(chords.begin(), chords.end(), std::pair{edge, 0u});
    return it != chords.end() && it->first == edge ? &it->second : nullptr;
  };
  // Each tet is halved at its chords in one global order (by key), so that a face shared by
  // two tets is cut the same way in both; the halves keep the tet's orientation (one end of
  // the chord replaced by the midpoint in each).
  std::vector<Tet> out;
  out.reserve(mesh.tets.size() + 4 * chords.size());
  std::vector<Tet> stack;
  for (const Tet& tet : mesh.tets) {
    stack.assign(1, tet);
    while (!stack.empty()) {
      const Tet t = stack.back();
      stack.pop_back();
      int first_i = -1, first_j = -1;
      std::uint64_t first_key = 0;
      for (int i = 0; i < 4; ++i)
        for (int j = i + 1; j < 4; ++j)
          if (midpoint_of(edge_key(t[i], t[j])) &&
              (first_i < 0 || edge_key(t[i], t[j]) < first_key))
            first_i = i, first_j = j, first_key = edge_key(t[i], t[j]);
      if (first_i < 0) {
        out.push_back(t);
        continue;
      }
      const std::uint32_t m = *midpoint_of(first_key);
      Tet first = t, second = t;
      first[first_j] = m;
      second[first_i] = m;
      stack.push_back(second);
      stack.push_back(first);
    }
  }
  mesh.tets = std::move(out);

  // Then the faces inside whose three corners lie on the boundary (their edges are all on
  // it, a thin part's tip): such a face on one patch would lie on a cube face with tets on
  // both sides. Each gets a point at its centroid, and its two tets are cut in three there
  // (each corner of the face replaced by the point in turn; the other faces stay whole).
  on_boundary.resize(mesh.points.size(), 0);
  std::vector<std::pair<std::array<std::uint32_t, 3>, std::uint32_t>> faces;
  const std::vector<FaceUse> uses = sorted_face_uses(mesh);
  for (std::size_t i = 0; i + 1 < uses.size(); ++i) {
    const auto& k = uses[i].key;
    if (uses[i + 1].key != k || !(on_boundary[k[0]] && on_boundary[k[1]] && on_boundary[k[2]]))
      continue;
    const auto centre = static_cast<std::uint32_t>(mesh.points.size());
    mesh.points.push_back((1.0 / 3) * (mesh.points[k[0]] + mesh.points[k[1]] + mesh.points[k[2]]));
    if (!mesh.material.empty())
      mesh.material.push_back((mesh.material[k[0]] + mesh.material[k[1]] + mesh.material[k[2]]) /
                              3);
    faces.emplace_back(k, centre);
  }
  if (faces.empty()) return mesh;
  auto centre_of = [&](std::array<std::uint32_t, 3> k) -> const std::uint32_t* {
    std::sort(k.begin(), k.end());
    const auto it = std::lower_bound(faces.begin(), faces.end(), std::pair{k, 0u});
    return it != faces.end() && it->first == k ? &it->second : nullptr;
  };
  out.clear();
  for (const Tet& tet : mesh.tets) {
    stack.assign(1, tet);
    while (!stack.empty()) {
      const Tet t = stack.back();
      stack.pop_back();
      int opposite = -1;
      const std::uint32_t* centre = nullptr;
      for (int k = 0; k < 4 && !centre; ++k) {
        centre = centre_of({t[(k + 1) % 4], t[(k + 2) % 4], t[(k + 3) % 4]});
        opposite = k;
      }
      if (!centre) {
        out.push_back(t);
        continue;
      }
      for (int k = 3; k >= 0; --k)
        if (k != opposite) {
          Tet child = t;
          child[k] = *centre;
          stack.push_back(child);
        }
    }
  }
  mesh.tets = std::move(out);
  return mesh;
}

}  // namespace tpmsfill
