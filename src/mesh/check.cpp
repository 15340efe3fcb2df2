// Stage "check": plain-data topology (mesh/soup_topology) for the counts; self-intersections
// by validation's search (mesh/internal/self_intersections); then CGAL PMP on the repaired,
// oriented soup for what needs a halfedge mesh: holes (border cycles) and whether the shells
// bound a volume.
#include "tpmsfill/check.hpp"

#include <CGAL/Polygon_mesh_processing/border.h>
#include <CGAL/Polygon_mesh_processing/orient_polygon_soup.h>
#include <CGAL/Polygon_mesh_processing/orientation.h>
#include <CGAL/Polygon_mesh_processing/polygon_soup_to_polygon_mesh.h>

#include <algorithm>
#include <cmath>
#include <iterator>
#include <string>
#include <utility>

#include "mesh/cgal_types.hpp"
#include "mesh/internal/self_intersections.hpp"
#include "mesh/mesh_measures.hpp"
#include "mesh/soup_indices.hpp"
#include "mesh/soup_topology.hpp"
#include "tpmsfill/error.hpp"
#include "tpmsfill/io.hpp"

namespace PMP = CGAL::Polygon_mesh_processing;

namespace tpmsfill {
namespace {

using detail::SoupTopology;

/// The soup CGAL sees: what repair_polygon_soup() would leave (merged points, no
/// repeated-corner or duplicate triangles, the first of each duplicate set kept), in input
/// order, with the input index of every polygon.
struct RepairedSoup {
  std::vector<detail::Point3> points;
  std::vector<std::array<std::size_t, 3>> polygons;
  std::vector<std::uint32_t> input_triangle;  ///< per polygon (= per mesh face)
};

RepairedSoup repaired_soup(const TriangleSoup& soup, const SoupTopology& topo) {
  RepairedSoup r;
  std::vector<std::uint32_t> compact(topo.vertex_count, detail::kNoIndex);
  for (std::size_t t = 0; t < topo.corners.size(); ++t) {
    if (topo.flags[t]) continue;
    std::array<std::size_t, 3> polygon{};
    for (int k = 0; k < 3; ++k) {
      std::uint32_t v = topo.corners[t][k];
      if (compact[v] == detail::kNoIndex) {
        compact[v] = static_cast<std::uint32_t>(r.points.size());
        r.points.push_back(detail::to_cgal(soup.points[topo.merge.first_point[v]]));
      }
      polygon[k] = compact[v];
    }
    r.polygons.push_back(polygon);
    r.input_triangle.push_back(static_cast<std::uint32_t>(t));
  }
  return r;
}

/// Volume by the divergence theorem about the bounding box centre (so that translating the
/// mesh does not cost precision); serial, hence the same sum whatever the thread count.
double signed_volume(const TriangleSoup& soup, const SoupTopology& topo, Vec3 origin) {
  double six_v = 0;
  for (std::size_t t = 0; t < soup.triangles.size(); ++t) {
    if (topo.flags[t] & SoupTopology::kRepeatedCorner) continue;
    six_v += detail::six_volume(soup, soup.triangles[t], origin);
  }
  return six_v / 6.0;
}

// --- the facts, in the order check.hpp lists them -------------------------------------------

/// Input: sizes, bounding box, vertices, duplicate and unreferenced points.
void record_input(MeshCheck& c, const TriangleSoup& soup, const SoupTopology& topo) {
  c.points = soup.points.size();
  c.triangles = soup.triangles.size();
  c.bbox = bounding_box(soup);
  c.vertices = static_cast<std::uint64_t>(
      std::count(topo.vertex_referenced.begin(), topo.vertex_referenced.end(), true));
  c.duplicate_points = c.points - topo.vertex_count;
  const std::vector<std::uint8_t> used = detail::used_points(soup);
  c.unreferenced_points = static_cast<std::uint64_t>(std::count(used.begin(), used.end(), 0));
}

/// What the whole-mesh facts need to know about the faces.
struct FaceFacts {
  bool any_collinear = false;
  std::uint64_t surface_triangles = 0;  ///< not repeated-corner
  /// Per triangle: degenerate or a duplicate, left out of the self-intersection search.
  std::vector<std::uint8_t> left_out;
};

/// Faces: degenerate and duplicate triangles (with examples), area.
FaceFacts record_faces(MeshCheck& c, const TriangleSoup& soup, const SoupTopology& topo,
                       std::size_t max_examples) {
  FaceFacts faces;
  faces.left_out.assign(soup.triangles.size(), 0);
  for (std::size_t t = 0; t < soup.triangles.size(); ++t) {
    const Triangle& tri = soup.triangles[t];
    bool degenerate = (topo.flags[t] & SoupTopology::kRepeatedCorner) != 0;
    if (!degenerate) {
      ++faces.surface_triangles;
      if (CGAL::collinear(detail::to_cgal(soup.points[tri[0]]),
                          detail::to_cgal(soup.points[tri[1]]),
                          detail::to_cgal(soup.points[tri[2]]))) {
        degenerate = true;
        faces.any_collinear = true;
      }
    }
    if (degenerate && c.degenerate_triangles++ < max_examples)
      c.degenerate_triangle_examples.push_back(static_cast<std::uint32_t>(t));
    if ((topo.flags[t] & SoupTopology::kDuplicate) && c.duplicate_triangles++ < max_examples)
      c.duplicate_triangle_examples.push_back(static_cast<std::uint32_t>(t));
    faces.left_out[t] = degenerate || topo.flags[t] != 0;
    c.area += 0.5 * detail::double_area(soup, tri);
  }
  return faces;
}

/// Edges and vertices: border, non-manifold and inconsistent edges, pinched vertices (with
/// examples).
void record_edges_and_vertices(MeshCheck& c, const TriangleSoup& soup, const SoupTopology& topo,
                               std::size_t max_examples) {
  auto position = [&](std::uint32_t vertex) { return soup.points[topo.merge.first_point[vertex]]; };
  c.edges = topo.edges.size();
  auto location = [&](const detail::EdgeUse& use) {
    const auto& corners = topo.corners[use.triangle];
    return EdgeLocation{{position(corners[use.corner]), position(corners[(use.corner + 1) % 3])},
                        use.triangle};
  };
  for (const detail::Edge& e : topo.edges) {
    const detail::EdgeUse* uses = topo.edge_uses.data() + e.first_use;
    if (e.use_count == 1) {
      if (c.border_edges++ < max_examples) c.border_edge_examples.push_back(location(uses[0]));
    } else if (e.use_count >= 3) {
      if (c.non_manifold_edges++ < max_examples)
        c.non_manifold_edge_examples.push_back(location(uses[0]));
    } else if (uses[0].forward == uses[1].forward) {
      if (c.inconsistent_edges++ < max_examples)
        c.inconsistent_edge_examples.push_back(location(uses[0]));
    }
  }
  for (std::uint32_t v = 0; v < topo.vertex_count; ++v)
    if (topo.fans[v] > 1 && c.non_manifold_vertices++ < max_examples)
      c.non_manifold_vertex_examples.push_back(position(v));
}

/// The halfedge mesh CGAL builds from the repaired soup (empty without polygons). The soup
/// is already a polygon mesh when nothing below is wrong; otherwise it is oriented first,
/// which also duplicates points at non-manifold vertices and edges (polygons keep their
/// order, so mesh face i is still polygon i).
detail::SurfaceMesh build_mesh(RepairedSoup& repaired, const MeshCheck& c) {
  detail::SurfaceMesh mesh;
  if (repaired.polygons.empty()) return mesh;
  if (c.non_manifold_edges > 0 || c.non_manifold_vertices > 0 || c.inconsistent_edges > 0)
    PMP::orient_polygon_soup(repaired.points, repaired.polygons);
  PMP::polygon_soup_to_polygon_mesh(repaired.points, repaired.polygons, mesh);
  if (mesh.number_of_faces() != repaired.polygons.size())
    throw Error("internal error: CGAL built " + std::to_string(mesh.number_of_faces()) +
                " faces from " + std::to_string(repaired.polygons.size()) + " polygons");
  return mesh;
}

/// Self-intersecting pairs, as (i < j) input triangle indices: the search validation runs
/// (the same exact pair test), on the soup with its bit-identical points merged, so shared
/// corners are decided by position; degenerate and duplicate triangles left out.
void record_self_intersections(MeshCheck& c, const TriangleSoup& soup, const SoupTopology& topo,
                               const FaceFacts& faces, std::size_t max_examples) {
  TriangleSoup merged;
  merged.points.reserve(topo.vertex_count);
  for (std::uint32_t v = 0; v < topo.vertex_count; ++v)
    merged.points.push_back(soup.points[topo.merge.first_point[v]]);
  merged.triangles.assign(topo.corners.begin(), topo.corners.end());
  detail::ProgressCounter none(nullptr, "check", 1);
  std::vector<detail::TrianglePair> pairs =
      detail::find_self_intersections(merged, faces.left_out, std::nullopt, none).pairs;
  c.self_intersecting_pairs = pairs.size();
  pairs.resize(std::min(pairs.size(), max_examples));
  c.self_intersection_examples = std::move(pairs);
}

/// Vertices of the non-repeated-corner triangles.
std::int64_t surface_vertices(const SoupTopology& topo) {
  std::int64_t v = 0;
  std::vector<bool> seen(topo.vertex_count, false);
  for (std::size_t t = 0; t < topo.corners.size(); ++t) {
    if (topo.flags[t] & SoupTopology::kRepeatedCorner) continue;
    for (std::uint32_t x : topo.corners[t])
      if (!seen[x]) {
        seen[x] = true;
        ++v;
      }
  }
  return v;
}

/// Volume, orientation and genus; only for a closed, oriented 2-manifold with a surface.
void record_closed_shape(MeshCheck& c, const TriangleSoup& soup, const SoupTopology& topo,
                         const detail::SurfaceMesh& mesh, const FaceFacts& faces) {
  if (!(c.closed() && c.manifold() && c.consistently_oriented() && faces.surface_triangles > 0))
    return;
  const Vec3 centre = c.bbox.centre();
  c.volume = signed_volume(soup, topo, centre);
  // does_bound_a_volume() checks that nested shells alternate in orientation, but it also
  // accepts a mesh whose outermost shells are all inside out (it then bounds the unbounded
  // complement): the sign of the volume tells those apart. It is undefined for
  // self-intersecting meshes and relies on non-degenerate faces; there, and when
  // self-intersections were not searched for, the sign of the volume alone decides.
  const bool bounds = c.self_intersecting_pairs == std::uint64_t{0} && !faces.any_collinear &&
                              c.duplicate_triangles == 0
                          ? PMP::does_bound_a_volume(mesh)
                          : true;
  c.outward = bounds && *c.volume > 0;
  const std::int64_t euler = surface_vertices(topo) - static_cast<std::int64_t>(c.edges) +
                             static_cast<std::int64_t>(faces.surface_triangles);
  c.genus = (2 * static_cast<std::int64_t>(topo.surface_components) - euler) / 2;
}

}  // namespace

namespace {

// Lengths, areas, volumes and locations × f, f², f³ (f: millimetres per model unit).
void facts_in_millimetres(MeshCheck& c, double f) {
  if (f == 1) return;
  if (!c.bbox.empty()) c.bbox = {f * c.bbox.min, f * c.bbox.max};
  c.area *= f * f;
  if (c.volume) *c.volume *= f * f * f;
  for (auto* edges :
       {&c.border_edge_examples, &c.non_manifold_edge_examples, &c.inconsistent_edge_examples})
    for (EdgeLocation& e : *edges) e.ends = {f * e.ends[0], f * e.ends[1]};
  for (Vec3& p : c.non_manifold_vertex_examples) p = f * p;
}

}  // namespace

MeshCheck check_mesh(const TriangleSoup& soup, const CheckOptions& options) {
  require_valid(options.units);
  detail::require_32bit_mesh(soup, "check");
  MeshCheck c;
  c.merged_points = true;
  const SoupTopology topo = detail::analyze_soup(soup);
  record_input(c, soup, topo);
  const FaceFacts faces = record_faces(c, soup, topo, options.max_examples);
  record_edges_and_vertices(c, soup, topo, options.max_examples);
  c.components = topo.vertex_components;
  c.edge_components = topo.edge_components;

  // CGAL, on the soup it would repair: holes, self-intersections, bounded volume.
  RepairedSoup repaired = repaired_soup(soup, topo);
  const detail::SurfaceMesh mesh = build_mesh(repaired, c);
  std::vector<detail::SurfaceMesh::Halfedge_index> cycles;
  if (!repaired.polygons.empty()) PMP::extract_boundary_cycles(mesh, std::back_inserter(cycles));
  c.holes = cycles.size();
  if (options.self_intersections)
    record_self_intersections(c, soup, topo, faces, options.max_examples);
  record_closed_shape(c, soup, topo, mesh, faces);
  facts_in_millimetres(c, options.units.factor());
  return c;
}

RoundingCheck check_rounding(const TriangleSoup& soup, CoordinateRounding rounding) {
  const CheckOptions facts{.self_intersections = false};
  RoundingCheck r;
  r.degenerate = r.held_degenerate = check_mesh(soup, facts).degenerate_triangles;
  if (rounding == CoordinateRounding::None) return r;
  TriangleSoup held = soup;
  round_coordinates(rounding, held);
  r.held_degenerate = check_mesh(held, facts).degenerate_triangles;
  if (r.held_degenerate <= r.degenerate) return r;
  const Box3 b = bounding_box(held);
  const double reach = std::max({std::fabs(b.min.x), std::fabs(b.min.y), std::fabs(b.min.z),
                                 std::fabs(b.max.x), std::fabs(b.max.y), std::fabs(b.max.z)});
  const char* as = rounding == CoordinateRounding::Float     ? "STL's floats"
                   : rounding == CoordinateRounding::ThreeMf ? "3MF's micrometres"
                                                             : "six decimals";
  r.warning = std::to_string(r.held_degenerate - r.degenerate) +
              " triangles are degenerate once their coordinates are rounded to " + as + ", " +
              std::to_string(static_cast<long long>(reach)) +
              " mm from the origin: write PLY, OBJ or OFF, which hold doubles, or move the part "
              "nearer the origin";
  return r;
}

}  // namespace tpmsfill
