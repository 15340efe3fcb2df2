// Stage "repair": CGAL PMP on the exact-predicate kernel turns a defective soup into a closed,
// outward 2-manifold without self-intersections; an alpha wrap (repair_wrap.cpp) is the
// fallback. The steps are listed in repair.hpp; the report's wording is in repair_report.cpp.
//
// Robustness: some of these CGAL 5.5 functions (autorefinement above all, which is
// experimental) can fail on real input. Release builds compile CGAL's checks out, and a
// failed one then runs on into a crash; CGAL_DEBUG keeps them in this file, so a failure is a
// CGAL::Failure_exception, caught below per step: the step is undone (each works on a copy or
// is retried without the failing hole) and the pipeline goes on, to the wrap if need be.
#define CGAL_DEBUG 1
#define EIGEN_NO_DEBUG 1  // Eigen's checks abort() rather than throw: leave them out

#include "tpmsfill/repair.hpp"

#include <CGAL/Polygon_mesh_processing/border.h>
#include <CGAL/Polygon_mesh_processing/connected_components.h>
#include <CGAL/Polygon_mesh_processing/corefinement.h>
#include <CGAL/Polygon_mesh_processing/manifoldness.h>
#include <CGAL/Polygon_mesh_processing/measure.h>
#include <CGAL/Polygon_mesh_processing/orient_polygon_soup.h>
#include <CGAL/Polygon_mesh_processing/orientation.h>
#include <CGAL/Polygon_mesh_processing/polygon_soup_to_polygon_mesh.h>
#include <CGAL/Polygon_mesh_processing/repair.h>
#include <CGAL/Polygon_mesh_processing/repair_degeneracies.h>
#include <CGAL/Polygon_mesh_processing/repair_polygon_soup.h>
#include <CGAL/Polygon_mesh_processing/repair_self_intersections.h>
#include <CGAL/Polygon_mesh_processing/self_intersections.h>
#include <CGAL/Polygon_mesh_processing/shape_predicates.h>
#include <CGAL/Polygon_mesh_processing/stitch_borders.h>
#include <CGAL/Polygon_mesh_processing/triangulate_hole.h>
#if defined(CGAL_EIGEN3_ENABLED)
#include <CGAL/Polygon_mesh_processing/fair.h>
#endif

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <iterator>
#include <map>
#include <mutex>
#include <numeric>
#include <optional>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

#include "core/index_limits.hpp"
#include "core/stage_progress.hpp"
#include "mesh/cgal_types.hpp"
#include "mesh/mesh_measures.hpp"
#include "mesh/soup_indices.hpp"
#include "mesh/surface_deviation.hpp"
#include "repair/internal/alpha_wrap.hpp"
#include "repair/internal/winding_solid.hpp"
#include "tpmsfill/decimate.hpp"
#include "tpmsfill/error.hpp"
#include "tpmsfill/mesh/components.hpp"

namespace PMP = CGAL::Polygon_mesh_processing;

namespace tpmsfill {
namespace {

using detail::Point3;
using detail::SurfaceMesh;
using Face = SurfaceMesh::Face_index;
using Halfedge = SurfaceMesh::Halfedge_index;
using Vertex = SurfaceMesh::Vertex_index;

/// Holes with more border edges than this are filled with the Delaunay-based searches only:
/// the exhaustive one is cubic in the edge count (400 edges: about 6·10^7 candidates).
constexpr std::size_t kMaxCubicHole = 400;

/// A vertex's position as plain data.
Vec3 position(const SurfaceMesh& mesh, Vertex v) {
  const Point3& p = mesh.point(v);
  return {p.x(), p.y(), p.z()};
}

/// A face's first three vertices (every face here is a triangle), in the face's order.
std::array<Vertex, 3> face_vertices(const SurfaceMesh& mesh, Face f) {
  std::array<Vertex, 3> c{};
  int k = 0;
  for (Vertex v : CGAL::vertices_around_face(mesh.halfedge(f), mesh)) {
    if (k == 3) break;
    c[k++] = v;
  }
  return c;
}

/// The mesh as a soup: vertices that some face uses, in index order; faces in index order.
TriangleSoup to_soup(const SurfaceMesh& mesh) {
  TriangleSoup soup;
  std::vector<std::uint32_t> index(mesh.num_vertices(), detail::kNoIndex);
  soup.triangles.reserve(mesh.number_of_faces());
  for (Face f : mesh.faces()) {
    const std::array<Vertex, 3> c = face_vertices(mesh, f);
    soup.triangles.push_back({c[0].idx(), c[1].idx(), c[2].idx()});
  }
  for (Vertex v : mesh.vertices()) {
    // Only referenced vertices are kept (component removal leaves isolated ones).
    if (mesh.is_isolated(v)) continue;
    index[v.idx()] = static_cast<std::uint32_t>(soup.points.size());
    soup.points.push_back(position(mesh, v));
  }
  for (Triangle& t : soup.triangles)
    for (std::uint32_t& v : t) v = index[v];
  return soup;
}

std::uint64_t count_degenerate_faces(const SurfaceMesh& mesh) {
  std::vector<Face> faces;
  PMP::degenerate_faces(mesh, std::back_inserter(faces));
  return faces.size();
}

std::uint64_t count_self_intersections(const SurfaceMesh& mesh) {
  std::vector<std::pair<Face, Face>> pairs;
  PMP::self_intersections<CGAL::Parallel_if_available_tag>(mesh.faces(), mesh,
                                                           std::back_inserter(pairs));
  return static_cast<std::uint64_t>(
      std::count_if(pairs.begin(), pairs.end(), [](const auto& p) { return p.first != p.second; }));
}

/// A face's corners as a cyclic sequence with the smallest vertex first, so that a reversed
/// face compares unequal and a merely rotated one equal.
std::array<std::uint32_t, 3> cyclic_corners(const SurfaceMesh& mesh, Face f) {
  const std::array<Vertex, 3> v = face_vertices(mesh, f);
  std::array<std::uint32_t, 3> c{v[0].idx(), v[1].idx(), v[2].idx()};
  std::rotate(c.begin(), std::min_element(c.begin(), c.end()), c.end());
  return c;
}

std::uint64_t orient_shells_unguarded(SurfaceMesh& mesh, bool bound_volume);

/// Orients every closed shell outward, each on its own (PMP::orient) or, when `bound_volume`,
/// so that nested shells alternate and the mesh bounds a volume (PMP::orient_to_bound_a_volume,
/// which needs a mesh without self-intersections). Returns how many shells were reversed.
/// Precondition: the mesh is closed. If CGAL fails (it needs a non-degenerate neighbourhood
/// around each shell's topmost vertex), the mesh is left as it was and 0 returned.
std::uint64_t orient_shells(SurfaceMesh& mesh, bool bound_volume) {
  SurfaceMesh backup = mesh;
  try {
    return orient_shells_unguarded(mesh, bound_volume);
  } catch (const CGAL::Failure_exception&) {
    mesh = std::move(backup);
    return 0;
  }
}

std::uint64_t orient_shells_unguarded(SurfaceMesh& mesh, bool bound_volume) {
  auto fccmap = mesh.add_property_map<Face, std::size_t>("f:repair_orient", 0).first;
  const std::size_t n = PMP::connected_components(mesh, fccmap);
  std::vector<std::array<std::uint32_t, 3>> corners;
  corners.reserve(mesh.number_of_faces());
  for (Face f : mesh.faces()) corners.push_back(cyclic_corners(mesh, f));
  if (bound_volume)
    PMP::orient_to_bound_a_volume(mesh);
  else
    PMP::orient(mesh);
  std::vector<bool> flipped(n, false);
  for (Face f : mesh.faces())
    if (cyclic_corners(mesh, f) != corners[f.idx()]) flipped[fccmap[f]] = true;
  mesh.remove_property_map(fccmap);
  return static_cast<std::uint64_t>(std::count(flipped.begin(), flipped.end(), true));
}

/// Removes collinear faces; returns how many degenerate faces remain. Unchanged if CGAL fails.
std::uint64_t remove_degenerate(SurfaceMesh& mesh) {
  const std::uint64_t found = count_degenerate_faces(mesh);
  if (found == 0) return 0;
  SurfaceMesh work = mesh;
  try {
    PMP::remove_degenerate_faces(work);
  } catch (const CGAL::Failure_exception&) {
    return found;
  }
  work.collect_garbage();
  mesh = std::move(work);
  return count_degenerate_faces(mesh);
}

struct HoleCounts {
  std::uint64_t found = 0, filled = 0, faired = 0, flat = 0, fairing_undone = 0;
};

// A hole's rim: its points' box, its diameter (the box's diagonal) and whether it lies in one
// plane (within a thousandth of its diameter, Newell's normal through the rim's centroid).
struct Rim {
  Box3 box;
  double diameter = 0;
  bool planar = false;
};

Rim rim_of(const SurfaceMesh& mesh, Halfedge h) {
  std::vector<Vec3> p;
  for (Halfedge e : CGAL::halfedges_around_face(h, mesh))
    p.push_back(position(mesh, mesh.target(e)));
  Rim rim;
  Vec3 normal{}, centroid{};
  for (std::size_t i = 0; i < p.size(); ++i) {
    const Vec3 a = p[i], b = p[(i + 1) % p.size()];
    normal = normal +
             Vec3{(a.y - b.y) * (a.z + b.z), (a.z - b.z) * (a.x + b.x), (a.x - b.x) * (a.y + b.y)};
    centroid = centroid + (1.0 / static_cast<double>(p.size())) * a;
    rim.box.extend(a);
  }
  rim.diameter = norm(rim.box.size());
  const double length = norm(normal);
  if (length == 0) return rim;
  double off_plane = 0;
  for (const Vec3& q : p)
    off_plane = std::max(off_plane, std::fabs(dot(q - centroid, normal)) / length);
  rim.planar = off_plane <= 1e-3 * rim.diameter;
  return rim;
}

// Fairing may not grow a dome out of its hole: every new vertex stays within the rim's box
// grown by a tenth of the rim's diameter, and within the part's own box.
bool within_rim(const SurfaceMesh& mesh, const std::vector<Vertex>& inner, const Rim& rim,
                const Box3& part) {
  const double margin = 0.1 * rim.diameter;
  for (Vertex v : inner) {
    const Vec3 q = position(mesh, v);
    for (int a = 0; a < 3; ++a)
      if (q[a] < std::max(rim.box.min[a] - margin, part.min[a]) ||
          q[a] > std::min(rim.box.max[a] + margin, part.max[a]))
        return false;
  }
  return true;
}

/// Fills one hole: flat if planar; else triangulated and refined, then faired where the
/// patch stays within its rim; the exhaustive triangulation alone as the last resort.
/// Returns whether faces were added (marked in the "f:patch" property); counts what it did.
bool fill_hole(SurfaceMesh& mesh, Halfedge h, bool fair, const Box3& part, HoleCounts& counts) {
  // `part` is the part's box grown by the tolerance.
  const std::size_t edges = CGAL::halfedges_around_face(h, mesh).size();
  const bool cubic_too = edges <= kMaxCubicHole;
  const Rim rim = rim_of(mesh, h);
  const auto np = CGAL::parameters::use_2d_constrained_delaunay_triangulation(true)
                      .use_delaunay_triangulation(true)
                      .do_not_use_cubic_algorithm(!cubic_too);
  std::vector<Face> patch;
  std::vector<Vertex> inner;
  if (rim.planar) {
    PMP::triangulate_hole(mesh, h, std::back_inserter(patch), np);
    if (!patch.empty()) ++counts.flat;
  }
  if (patch.empty() && mesh.is_border(h)) {
    PMP::triangulate_and_refine_hole(mesh, h, std::back_inserter(patch), std::back_inserter(inner),
                                     np);
#if defined(CGAL_EIGEN3_ENABLED)
    if (fair && !patch.empty() && !inner.empty()) {
      std::vector<Point3> refined;
      for (Vertex v : inner) refined.push_back(mesh.point(v));
      const bool faired = PMP::fair(mesh, inner);
      if (faired && within_rim(mesh, inner, rim, part)) {
        ++counts.faired;
      } else {
        for (std::size_t i = 0; i < inner.size(); ++i) mesh.point(inner[i]) = refined[i];
        if (faired) ++counts.fairing_undone;
      }
    }
#else
    (void)fair;  // built without Eigen: no fairing
#endif
  }
  // Last resort: no Delaunay search space at all, only the exhaustive one.
  if (patch.empty() && mesh.is_border(h) && cubic_too)
    PMP::triangulate_hole(mesh, h, std::back_inserter(patch),
                          CGAL::parameters::use_delaunay_triangulation(false)
                              .use_2d_constrained_delaunay_triangulation(false));
  auto is_patch = mesh.property_map<Face, bool>("f:patch").first;
  for (Face f : patch) is_patch[f] = true;
  return !patch.empty();
}

/// Fills every border cycle (step 4), marking the patches' faces. A hole whose filling fails
/// inside CGAL is left open: the mesh is restored and the holes are filled again without it.
HoleCounts fill_holes(SurfaceMesh& mesh, bool fair, double tolerance, Progress* progress) {
  std::vector<Halfedge> cycles;
  PMP::extract_boundary_cycles(mesh, std::back_inserter(cycles));
  HoleCounts counts;
  counts.found = cycles.size();
  if (cycles.empty()) return counts;
  mesh.add_property_map<Face, bool>("f:patch", false);
  Box3 part;
  for (Vertex v : mesh.vertices()) part.extend(position(mesh, v));
  const double grow = tolerance > 0 ? tolerance : 0.01 * norm(part.size());
  part = {part.min - Vec3{grow, grow, grow}, part.max + Vec3{grow, grow, grow}};
  const SurfaceMesh original = mesh;  // halfedge indices stay valid in copies
  std::vector<bool> skip(cycles.size(), false);
  for (;;) {
    counts = {.found = counts.found};
    std::size_t i = 0;
    try {
      for (; i < cycles.size(); ++i) {
        detail::report_or_cancel(progress,
                                 static_cast<double>(i) / static_cast<double>(cycles.size()));
        if (skip[i] || !mesh.is_border(cycles[i])) continue;
        if (fill_hole(mesh, cycles[i], fair, part, counts)) ++counts.filled;
      }
      break;
    } catch (const CGAL::Failure_exception&) {
      skip[i] = true;
      mesh = original;
    }
  }
  detail::report_or_cancel(progress, 1.0);
  return counts;
}

RepairAction action(std::string defect, std::uint64_t found, std::string done,
                    std::uint64_t fixed) {
  if (found == 0) done.clear();
  return RepairAction{std::move(defect), found, std::move(done), fixed};
}

/// Where a CGAL check failed, for a sentence: "an internal check in its Visitor.h". CGAL's own
/// text (the failed expression, its bug-reporting plea) means nothing to a user.
std::string cgal_check_place(const std::string& file) {
  const std::string name = std::filesystem::path(file).filename().string();
  return name.empty() ? "an internal check" : "an internal check in its " + name;
}

/// Puts the soup in an order that depends only on its geometry, not on how CGAL happened to
/// number what it made (autorefinement numbers new elements in an order that varies from run
/// to run): each triangle rotated to start at its lexicographically smallest corner, triangles
/// sorted by their corners' coordinates, points numbered by first use. Two points at one
/// position (split at a pinch) stay two: each is numbered where its first triangle comes.
void canonical_order(TriangleSoup& soup) {
  using Key = std::array<double, 9>;
  auto less_point = [](const Vec3& a, const Vec3& b) {
    return std::tie(a.x, a.y, a.z) < std::tie(b.x, b.y, b.z);
  };
  std::vector<Key> keys(soup.triangles.size());
  for (std::size_t t = 0; t < soup.triangles.size(); ++t) {
    Triangle& tri = soup.triangles[t];
    int first = 0;
    for (int k = 1; k < 3; ++k)
      if (less_point(soup.points[tri[k]], soup.points[tri[first]])) first = k;
    std::rotate(tri.begin(), tri.begin() + first, tri.end());
    for (int k = 0; k < 3; ++k) {
      const Vec3& p = soup.points[tri[k]];
      keys[t][3 * k] = p.x;
      keys[t][3 * k + 1] = p.y;
      keys[t][3 * k + 2] = p.z;
    }
  }
  std::vector<std::uint32_t> order(soup.triangles.size());
  for (std::uint32_t t = 0; t < order.size(); ++t) order[t] = t;
  std::stable_sort(order.begin(), order.end(),
                   [&](std::uint32_t a, std::uint32_t b) { return keys[a] < keys[b]; });
  TriangleSoup out;
  out.triangles.reserve(soup.triangles.size());
  std::vector<std::uint32_t> index(soup.points.size(), detail::kNoIndex);
  for (std::uint32_t t : order) {
    Triangle tri = soup.triangles[t];
    for (std::uint32_t& v : tri) {
      if (index[v] == detail::kNoIndex) {
        index[v] = static_cast<std::uint32_t>(out.points.size());
        out.points.push_back(soup.points[v]);
      }
      v = index[v];
    }
    out.triangles.push_back(tri);
  }
  soup = std::move(out);
}

void check_options(const RepairOptions& o) {
  if (!(o.min_component_fraction >= 0 && o.min_component_fraction < 1))
    throw InputError("the small-component fraction must be in [0, 1), not " +
                     std::to_string(o.min_component_fraction));
  if (!(o.alpha >= 0 && std::isfinite(o.alpha)))
    throw InputError("alpha must be a positive length in mm (0 = derived from the mesh size)");
  if (!(o.offset >= 0 && std::isfinite(o.offset)))
    throw InputError("the wrap offset must be a positive length in mm (0 = alpha / 30)");
  if (!(o.voxel >= 0 && std::isfinite(o.voxel)))
    throw InputError("the voxel must be a positive length in mm (0 = half the tolerance)");
}

/// What steps 1-6 did, for the log.
struct Counts {
  std::uint64_t stitched = 0, pinched = 0, degenerate_left = 0, specks = 0;
  HoleCounts holes;
  std::uint64_t si_found = 0, si_fixed = 0, inward_shells = 0;
  std::uint64_t separated = 0;  ///< vertices pulled apart from others at their position
  std::string si_action = "left (self-intersection removal off)";
};

/// Numbers distinct points in lexicographic order of their positions, starts each polygon at
/// its smallest number (keeping its orientation) and sorts the polygons. The steps after it
/// depend on the order they meet elements in; a file's order says nothing about the part, so
/// one mesh in any encoding (STL, OBJ, PLY, OFF number it differently) repairs alike.
void order_by_position(std::vector<Point3>& points,
                       std::vector<std::array<std::size_t, 3>>& polygons) {
  std::vector<std::size_t> by_position(points.size());
  std::iota(by_position.begin(), by_position.end(), std::size_t{0});
  std::stable_sort(by_position.begin(), by_position.end(), [&](std::size_t a, std::size_t b) {
    return CGAL::compare_xyz(points[a], points[b]) == CGAL::SMALLER;
  });
  std::vector<std::size_t> number(points.size());
  std::vector<Point3> sorted(points.size());
  for (std::size_t i = 0; i < by_position.size(); ++i) {
    number[by_position[i]] = i;
    sorted[i] = points[by_position[i]];
  }
  points = std::move(sorted);
  for (auto& polygon : polygons) {
    for (std::size_t& v : polygon) v = number[v];
    std::rotate(polygon.begin(), std::min_element(polygon.begin(), polygon.end()), polygon.end());
  }
  std::sort(polygons.begin(), polygons.end());
}

/// Step 1: the soup cleaned and oriented, as a halfedge mesh.
SurfaceMesh mesh_from_soup(const TriangleSoup& input) {
  std::vector<Point3> points;
  points.reserve(input.points.size());
  for (const Vec3& p : input.points) points.push_back(detail::to_cgal(p));
  std::vector<std::array<std::size_t, 3>> polygons;
  polygons.reserve(input.triangles.size());
  for (const Triangle& t : input.triangles) polygons.push_back({t[0], t[1], t[2]});
  // repair_polygon_soup() on triangles (std::array) keeps repeated-corner ones: its steps one
  // by one, dropping those after the merge.
  PMP::merge_duplicate_points_in_polygon_soup(points, polygons);
  order_by_position(points, polygons);
  std::erase_if(polygons, detail::repeated_corner<std::size_t>);
  PMP::merge_duplicate_polygons_in_polygon_soup(points, polygons);
  PMP::remove_isolated_points_in_polygon_soup(points, polygons);
  if (polygons.empty())
    throw InputError("no triangle has three distinct corners: there is no surface to repair");
  PMP::orient_polygon_soup(points, polygons);
  if (!PMP::is_polygon_soup_a_polygon_mesh(polygons))
    throw Error("internal error: the oriented soup is not a polygon mesh");
  SurfaceMesh mesh;
  PMP::polygon_soup_to_polygon_mesh(points, polygons, mesh);
  return mesh;
}

/// What steps 1-6 made and did. When a step fails inside CGAL where no per-step guard
/// catches it, `failure` says so and the other fields hold what the steps before it did.
struct Steps {
  SurfaceMesh mesh;                      ///< after step 6
  SurfaceMesh filled;                    ///< after step 4: what the wrap wraps
  Counts counts;                         ///< for the log
  std::uint64_t components = 0;          ///< RepairReport::components
  double small_component_threshold = 0;  ///< RepairReport::small_component_threshold
  std::uint64_t holes_faired = 0;        ///< RepairReport::holes_faired
  std::optional<std::string> failure;
};

/// Step 3: removes components below the threshold; returns how many. Records the component
/// count and the threshold in `steps`.
std::uint64_t remove_small_components(SurfaceMesh& mesh, double fraction, Steps& steps) {
  auto fccmap = mesh.add_property_map<Face, std::size_t>("f:repair_cc", 0).first;
  const std::size_t n = PMP::connected_components(mesh, fccmap);
  std::vector<double> area(n, 0.0);
  for (Face f : mesh.faces()) area[fccmap[f]] += PMP::face_area(f, mesh);
  const double largest = n ? *std::max_element(area.begin(), area.end()) : 0.0;
  steps.components = n;
  steps.small_component_threshold = fraction * largest;
  std::vector<std::size_t> remove;
  for (std::size_t c = 0; c < n; ++c)
    if (area[c] < steps.small_component_threshold) remove.push_back(c);
  if (!remove.empty()) {
    PMP::remove_connected_components(mesh, remove, fccmap);
    PMP::remove_isolated_vertices(mesh);
  }
  mesh.remove_property_map(fccmap);
  mesh.collect_garbage();
  return remove.size();
}

/// Accepts a candidate for step 5 if it has faces, no degenerate ones, no self-intersections,
/// and is closed if `closed`.
bool acceptable(SurfaceMesh& candidate, bool closed) {
  candidate.collect_garbage();
  if (candidate.is_empty() || (closed && !CGAL::is_closed(candidate))) return false;
  PMP::duplicate_non_manifold_vertices(candidate);
  return remove_degenerate(candidate) == 0 && count_self_intersections(candidate) == 0;
}

/// Signed volume (mm^3, about `origin`) of each edge-connected component.
std::vector<double> shell_volumes(SurfaceMesh& mesh, Vec3 origin) {
  auto fccmap = mesh.add_property_map<Face, std::size_t>("f:repair_volume", 0).first;
  const std::size_t n = PMP::connected_components(mesh, fccmap);
  std::vector<double> six_v(n, 0.0);
  for (Face f : mesh.faces()) {
    const std::array<Vertex, 3> c = face_vertices(mesh, f);
    six_v[fccmap[f]] += detail::six_volume(origin, position(mesh, c[0]), position(mesh, c[1]),
                                           position(mesh, c[2]));
  }
  mesh.remove_property_map(fccmap);
  for (double& v : six_v) v /= 6.0;
  return six_v;
}

/// Whether a candidate's volume is one that removing self-intersections can give: at least
/// 90% of the smaller of the largest shell and the total (a union is no smaller than its
/// largest part; voids count negative), at most 101% of the shells' positive volumes summed.
/// Rejects an autorefinement that kept the wrong side (CGAL 5.5's is experimental).
bool plausible_volume(const std::vector<double>& before, double after) {
  double largest = 0, total = 0, positive = 0;
  for (double v : before) {
    largest = std::max(largest, v);
    total += v;
    positive += std::max(v, 0.0);
  }
  return after >= 0.9 * std::min(largest, total) && after <= 1.01 * positive;
}

/// Step 5: autorefinement (keeps the outer hull), else local remeshing, each on a copy.
void resolve_self_intersections(SurfaceMesh& mesh, Counts& counts, Progress* progress) {
  counts.si_action = "not resolved";
  const bool closed = CGAL::is_closed(mesh);
  Box3 box;
  for (Vertex v : mesh.vertices()) box.extend(position(mesh, v));
  const Vec3 origin = box.centre();
  const std::vector<double> before = closed ? shell_volumes(mesh, origin) : std::vector<double>{};
  auto volume_ok = [&](SurfaceMesh& candidate) {
    if (!closed) return true;
    double after = 0;
    for (double v : shell_volumes(candidate, origin)) after += v;
    return plausible_volume(before, after);
  };
  try {
    SurfaceMesh refined = mesh;
    if (PMP::experimental::autorefine_and_remove_self_intersections(refined) &&
        acceptable(refined, closed) && volume_ok(refined)) {
      mesh = std::move(refined);
      counts.si_fixed = counts.si_found;
      counts.si_action = "autorefined, inner patches removed (overlapping shells united)";
      return;
    }
  } catch (const CGAL::Failure_exception&) {
    // CGAL 5.5's experimental autorefinement fails on some inputs: try the local way.
  }
  detail::report_or_cancel(progress, 0.5);
  try {
    SurfaceMesh local = mesh;
    if (PMP::experimental::remove_self_intersections(local) && acceptable(local, closed) &&
        volume_ok(local)) {
      mesh = std::move(local);
      counts.si_fixed = counts.si_found;
      counts.si_action = "removed by local remeshing";
    }
  } catch (const CGAL::Failure_exception&) {
  }
}

/// CGAL's failure as one of RepairReport::unresolved's sentences.
std::string step_failure(const CGAL::Failure_exception& e) {
  return "a repair step failed inside CGAL (" + cgal_check_place(e.filename()) + ")";
}

/// Steps 1-4: the soup as a mesh, stitched, without specks, holes filled. Writes into `s`
/// as it goes.
void repair_surface(const TriangleSoup& input, const RepairOptions& options, Steps& s) {
  Progress* progress = options.progress;
  detail::begin_stage(progress, "repair soup");
  s.mesh = mesh_from_soup(input);
  detail::report_or_cancel(progress, 0.5);

  // --- 2. stitch, split pinched vertices, remove collinear faces ---------------------------
  s.counts.stitched = PMP::stitch_borders(s.mesh);
  s.counts.pinched = PMP::duplicate_non_manifold_vertices(s.mesh);
  s.counts.degenerate_left = remove_degenerate(s.mesh);
  detail::report_or_cancel(progress, 1.0);

  // --- 3. small components ---------------------------------------------------------------
  detail::begin_stage(progress, "components");
  s.counts.specks = remove_small_components(s.mesh, options.min_component_fraction, s);
  detail::report_or_cancel(progress, 1.0);

  // --- 4. holes -------------------------------------------------------------------------
  if (options.fill_holes) {
    detail::begin_stage(progress, "fill holes");
    s.counts.holes = fill_holes(s.mesh, options.fair_holes, options.tolerance, progress);
    s.mesh.collect_garbage();
    // A patch may pinch a vertex where a hole's border touches itself, or have a collinear
    // triangle where the border has three collinear corners.
    s.counts.pinched += PMP::duplicate_non_manifold_vertices(s.mesh);
    remove_degenerate(s.mesh);
  } else {
    std::vector<Halfedge> cycles;
    PMP::extract_boundary_cycles(s.mesh, std::back_inserter(cycles));
    s.counts.holes.found = cycles.size();
  }
  s.holes_faired = s.counts.holes.faired;
  s.filled = s.mesh;
}

/// Pulls apart vertices that share a position (sheets that touch at a point, split into one
/// vertex per fan, but still one point in a file): each moves 1 % of the way to its own
/// neighbours' centroid, into its own fan, so that no reader welds them again. The final
/// check decides whether that made the mesh valid. Returns how many vertices moved.
std::uint64_t separate_pinches(SurfaceMesh& mesh) {
  PMP::duplicate_non_manifold_vertices(mesh);
  std::map<std::array<double, 3>, std::vector<Vertex>> at;
  for (Vertex v : mesh.vertices()) {
    if (mesh.is_isolated(v)) continue;
    const Point3& p = mesh.point(v);
    at[{p.x(), p.y(), p.z()}].push_back(v);
  }
  std::vector<std::pair<Vertex, Vec3>> moves;
  for (const auto& [p, group] : at) {
    if (group.size() < 2) continue;
    for (Vertex v : group) {
      Vec3 centroid{};
      double n = 0;
      for (Vertex w : CGAL::vertices_around_target(mesh.halfedge(v), mesh)) {
        centroid = centroid + position(mesh, w);
        ++n;
      }
      const Vec3 q = position(mesh, v);
      moves.emplace_back(v, q + 0.01 * ((1.0 / n) * centroid - q));
    }
  }
  for (const auto& [v, q] : moves) mesh.point(v) = detail::to_cgal(q);
  return moves.size();
}

/// Steps 5-6 on s.mesh: self-intersections resolved, shells oriented.
void resolve_and_orient(const RepairOptions& options, Steps& s) {
  SurfaceMesh& mesh = s.mesh;
  detail::begin_stage(options.progress, "self-intersections");
  // Autorefinement keeps the outside of each shell, as its orientation says: orient first.
  if (!mesh.is_empty() && CGAL::is_closed(mesh))
    s.counts.inward_shells = orient_shells(mesh, false);
  s.counts.si_found = count_self_intersections(mesh);
  if (s.counts.si_found > 0 && options.self_intersections)
    resolve_self_intersections(mesh, s.counts, options.progress);
  detail::report_or_cancel(options.progress, 1.0);

  // --- 6. orientation -------------------------------------------------------------------
  if (!mesh.is_empty() && CGAL::is_closed(mesh) && count_self_intersections(mesh) == 0)
    s.counts.inward_shells += orient_shells(mesh, true);
  s.counts.separated = separate_pinches(mesh);
}

/// Steps 1-6.
Steps repair_steps(const TriangleSoup& input, const RepairOptions& options) {
  Steps s;
  try {
    repair_surface(input, options, s);
    resolve_and_orient(options, s);
  } catch (const CGAL::Failure_exception& e) {
    // A step the per-step guards do not cover failed: what is left to try is the wrap.
    s.failure = step_failure(e);
  }
  return s;
}

/// The log: one action per defect class, in RepairReport::actions' order.
std::vector<RepairAction> write_log(const MeshCheck& before, const Counts& c,
                                    const RepairOptions& options) {
  std::vector<RepairAction> a;
  a.push_back(action("duplicate points", before.duplicate_points,
                     "merged (bit-identical positions)", before.duplicate_points));
  a.push_back(action("degenerate triangles", before.degenerate_triangles,
                     "removed (repeated corners from the soup, collinear ones by edge collapse "
                     "and flip)",
                     before.degenerate_triangles -
                         std::min<std::uint64_t>(before.degenerate_triangles, c.degenerate_left)));
  a.push_back(action("duplicate triangles", before.duplicate_triangles, "removed",
                     before.duplicate_triangles));
  a.push_back(action("inconsistently oriented edges", before.inconsistent_edges,
                     "faces re-oriented consistently", before.inconsistent_edges));
  a.push_back(action("non-manifold edges", before.non_manifold_edges, "split into manifold sheets",
                     before.non_manifold_edges));
  a.push_back(action("non-manifold vertices", before.non_manifold_vertices + c.pinched,
                     c.separated ? "split (one vertex per fan), the fans pulled apart"
                                 : "split (one vertex per fan)",
                     before.non_manifold_vertices + c.pinched));
  a.push_back(action("coincident border edge pairs", c.stitched, "stitched", c.stitched));
  a.push_back(action("small components", c.specks, "removed", c.specks));
  a.push_back(action("holes", c.holes.found,
                     options.fill_holes ? "filled (triangulated, refined, faired where possible)"
                                        : "left (hole filling off)",
                     c.holes.filled));
  a.push_back(action("self-intersecting triangle pairs", c.si_found, c.si_action, c.si_fixed));
  a.push_back(action("shells oriented inward", c.inward_shells, "reversed", c.inward_shells));
  return a;
}

/// Rounds the result as its file will hold it. Rounding can break a valid repair (two faces a few
/// ulps apart now touch, a sliver turns degenerate): then the rounded mesh is repaired again, at
/// most twice, as long as that does not change the solid.
void round_result(RepairResult& result, const RepairOptions& options) {
  RepairReport& report = result.report;
  const bool valid_in_double = report.after.valid();
  round_coordinates(options.rounding, result.mesh);
  report.after = check_mesh(result.mesh);
  const std::optional<double> volume = report.after.volume;
  while (valid_in_double && !report.after.valid() && report.float_repasses < 2) {
    ++report.float_repasses;
    const Steps again = repair_steps(result.mesh, options);
    if (again.failure) break;
    try {
      TriangleSoup next = to_soup(again.mesh);
      canonical_order(next);
      round_coordinates(options.rounding, next);
      const MeshCheck check = check_mesh(next);
      // A repair of rounding errors must not change the solid.
      if (volume &&
          !(check.volume && std::fabs(*check.volume - *volume) <= 0.01 * std::fabs(*volume)))
        break;
      result.mesh = std::move(next);
      report.after = check;
    } catch (const CGAL::Failure_exception&) {
      break;
    }
  }
}

/// The reference a repair is measured against: the input as cleaned, with its hole patches
/// (`all`), and without them (`surface`, what the output must stay near).
struct Reference {
  TriangleSoup all, surface;
  Box3 input_box;
  /// Where shells may overlap or nest (several components, or self-intersections), the summed
  /// signed volume of `all` counts what they share twice: volumes are then measured as the
  /// winding-number solid's, input and output on this one grid of rays.
  std::optional<Grid> volume_grid;
  double volume = 0;  ///< the input's solid volume, mm³ (magnitude)
};

/// Rays per bounding-box diagonal of the grid that measures volumes where shells overlap: with
/// its 5 % margins at most 1.1³·400³/√27 ≈ 1.6·10⁷ nodes (a cube) and 6.5·10⁴ rays.
constexpr double kVolumeRaysPerDiagonal = 400;

double summed_volume(const TriangleSoup& soup) {
  double six = 0;
  for (const Triangle& t : soup.triangles) six += detail::six_volume(soup, t, Vec3{});
  return six / 6;
}

Reference reference_of(const Steps& steps, const TriangleSoup& input, const MeshCheck& before,
                       Progress* progress) {
  Reference r;
  r.input_box = bounding_box(input);
  if (steps.failure || steps.filled.is_empty()) {
    r.all = r.surface = input;
  } else {
    r.all = to_soup(steps.filled);
    r.surface = r.all;
    const auto patch = steps.filled.property_map<Face, bool>("f:patch");
    if (patch.second) {
      std::size_t t = 0;
      std::vector<Triangle> kept;
      for (Face f : steps.filled.faces()) {
        if (!patch.first[f]) kept.push_back(r.all.triangles[t]);
        ++t;
      }
      r.surface.triangles = std::move(kept);
    }
  }
  r.volume = std::fabs(summed_volume(r.all));
  if (before.components > 1 || before.self_intersecting_pairs.value_or(0) > 0) {
    // A margin around the input for what a wrap adds (its offset); what reaches further is
    // reported as bounding-box growth.
    const double diagonal = norm(r.input_box.size());
    const double spacing = diagonal / kVolumeRaysPerDiagonal;
    Box3 box = r.input_box;
    box.extend(box.min - (0.05 * diagonal) * Vec3{1, 1, 1});
    box.extend(box.max + (0.05 * diagonal) * Vec3{1, 1, 1});
    try {
      const Grid grid = make_grid(box, {.voxel_size = spacing, .padding = 2});
      // Nothing inside by the winding rule (an input the steps left inside out): the summed
      // magnitude stands.
      if (const double w = detail::winding_solid_volume(r.all, grid, progress); w > 0) {
        r.volume_grid = grid;
        r.volume = w;
      }
    } catch (const InputError&) {  // no triangle with three distinct corners
    }
  }
  return r;
}

/// The volume a deviation compares with the reference's, measured the same way.
double output_volume(const TriangleSoup& output, const Reference& ref) {
  if (!ref.volume_grid) return std::fabs(summed_volume(output));
  return detail::winding_solid_volume(output, *ref.volume_grid, nullptr);
}

/// The output's deviation from the reference. A repair's output follows the input except where
/// a union of overlapping shells removed surface from inside the solid: input samples inside
/// the output are left out. A wrap encloses all of its input (by its offset, or a cavity's
/// depth): only input faces buried in the input's own solid (inside another shell) are left
/// out, and a cavity's walls count.
RepairDeviation deviation_of(const TriangleSoup& output, const Reference& ref, bool wrapped) {
  RepairDeviation d;
  const detail::DistanceStats to = detail::surface_distances(output, ref.all);
  const detail::DistanceStats from = detail::surface_distances(
      ref.surface, output, /*skip_inside=*/!wrapped, 1, 600000, wrapped ? &ref.all : nullptr);
  d.to_input = {to.max, to.p95};
  d.from_input = {from.max, from.p95};
  // Magnitudes: an inside-out input turned outward is the same solid.
  const double before = ref.volume, after = output_volume(output, ref);
  if (before != 0) d.volume_change = (after - before) / before;
  // Volume gained, spread over the input's area: what a filled cavity adds, which no surface
  // distance sees once its walls are inside the solid.
  double area = 0;
  for (const Triangle& t : ref.all.triangles) area += 0.5 * detail::double_area(ref.all, t);
  if (area > 0) d.added_thickness = std::max(0.0, (after - before) / area);
  const Box3 out = bounding_box(output);
  for (int a = 0; a < 3 && !out.empty(); ++a)
    d.bbox_growth = std::max(
        {d.bbox_growth, out.max[a] - ref.input_box.max[a], ref.input_box.min[a] - out.min[a]});
  return d;
}

std::string mm(double v) {
  char s[32];
  std::snprintf(s, sizeof s, "%.3g mm", v);
  return s;
}

/// One route to a valid mesh (step 7): what it made and its record for the report.
struct Candidate {
  RepairCandidate record;
  TriangleSoup mesh;
  MeshCheck after;
  /// The mesh's deviation where the route already measured it (a sampled measure of a large
  /// surface takes seconds; assess() does not take it twice).
  std::optional<RepairDeviation> measured;
};

/// The alpha wrap of `wrap_input`, rounded as the file will hold it.
Candidate wrap_candidate(const TriangleSoup& wrap_input, double alpha, double offset,
                         const RepairOptions& options) {
  Candidate c;
  c.record.route = "wrap";
  c.record.alpha = alpha;
  c.record.offset = offset;
  try {
    c.mesh = detail::alpha_wrap(wrap_input, alpha, offset);
  } catch (const CGAL::Failure_exception& e) {
    c.record.failure = "the alpha wrap failed inside CGAL (" + cgal_check_place(e.filename()) + ")";
    return c;
  }
  canonical_order(c.mesh);
  round_coordinates(options.rounding, c.mesh);
  return c;
}

/// The volumetric route's decimation makes no edge longer than this many voxels: flat faces of
/// a CAD part would otherwise become a few huge triangles, each collapse proven against the
/// thousands of marching-cubes triangles under them (quadratic; minutes for a plain box).
constexpr double kMaxEdgeVoxels = 10;

/// The volumetric route: the surface of `solid_input`'s winding-number solid at `voxel`
/// (valid by construction), then decimated within three quarters of what the tolerance leaves
/// once the surface's own deviation is measured (the decimation's bound is proven, the measure
/// is sampled: the quarter is the margin between them).
Candidate volume_candidate(const TriangleSoup& solid_input, double voxel, double tolerance,
                           const Reference& ref, const RepairOptions& options) {
  Candidate c;
  c.record.route = "volume";
  c.record.voxel = voxel;
  try {
    c.mesh = detail::winding_solid_surface(solid_input, voxel, options.rounding, options.progress);
  } catch (const Cancelled&) {
    throw;
  } catch (const Error& e) {  // nothing inside at this voxel, or a grid too large
    c.record.failure = std::string("the volumetric route made no surface: ") + e.what();
    return c;
  }
  c.measured = deviation_of(c.mesh, ref, false);
  const double left = tolerance - c.measured->worst();
  if (left > 0) {
    // The decimation's bound is proven against the surface, whose own deviation is sampled:
    // where the two add up past the tolerance after all, the surface is kept as it was.
    DecimateOptions o;
    o.tolerance = 0.75 * left;
    o.max_edge_length = kMaxEdgeVoxels * voxel;
    o.rounding = options.rounding;
    o.progress = options.progress;
    try {
      DecimateResult d = decimate(c.mesh, o);
      if (d.report.validation.valid() && d.report.stop != DecimateStop::Unchanged) {
        const RepairDeviation decimated = deviation_of(d.mesh, ref, false);
        if (decimated.worst() <= tolerance) {
          c.mesh = std::move(d.mesh);
          c.measured = decimated;
          c.record.decimation = o.tolerance;
        }
      }
    } catch (const Cancelled&) {
      throw;
    } catch (const Error&) {
      // Decimation refuses what it cannot prove valid: the surface stays as marching cubes made it.
    }
  }
  canonical_order(c.mesh);
  return c;
}

/// Checks and measures a candidate (unless it already failed) and records it in the report.
void assess(Candidate& c, const Reference& ref, RepairReport& report) {
  if (c.record.failure.empty()) {
    c.after = check_mesh(c.mesh);
    c.record.triangles = c.mesh.triangles.size();
    c.record.valid = c.after.valid();
    if (c.record.valid) {
      c.record.deviation =
          c.measured ? *c.measured : deviation_of(c.mesh, ref, c.record.route == "wrap");
    } else {
      const std::vector<std::string> problems = c.after.problems();
      c.record.failure =
          "its result is not valid (" + (problems.empty() ? "" : problems.front()) + ")";
    }
  }
  report.candidates.push_back(c.record);
}

/// The log's lines for defects that were still there after the repair steps: "N remained" and
/// `then` (which route replaced the surface), so the log and the reasons never contradict.
void mark_remaining(std::vector<RepairAction>& actions, const MeshCheck& left,
                    const std::string& then) {
  const std::pair<const char*, std::uint64_t> remaining[] = {
      {"non-manifold vertices", left.non_manifold_vertices},
      {"non-manifold edges", left.non_manifold_edges},
      {"inconsistently oriented edges", left.inconsistent_edges},
      {"degenerate triangles", left.degenerate_triangles},
      {"duplicate triangles", left.duplicate_triangles},
      {"holes", left.closed() ? 0 : left.holes.value_or(0)},
      {"self-intersecting triangle pairs", left.self_intersecting_pairs.value_or(0)}};
  for (RepairAction& a : actions)
    for (const auto& [defect, count] : remaining)
      if (a.defect == defect && count > 0) {
        a.fixed = a.found > count ? a.found - count : 0;
        a.action += (a.action.empty() ? "" : "; ") + std::to_string(count) + " remained" +
                    (then.empty() ? "" : ", " + then);
      }
}

/// CGAL's warnings and error messages (printed raw to stderr by its default handlers, with
/// bug-reporting instructions) are collected while a repair runs and become one sentence of
/// the report. The handlers are process-wide: installed by the first repair running,
/// restored by the last.
class CgalMessages {
 public:
  CgalMessages() {
    std::lock_guard lock(mutex());
    if (users()++ == 0) {
      previous_warning() = CGAL::set_warning_handler(&record);
      previous_error() = CGAL::set_error_handler(&record);
    }
  }
  ~CgalMessages() {
    std::lock_guard lock(mutex());
    if (--users() == 0) {
      CGAL::set_warning_handler(previous_warning());
      CGAL::set_error_handler(previous_error());
    }
  }
  /// The sentence for what was collected since construction ("" if nothing), and clears it.
  std::string sentence() {
    std::lock_guard lock(mutex());
    std::vector<std::string>& seen = messages();
    if (seen.empty()) return "";
    std::string s = "CGAL stopped on " + std::to_string(seen.size()) +
                    " internal check(s) during the repair (the first was " + seen.front() +
                    "); the steps concerned were undone and the result was checked on its own, "
                    "as every result is";
    seen.clear();
    return s;
  }

 private:
  static void record(const char* type, const char* expression, const char* file, int line,
                     const char* message) {
    (void)type, (void)expression, (void)line, (void)message;
    std::lock_guard lock(mutex());
    if (messages().size() < 1000) messages().push_back(cgal_check_place(file ? file : ""));
  }
  static std::mutex& mutex() {
    static std::mutex m;
    return m;
  }
  static int& users() {
    static int n = 0;
    return n;
  }
  static std::vector<std::string>& messages() {
    static std::vector<std::string> m;
    return m;
  }
  static CGAL::Failure_function& previous_warning() {
    static CGAL::Failure_function f = nullptr;
    return f;
  }
  static CGAL::Failure_function& previous_error() {
    static CGAL::Failure_function f = nullptr;
    return f;
  }
};

/// Sentences for what the result does not show by itself: cavities the wrap filled, a box
/// that grew beyond the tolerance, a result past the tolerance.
void warn_deviation(RepairReport& report, const Reference& ref) {
  const RepairDeviation& d = report.deviation;
  char pct[32];
  std::snprintf(pct, sizeof pct, "%+.1f %%", 100 * d.volume_change);
  if (report.wrapped && d.volume_change > 0.02) {
    std::uint64_t cavities = 0;
    for (const auto& c : mesh_components(ref.all).info) cavities += c.volume < 0;
    report.warnings.push_back(
        "the alpha wrap changed the volume by " + std::string(pct) +
        (cavities ? ": it filled the input's " + std::to_string(cavities) + " enclosed cavity(s)"
                  : ": it closed openings and concavities narrower than alpha (" +
                        mm(report.alpha) + ")"));
  }
  if (d.bbox_growth > report.tolerance)
    report.warnings.push_back("the output reaches " + mm(d.bbox_growth) +
                              " beyond the input's bounding box (tolerance " +
                              mm(report.tolerance) + ")");
  if (!report.within_tolerance)
    report.warnings.push_back(
        "the result lies up to " + mm(d.worst()) + " from the input (95 % within " +
        mm(std::max(d.to_input.p95, d.from_input.p95)) + "), beyond the tolerance of " +
        mm(report.tolerance) + "; volume " + pct);
}

}  // namespace

double RepairDeviation::worst() const {
  return std::max({to_input.max, from_input.max, bbox_growth, added_thickness});
}

RepairResult repair_mesh(const TriangleSoup& input, const RepairOptions& options) {
  check_options(options);
  detail::require_indices_in_range(input);
  if (input.triangles.empty()) throw InputError("the mesh has no triangles");
  CgalMessages cgal_messages;
  RepairResult result;
  RepairReport& report = result.report;
  report.min_component_fraction = options.min_component_fraction;

  detail::begin_stage(options.progress, "check input");
  report.before = check_mesh(input);
  report.tolerance =
      options.tolerance > 0 ? options.tolerance : 0.01 * norm(bounding_box(input).size());
  detail::report_or_cancel(options.progress, 1.0);

  Steps steps = repair_steps(input, options);
  report.components = steps.components;
  report.small_component_threshold = steps.small_component_threshold;
  report.holes_faired = steps.counts.holes.faired;
  report.holes_flat = steps.counts.holes.flat;
  report.fairing_undone = steps.counts.holes.fairing_undone;
  std::optional<std::string> failure = std::move(steps.failure);
  if (!failure) {
    try {
      const SurfaceMesh mesh = std::move(steps.mesh);
      result.mesh = to_soup(mesh);
      canonical_order(result.mesh);
    } catch (const CGAL::Failure_exception& e) {
      failure = step_failure(e);
    }
  }
  if (failure) result.mesh = input;
  report.actions = write_log(report.before, steps.counts, options);
  steps.failure = failure;
  const Reference reference = reference_of(steps, input, report.before, options.progress);

  // --- 7. check; other routes if not valid or past the tolerance ---------------------------
  detail::begin_stage(options.progress, "check result");
  report.after = check_mesh(result.mesh);
  if (options.rounding != CoordinateRounding::None && !failure) round_result(result, options);
  detail::report_or_cancel(options.progress, 1.0);
  std::vector<Candidate> candidates;
  candidates.reserve(6);  // `repaired` is read below while the list grows
  Candidate& repaired = candidates.emplace_back();
  repaired.record.route = "repair";
  repaired.mesh = std::move(result.mesh);
  repaired.after = report.after;
  repaired.record.triangles = repaired.mesh.triangles.size();
  repaired.record.valid = report.after.valid();
  if (repaired.record.valid) {
    detail::begin_stage(options.progress, "deviation");
    repaired.record.deviation = deviation_of(repaired.mesh, reference, false);
  } else {
    report.unresolved = report.after.problems();
    if (failure) report.unresolved.insert(report.unresolved.begin(), *failure);
    repaired.record.failure = "its result is not valid (" + report.unresolved.front() + ")";
  }
  report.candidates.push_back(repaired.record);
  auto within = [&](const Candidate& c) {
    return c.record.valid && c.record.deviation.worst() <= report.tolerance;
  };
  if (repaired.record.valid && !within(repaired))
    report.unresolved = {"the repair lies up to " + mm(repaired.record.deviation.worst()) +
                         " from the input, beyond the tolerance of " + mm(report.tolerance)};

  // Coarse to fine, cheapest first, until one is within the tolerance: the wrap at CGAL's usual
  // alpha, the winding-number solid remade at half the tolerance (and a quarter, if that
  // surface alone was beyond), then wraps at half and a quarter of that alpha (each about four
  // times the cost of the one before).
  if (!within(repaired)) {
    const TriangleSoup wrap_input = failure ? input : to_soup(steps.filled);
    const double diagonal = norm(bounding_box(wrap_input).size());
    std::vector<double> alphas;
    if (options.alpha > 0)
      alphas = {options.alpha};
    else if (diagonal > 0)
      alphas = {diagonal / 100, diagonal / 200, diagonal / 400};
    auto try_route = [&](Candidate c) {
      assess(c, reference, report);
      candidates.push_back(std::move(c));
      return within(candidates.back());
    };
    auto wrap_at = [&](double alpha) {
      detail::begin_stage(options.progress, "alpha wrap");
      return try_route(wrap_candidate(wrap_input, alpha,
                                      options.offset > 0 ? options.offset : alpha / 30, options));
    };
    bool done = options.wrap && !alphas.empty() && wrap_at(alphas[0]);
    if (!done && options.volume && options.fill_holes && !wrap_input.triangles.empty()) {
      const double voxel = options.voxel > 0 ? options.voxel : report.tolerance / 2;
      detail::begin_stage(options.progress, "volume");
      done = try_route(volume_candidate(wrap_input, voxel, report.tolerance, reference, options));
      // The surface itself beyond the tolerance (nothing left to decimate within): a part
      // about a voxel thin was lost. Once more at half the voxel (8 times the nodes).
      const RepairCandidate& coarse = candidates.back().record;
      if (!done && options.voxel == 0 && coarse.valid && coarse.decimation == 0) {
        detail::begin_stage(options.progress, "volume");
        done = try_route(
            volume_candidate(wrap_input, voxel / 2, report.tolerance, reference, options));
      }
    }
    for (std::size_t i = 1; !done && options.wrap && i < alphas.size(); ++i)
      done = wrap_at(alphas[i]);
  }

  // The valid candidate nearest the input (the first of equals); the repair as it came when
  // none is valid.
  std::size_t pick = 0;
  for (std::size_t i = 0; i < candidates.size(); ++i)
    if (candidates[i].record.valid &&
        (!candidates[pick].record.valid ||
         candidates[i].record.deviation.worst() < candidates[pick].record.deviation.worst()))
      pick = i;
  Candidate& chosen = candidates[pick];
  report.candidates[pick].taken = true;
  result.mesh = std::move(chosen.mesh);
  report.after = chosen.after;
  if (chosen.record.valid) {
    report.route = chosen.record.route;
    report.deviation = chosen.record.deviation;
    report.within_tolerance = within(chosen);
    report.wrapped = report.route == "wrap";
    report.alpha = chosen.record.alpha;
    report.offset = chosen.record.offset;
    report.voxel = chosen.record.voxel;
  } else {
    report.within_tolerance = false;
  }
  if (!candidates[0].record.valid)
    mark_remaining(report.actions, candidates[0].after,
                   report.route == "wrap"     ? "so the surface was wrapped"
                   : report.route == "volume" ? "so the surface was remade from its volume"
                                              : "");
  if (report.valid()) warn_deviation(report, reference);
  if (std::string cgal = cgal_messages.sentence(); !cgal.empty()) report.warnings.push_back(cgal);
  return result;
}

}  // namespace tpmsfill
