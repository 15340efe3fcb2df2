// Stage "validate": is an indexed mesh (marching-cubes output) a closed, outward 2-manifold
// without degenerate faces or self-intersections? With a construction proof that speaks of the
// mesh, its verdict, and only the measures are taken; otherwise judged as indexed, fast:
// - topology from a vertex -> corner table (counting sort): each vertex looks at its own
//   corners, so edges (classified at their smaller vertex) and fans are per-vertex work;
// - duplicate points by sorting position hashes; components by union-find
//   (detail::triangle_components);
// - sums (area, volume) per fixed chunk, added in chunk order (detail::deterministic_sum);
// - self-intersections in mesh/internal/self_intersections (exact predicates, by grid cells or by
//   CGAL's box intersection search).
// Every parallel loop runs over fixed chunks whose results are merged in chunk order, so the
// report is the same for any thread count.
#include "tpmsfill/mesh/validate.hpp"

#include <tbb/parallel_sort.h>

#include <algorithm>
#include <bit>
#include <numeric>
#include <string>
#include <utility>

#include "core/parallel.hpp"
#include "core/stage_progress.hpp"
#include "mesh/cgal_types.hpp"
#include "mesh/internal/problem_text.hpp"
#include "mesh/internal/self_intersections.hpp"
#include "mesh/mesh_measures.hpp"
#include "mesh/soup_indices.hpp"
#include "mesh/soup_topology.hpp"
#include "mesh/validate_window.hpp"

namespace tpmsfill {
namespace {

constexpr std::size_t kChunk = 4096;  // items per fixed chunk of every parallel loop

std::size_t chunk_count(std::size_t n) {
  return (n + kChunk - 1) / kChunk;
}

using detail::repeated_corner;

// --- topology -----------------------------------------------------------------------------

struct EdgeFacts {
  std::uint64_t border = 0, non_manifold = 0, inconsistent = 0, pinched_vertices = 0;
  std::vector<EdgeLocation> border_examples, non_manifold_examples, inconsistent_examples;
  std::vector<Vec3> pinched_examples;
};

/// The corners around each vertex: the slots 3t + k of triangle t's corner k at vertex v lie
/// in corners[first[v], first[v + 1]), by increasing slot. Repeated-corner triangles are left
/// out.
struct CornerTable {
  std::vector<std::uint32_t> first;
  std::vector<std::uint32_t> corners;
};

CornerTable corner_table(const TriangleSoup& mesh) {
  const std::size_t np = mesh.points.size(), nt = mesh.triangles.size();
  CornerTable table;
  table.first.assign(np + 1, 0);
  for (const Triangle& t : mesh.triangles)
    if (!repeated_corner(t))
      for (std::uint32_t v : t) ++table.first[v + 1];
  for (std::size_t v = 0; v < np; ++v) table.first[v + 1] += table.first[v];
  table.corners.resize(table.first[np]);
  std::vector<std::uint32_t> fill(table.first.begin(), table.first.end() - 1);
  for (std::size_t t = 0; t < nt; ++t)
    if (!repeated_corner(mesh.triangles[t]))
      for (std::uint32_t k = 0; k < 3; ++k)
        table.corners[fill[mesh.triangles[t][k]]++] = static_cast<std::uint32_t>(3 * t + k);
  return table;
}

/// One corner's edge at a vertex v.
struct Use {
  std::uint32_t other;  // the edge's other end
  std::uint32_t local;  // index of the corner among v's corners
  bool out;             // the triangle walks v -> other
};

/// Counts edge v-w (v < w) whose m uses start at `use`, in the direction its first triangle
/// (the lowest-index one: v's corners are listed by slot) walks it.
void record_edge(EdgeFacts& f, const TriangleSoup& mesh, const CornerTable& table, std::size_t v,
                 const Use* use, std::size_t m, std::size_t max_examples) {
  const Vec3 pv = mesh.points[v], pw = mesh.points[use[0].other];
  const EdgeLocation ends{use[0].out ? std::array<Vec3, 2>{pv, pw} : std::array<Vec3, 2>{pw, pv},
                          table.corners[table.first[v] + use[0].local] / 3};
  if (m == 1) {
    if (f.border++ < max_examples) f.border_examples.push_back(ends);
  } else if (m >= 3) {
    if (f.non_manifold++ < max_examples) f.non_manifold_examples.push_back(ends);
  } else if (use[0].out == use[1].out) {
    if (f.inconsistent++ < max_examples) f.inconsistent_examples.push_back(ends);
  }
}

/// Per-thread buffers for classify_vertex().
struct VertexScratch {
  std::vector<Use> uses;
  std::vector<std::uint32_t> parent;
};

/// Vertex v's corner (t, k) has the edges v -> next and prev -> v. Grouping v's corners by
/// the other end w gives every edge at v with all its uses: edges are counted at their
/// smaller vertex, and corners that share an edge used by two or more triangles are in one
/// fan (as in detail::analyze_soup); more than one fan makes v pinched.
void classify_vertex(const TriangleSoup& mesh, const CornerTable& table, std::size_t v,
                     std::size_t max_examples, VertexScratch& scratch, EdgeFacts& f) {
  const std::uint32_t d = table.first[v + 1] - table.first[v];
  if (d == 0) return;
  std::vector<Use>& uses = scratch.uses;
  uses.clear();
  for (std::uint32_t l = 0; l < d; ++l) {
    const std::uint32_t slot = table.corners[table.first[v] + l];
    const Triangle& t = mesh.triangles[slot / 3];
    const std::uint32_t k = slot % 3;
    uses.push_back({t[(k + 1) % 3], l, true});
    uses.push_back({t[(k + 2) % 3], l, false});
  }
  // A vertex has a dozen uses or so: insertion sort, by (other, local).
  auto before = [](const Use& a, const Use& b) {
    return a.other != b.other ? a.other < b.other : a.local < b.local;
  };
  for (std::size_t i = 1; i < uses.size(); ++i) {
    const Use u = uses[i];
    std::size_t at = i;
    for (; at > 0 && before(u, uses[at - 1]); --at) uses[at] = uses[at - 1];
    uses[at] = u;
  }
  std::vector<std::uint32_t>& parent = scratch.parent;
  parent.resize(d);
  std::iota(parent.begin(), parent.end(), 0u);
  auto find = [&](std::uint32_t x) {
    while (parent[x] != x) x = parent[x] = parent[parent[x]];
    return x;
  };
  for (std::size_t i = 0; i < uses.size();) {
    std::size_t j = i + 1;
    while (j < uses.size() && uses[j].other == uses[i].other) ++j;
    const std::size_t m = j - i;
    if (m >= 2)
      for (std::size_t u = i + 1; u < j; ++u) {
        const std::uint32_t a = find(uses[i].local), b = find(uses[u].local);
        parent[std::max(a, b)] = std::min(a, b);
      }
    if (uses[i].other > v) record_edge(f, mesh, table, v, &uses[i], m, max_examples);
    i = j;
  }
  std::uint32_t fans = 0;
  for (std::uint32_t l = 0; l < d; ++l) fans += find(l) == l;
  if (fans > 1 && f.pinched_vertices++ < max_examples) f.pinched_examples.push_back(mesh.points[v]);
}

/// The chunks' facts in chunk order, at most max_examples examples of each kind.
EdgeFacts merge(const std::vector<EdgeFacts>& partial, std::size_t max_examples) {
  EdgeFacts all;
  auto append = [&](auto& to, const auto& from) {
    for (const auto& e : from)
      if (to.size() < max_examples) to.push_back(e);
  };
  for (const EdgeFacts& f : partial) {
    all.border += f.border;
    all.non_manifold += f.non_manifold;
    all.inconsistent += f.inconsistent;
    all.pinched_vertices += f.pinched_vertices;
    append(all.border_examples, f.border_examples);
    append(all.non_manifold_examples, f.non_manifold_examples);
    append(all.inconsistent_examples, f.inconsistent_examples);
    append(all.pinched_examples, f.pinched_examples);
  }
  return all;
}

/// Edges and fans at vertices [first, end) from a vertex -> corner table, per fixed chunk of
/// vertices.
EdgeFacts edge_facts(const TriangleSoup& mesh, std::size_t first, std::size_t end,
                     std::size_t max_examples, detail::ProgressCounter& progress) {
  const std::size_t np = end;
  const CornerTable table = corner_table(mesh);
  const std::size_t chunks = chunk_count(end - first);
  std::vector<EdgeFacts> partial(chunks);
  detail::parallel_for(chunks, 1, [&](std::size_t cb, std::size_t ce) {
    VertexScratch scratch;
    for (std::size_t c = cb; c < ce; ++c) {
      const std::size_t vb = first + c * kChunk, ve = std::min(np, vb + kChunk);
      for (std::size_t v = vb; v < ve; ++v)
        classify_vertex(mesh, table, v, max_examples, scratch, partial[c]);
      progress.add(ve - vb);
    }
  });
  return merge(partial, max_examples);
}

/// Referenced points in [first, end) whose position an earlier referenced point already has
/// (bit-identical, -0.0 == +0.0): sort position hashes, then compare positions within equal
/// hashes.
std::uint64_t duplicate_points(const TriangleSoup& mesh, const std::vector<std::uint8_t>& used,
                               std::size_t first, std::size_t end) {
  auto bits = [](double c) {
    return c == 0.0 ? std::uint64_t{0} : std::bit_cast<std::uint64_t>(c);
  };
  auto mix = [](std::uint64_t h) {
    h ^= h >> 33;
    h *= 0xff51afd7ed558ccdULL;
    h ^= h >> 33;
    h *= 0xc4ceb9fe1a85ec53ULL;
    return h ^ (h >> 33);
  };
  std::vector<std::pair<std::uint64_t, std::uint32_t>> keys;
  for (std::size_t i = 0; i < mesh.points.size(); ++i)
    if (used[i]) keys.push_back({0, static_cast<std::uint32_t>(i)});
  detail::parallel_for(keys.size(), kChunk, [&](std::size_t b, std::size_t e) {
    for (std::size_t i = b; i < e; ++i) {
      const Vec3 p = mesh.points[keys[i].second];
      keys[i].first = mix(mix(mix(bits(p.x)) ^ bits(p.y)) ^ bits(p.z));
    }
  });
  tbb::parallel_sort(keys.begin(), keys.end());
  std::uint64_t duplicates = 0;
  for (std::size_t i = 0; i < keys.size();) {
    std::size_t j = i + 1;
    while (j < keys.size() && keys[j].first == keys[i].first) ++j;
    for (std::size_t a = i + 1; a < j; ++a)
      for (std::size_t b = i; b < a && keys[a].second >= first && keys[a].second < end; ++b)
        if (mesh.points[keys[a].second] == mesh.points[keys[b].second]) {
          ++duplicates;
          break;
        }
    i = j;
  }
  return duplicates;
}

// --- the report, step by step ------------------------------------------------------------

/// Per triangle: degenerate (repeated corner or collinear, exact)?
std::vector<std::uint8_t> degenerate_flags(const TriangleSoup& mesh) {
  const std::size_t nt = mesh.triangles.size();
  std::vector<std::uint8_t> degenerate(nt, 0);
  detail::parallel_for(nt, kChunk, [&](std::size_t b, std::size_t e) {
    for (std::size_t t = b; t < e; ++t) {
      const Triangle& tri = mesh.triangles[t];
      degenerate[t] = repeated_corner(tri) || CGAL::collinear(detail::to_cgal(mesh.points[tri[0]]),
                                                              detail::to_cgal(mesh.points[tri[1]]),
                                                              detail::to_cgal(mesh.points[tri[2]]));
    }
  });
  return degenerate;
}

/// Degenerate triangles: per triangle a flag.
std::vector<std::uint8_t> record_degenerates(MeshValidity& r, const TriangleSoup& mesh,
                                             std::size_t max_examples) {
  std::vector<std::uint8_t> degenerate = degenerate_flags(mesh);
  for (std::size_t t = 0; t < degenerate.size(); ++t)
    if (degenerate[t] && r.degenerate_triangles++ < max_examples)
      r.degenerate_triangle_examples.push_back(static_cast<std::uint32_t>(t));
  return degenerate;
}

/// Border, non-manifold and inconsistent edges, pinched vertices.
void record_edges(MeshValidity& r, const TriangleSoup& mesh, std::size_t max_examples,
                  detail::ProgressCounter& progress) {
  EdgeFacts edges = edge_facts(mesh, 0, mesh.points.size(), max_examples, progress);
  r.border_edges = edges.border;
  r.non_manifold_edges = edges.non_manifold;
  r.inconsistent_edges = edges.inconsistent;
  r.non_manifold_vertices = edges.pinched_vertices;
  r.border_edge_examples = std::move(edges.border_examples);
  r.non_manifold_edge_examples = std::move(edges.non_manifold_examples);
  r.inconsistent_edge_examples = std::move(edges.inconsistent_examples);
  r.non_manifold_vertex_examples = std::move(edges.pinched_examples);
}

/// Components, area, volume (about the centre of the used points' box) and orientation.
void record_volume(MeshValidity& r, const TriangleSoup& mesh,
                   const std::vector<std::uint8_t>& used) {
  const std::size_t nt = mesh.triangles.size();
  const detail::TriangleComponents components = detail::triangle_components(mesh);
  r.components = components.count;
  const Vec3 centre = detail::box_centre(mesh, used);
  std::vector<double> six_v(nt);
  detail::parallel_for(nt, kChunk, [&](std::size_t b, std::size_t e) {
    for (std::size_t t = b; t < e; ++t)
      six_v[t] = detail::six_volume(mesh, mesh.triangles[t], centre);
  });
  const double volume =
      detail::deterministic_sum(nt, kChunk, [&](std::size_t t) { return six_v[t]; }) / 6;
  r.volume = volume;
  r.area =
      detail::deterministic_sum(
          nt, kChunk, [&](std::size_t t) { return detail::double_area(mesh, mesh.triangles[t]); }) /
      2;
  std::vector<double> component_volume(r.components, 0.0);
  for (std::size_t t = 0; t < nt; ++t) component_volume[components.of_triangle[t]] += six_v[t];
  r.outward = r.components > 0 && volume > 0 &&
              std::none_of(component_volume.begin(), component_volume.end(),
                           [](double v) { return v == 0; });
}

/// Intersecting pairs among the non-degenerate triangles.
void record_self_intersections(MeshValidity& r, const TriangleSoup& mesh,
                               const std::vector<std::uint8_t>& degenerate,
                               const ValidateOptions& options, detail::ProgressCounter& progress) {
  detail::SelfIntersections found =
      detail::find_self_intersections(mesh, degenerate, options.cell_grid, progress);
  r.searched_by_cells = found.by_cells;
  r.self_intersecting_pairs = found.pairs.size();
  found.pairs.resize(std::min(found.pairs.size(), options.max_examples));
  r.self_intersection_examples = std::move(found.pairs);
}

/// The verdict of a construction proof, measured; nullopt when it does not speak of `mesh`.
std::optional<MeshValidity> validate_by_construction(const TriangleSoup& mesh,
                                                     const ConstructionProof& proof,
                                                     const ValidateOptions& options) {
  if (proof.triangles != mesh.triangles.size() || proof.points != mesh.points.size())
    return std::nullopt;
  MeshValidity r;
  r.validated_by = ValidatedBy::Construction;
  r.triangles = mesh.triangles.size();
  if (options.self_intersections) r.self_intersecting_pairs = 0;
  // Two steps, each reported: the points' count, then the components and sums.
  detail::ProgressCounter progress(options.progress, "validate", 2);
  const std::vector<std::uint8_t> used = detail::used_points(mesh);
  r.vertices = static_cast<std::uint64_t>(std::count(used.begin(), used.end(), 1));
  progress.add(1);
  record_volume(r, mesh, used);
  progress.finish();
  return r;
}

}  // namespace

bool MeshValidity::valid() const {
  return triangles > 0 && closed() && manifold() && consistently_oriented() && outward == true &&
         degenerate_triangles == 0 && duplicate_triangles == 0 &&
         (merged_points || duplicate_points == 0) && self_intersecting_pairs.value_or(0) == 0;
}

std::vector<std::string> MeshValidity::problems() const {
  namespace sentence = detail::sentence;
  std::vector<std::string> p;
  if (triangles == 0) p.push_back(sentence::no_triangles());
  // Holes are counted once non-manifold edges are split, which can add border edges.
  if (!closed()) p.push_back(sentence::border_edges(border_edges, holes));
  if (non_manifold_edges > 0) p.push_back(sentence::non_manifold_edges(non_manifold_edges));
  if (non_manifold_vertices > 0)
    p.push_back(sentence::non_manifold_vertices(non_manifold_vertices));
  if (!consistently_oriented()) p.push_back(sentence::inconsistent_edges(inconsistent_edges));
  if (triangles > 0 && outward == false)
    p.push_back(merged_points ? sentence::shells_not_outward(volume)
                              : sentence::components_not_outward(volume.value_or(0)));
  if (degenerate_triangles > 0) p.push_back(sentence::degenerate_triangles(degenerate_triangles));
  if (duplicate_triangles > 0) p.push_back(sentence::duplicate_triangles(duplicate_triangles));
  if (!merged_points && duplicate_points > 0)
    p.push_back(sentence::duplicate_points(duplicate_points));
  if (self_intersecting_pairs.value_or(0) > 0)
    p.push_back(sentence::self_intersections(*self_intersecting_pairs));
  return p;
}

MeshValidity validate_mesh(const TriangleSoup& mesh, const ValidateOptions& options) {
  detail::require_32bit_mesh(mesh, "validate");
  if (options.proof)
    if (std::optional<MeshValidity> proved =
            validate_by_construction(mesh, *options.proof, options))
      return *proved;
  MeshValidity r;
  const std::size_t nt = mesh.triangles.size(), np = mesh.points.size();
  r.triangles = nt;
  detail::ProgressCounter progress(options.progress, "validate",
                                   np + nt + (options.self_intersections ? nt : 0));
  const std::vector<std::uint8_t> used = detail::used_points(mesh);
  r.vertices = static_cast<std::uint64_t>(std::count(used.begin(), used.end(), 1));

  const std::vector<std::uint8_t> degenerate = record_degenerates(r, mesh, options.max_examples);
  progress.add(nt);
  record_edges(r, mesh, options.max_examples, progress);
  r.duplicate_points = duplicate_points(mesh, used, 0, np);
  record_volume(r, mesh, used);
  if (options.self_intersections) record_self_intersections(r, mesh, degenerate, options, progress);
  progress.finish();
  return r;
}

namespace detail {

WindowValidation validate_window(const TriangleSoup& window,
                                 std::array<std::size_t, 2> owned_points,
                                 std::size_t first_owned_triangle,
                                 const std::optional<Grid>& cell_grid, std::size_t max_examples,
                                 bool self_intersections) {
  require_32bit_mesh(window, "validate");
  WindowValidation w;
  const auto [pb, pe] = owned_points;
  const std::vector<std::uint8_t> used = used_points(window);
  w.vertices = static_cast<std::uint64_t>(std::count(used.begin() + static_cast<std::ptrdiff_t>(pb),
                                                     used.begin() + static_cast<std::ptrdiff_t>(pe),
                                                     std::uint8_t{1}));
  const std::vector<std::uint8_t> degenerate = degenerate_flags(window);
  for (std::size_t t = first_owned_triangle; t < degenerate.size(); ++t)
    if (degenerate[t] && w.degenerate++ < max_examples)
      w.degenerate_examples.push_back(static_cast<std::uint32_t>(t));
  ProgressCounter none(nullptr, "validate", 1);
  EdgeFacts edges = edge_facts(window, pb, pe, max_examples, none);
  w.border = edges.border;
  w.non_manifold = edges.non_manifold;
  w.inconsistent = edges.inconsistent;
  w.pinched = edges.pinched_vertices;
  w.border_examples = std::move(edges.border_examples);
  w.non_manifold_examples = std::move(edges.non_manifold_examples);
  w.inconsistent_examples = std::move(edges.inconsistent_examples);
  w.pinched_examples = std::move(edges.pinched_examples);
  w.duplicates = duplicate_points(window, used, pb, pe);
  if (self_intersections) {
    SelfIntersections found = find_self_intersections(window, degenerate, cell_grid, none);
    w.searched_by_cells = found.by_cells;
    for (const TrianglePair& p : found.pairs)  // sorted: the first max_examples are the least
      if (p[1] >= first_owned_triangle && w.intersecting_pairs++ < max_examples)
        w.intersection_examples.push_back(p);
  }
  return w;
}

}  // namespace detail
}  // namespace tpmsfill
