// Stage "tetrahedralize" (tetrahedralize.hpp): CGAL Mesh_3 on a polyhedral domain. The only file
// that compiles Mesh_3.
#include "tpmsfill/solid/tetrahedralize.hpp"

// Boost.Graph's edge descriptors in CGAL's feature detection (split_graph_into_polylines) are
// copied before GCC can see them set; no path reads them unset.
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#endif

#include <CGAL/AABB_face_graph_triangle_primitive.h>
#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_tree.h>
#include <CGAL/Handle_hash_function.h>
#include <CGAL/Mesh_complex_3_in_triangulation_3.h>
#include <CGAL/Mesh_criteria_3.h>
#include <CGAL/Mesh_triangulation_3.h>
#include <CGAL/Polygon_mesh_processing/measure.h>
#include <CGAL/Polygon_mesh_processing/orientation.h>
#include <CGAL/Polygon_mesh_processing/polygon_soup_to_polygon_mesh.h>
#include <CGAL/Polygon_mesh_processing/self_intersections.h>
#include <CGAL/Polyhedral_mesh_domain_with_features_3.h>
#include <CGAL/make_mesh_3.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <memory>
#include <string>
#include <unordered_map>
#include <vector>

#include "core/stage_progress.hpp"
#include "mesh/cgal_types.hpp"
#include "mesh/soup_topology.hpp"
#include "tpmsfill/error.hpp"

namespace tpmsfill {

namespace {

namespace PMP = CGAL::Polygon_mesh_processing;
using detail::Kernel;
using detail::SurfaceMesh;
using Domain = CGAL::Polyhedral_mesh_domain_with_features_3<Kernel, SurfaceMesh>;
using Triangulation = CGAL::Mesh_triangulation_3<Domain, CGAL::Default, CGAL::Sequential_tag>::type;
using Complex = CGAL::Mesh_complex_3_in_triangulation_3<Triangulation, Domain::Corner_index,
                                                        Domain::Curve_index>;
using Criteria = CGAL::Mesh_criteria_3<Triangulation>;

SurfaceMesh closed_surface_mesh(const TriangleSoup& surface) {
  if (surface.triangles.empty()) throw InputError("the surface has no triangles");
  // Points with equal coordinates are one vertex (STL stores three per triangle).
  const detail::PointMerge merge = detail::merge_equal_points(surface.points);
  std::vector<std::vector<std::size_t>> polygons;
  polygons.reserve(surface.triangles.size());
  for (const Triangle& t : surface.triangles)
    polygons.push_back(
        {merge.vertex_of_point[t[0]], merge.vertex_of_point[t[1]], merge.vertex_of_point[t[2]]});
  std::vector<detail::Point3> points;
  points.reserve(merge.first_point.size());
  for (std::uint32_t p : merge.first_point) points.push_back(detail::to_cgal(surface.points[p]));
  if (!PMP::is_polygon_soup_a_polygon_mesh(polygons))
    throw InputError(
        "the surface is not an oriented 2-manifold (an edge in more than two triangles, two "
        "triangles that disagree on orientation, or a pinched vertex); run tpmsfill repair first");
  SurfaceMesh mesh;
  PMP::polygon_soup_to_polygon_mesh(points, polygons, mesh);
  if (!CGAL::is_closed(mesh))
    throw InputError("the surface has holes (it is not closed); run tpmsfill repair first");
  // Mesh_3 needs to tell inside from outside: a surface through itself can make it run for
  // ever (a scan of a man with 848 crossing triangle pairs did not finish in 100 s).
  if (PMP::does_self_intersect(mesh))
    throw InputError(
        "the surface intersects itself; run tpmsfill repair first (tpmsfill check "
        "lists the pairs)");
  return mesh;
}

// Mesh_3 keeps a tet only where its circumcentre lies inside the surface, so a part thinner
// than the tets (an ear's flap, a bunny's toes) comes out with holes or not at all: at
// diagonal / 30, bear lost 3.7 % of a section through its ears to them. The sizes asked of
// Mesh_3 therefore follow the solid's local thickness: at a point, that of the boundary face
// nearest to it, divided by `cells_across`, between the uniform size and a floor.
constexpr double kThinnestCellRatio = 8;  // the floor: cell_size / 8
class ThicknessSizing {
 public:
  ThicknessSizing(const SurfaceMesh& mesh, double cell, double cells_across, double floor,
                  const std::vector<FinerRegion>& finer)
      : tree_(std::make_shared<Tree>(faces(mesh).first, faces(mesh).second, mesh)),
        size_(std::make_shared<std::vector<double>>(num_faces(mesh), cell)),
        finer_(std::make_shared<std::vector<FinerRegion>>(finer)),
        floor_(floor) {
    if (cells_across == 0) return;
    std::vector<double>& size = *size_;
    std::vector<Kernel::Vector_3> normal(num_faces(mesh));
    for (const auto f : faces(mesh)) normal[f.idx()] = PMP::compute_face_normal(f, mesh);
    for (const auto f : faces(mesh)) {
      const auto h = halfedge(f, mesh);
      const detail::Point3 centre =
          CGAL::centroid(mesh.point(source(h, mesh)), mesh.point(target(h, mesh)),
                         mesh.point(target(next(h, mesh), mesh)));
      const Kernel::Vector_3 inward = -normal[f.idx()];
      // The thickness is where the inward ray leaves the solid through a face turned against
      // this one (within 60°); the faces beside it at a concave crease, met sooner, are not the
      // other side of a thin part.
      const auto not_the_other_side = [&](const SurfaceMesh::Face_index g) {
        return g == f || normal[g.idx()] * inward < 0.5;
      };
      const auto hit = tree_->first_intersection(Kernel::Ray_3(centre, inward), not_the_other_side);
      if (!hit) continue;
      const auto* point = boost::get<detail::Point3>(&hit->first);
      if (!point) continue;
      const double thickness = std::sqrt(CGAL::squared_distance(centre, *point));
      size[f.idx()] = std::clamp(thickness / cells_across, floor, cell);
    }
  }

  // Mesh_3's sizing field (MeshDomainField_3): one value for cells, facets and feature edges.
  template <typename Index>
  double operator()(const detail::Point3& p, int, const Index&) const {
    double size = (*size_)[tree_->closest_point_and_primitive(p).second.idx()];
    // Beyond a region's ball its size grows by half the distance, so that the field has no
    // jump (Mesh_3 refined the lower femur without end across one).
    for (const FinerRegion& r : *finer_) {
      const double beyond = norm(Vec3{p.x(), p.y(), p.z()} - r.centre) - r.radius;
      size = std::min(size, std::max(r.size, floor_) + 0.5 * std::max(beyond, 0.0));
    }
    return size;
  }

 private:
  using Primitive = CGAL::AABB_face_graph_triangle_primitive<SurfaceMesh>;
  using Tree = CGAL::AABB_tree<CGAL::AABB_traits<Kernel, Primitive>>;
  // Shared: Mesh_3's criteria copy the field.
  std::shared_ptr<const Tree> tree_;
  std::shared_ptr<std::vector<double>> size_;
  std::shared_ptr<const std::vector<FinerRegion>> finer_;
  double floor_;
};

double positive_size(double value, double fallback, const char* name) {
  if (value == 0) return fallback;
  if (!(value > 0) || !std::isfinite(value))
    throw InputError(std::string(name) + " must be a positive number of mm");
  return value;
}

}  // namespace

TetMesh tetrahedralize(const TriangleSoup& surface, const TetrahedralizeOptions& options) {
  detail::begin_stage(options.progress, "tetrahedralize");
  SurfaceMesh mesh = closed_surface_mesh(surface);
  if (!PMP::is_outward_oriented(mesh)) PMP::reverse_face_orientations(mesh);
  const Box3 box = bounding_box(surface);
  const double cell = positive_size(options.cell_size, norm(box.size()) / 30, "cell_size");
  const double distance = positive_size(options.facet_distance, cell / 10, "facet_distance");
  if (!(options.cells_across_thin_parts >= 0) || !std::isfinite(options.cells_across_thin_parts))
    throw InputError("cells_across_thin_parts must be 0 (off) or a positive number");
  if (!(options.feature_angle > 0 && options.feature_angle <= 180))
    throw InputError("feature_angle must be in (0, 180] degrees");
  // Mesh_3 makes about 5 V / cell³ tets (bunny00 at cell 0.02: 113,447 for 124,500); refuse
  // before it runs for hours or out of memory.
  const double estimate = 5 * std::abs(PMP::volume(mesh)) / (cell * cell * cell);
  if (estimate > static_cast<double>(options.max_tets))
    throw InputError(
        "a cell of " + std::to_string(cell) + " mm would make about " +
        std::to_string(static_cast<std::uint64_t>(estimate)) + " tets (the limit is " +
        std::to_string(options.max_tets) + "); use a cell of at least " +
        std::to_string(cell * std::cbrt(estimate / static_cast<double>(options.max_tets))) + " mm");
  detail::report_or_cancel(options.progress, 0.0);

  using namespace CGAL::parameters;
  Domain domain(mesh);
  if (options.feature_angle < 180) domain.detect_features(options.feature_angle);
  for (const FinerRegion& r : options.finer)
    if (!(r.radius >= 0 && r.size > 0 && std::isfinite(r.radius) && std::isfinite(r.size)))
      throw InputError("a finer region needs a radius of 0 or more and a positive size, mm");
  const ThicknessSizing sizing(mesh, cell, options.cells_across_thin_parts,
                               cell / kThinnestCellRatio, options.finer);
  Criteria criteria(edge_size = sizing, facet_angle = 25, facet_size = sizing,
                    facet_distance = distance, cell_radius_edge_ratio = 3, cell_size = sizing);
  const Complex complex = [&] {
    // Mesh_3 stops on an assertion where its protection of sharp edges meets a point twice
    // (libcgal-demo's triceratops at 60°: "already inserted on surface"), and first dumps its
    // triangulation into the working directory: that dump is removed, and the job refused with
    // what to change, rather than reported as an internal error.
    const std::filesystem::path dumps[] = {"dump-bug.mesh", "dump-bug.binary.cgal"};
    bool dumped_before = false;
    for (const auto& d : dumps) dumped_before = dumped_before || std::filesystem::exists(d);
    // Mesh_3's refinement can run without end where the surface holds a sliver far finer than
    // the cell (the lower femur's front half, capped by repair, passed 11 GB in 15 min): it
    // stops at a vertex budget of 200 times the estimate's tets, about 1,000 times the vertices
    // it should make (a part thin everywhere, with tets down to cell / 8, makes at most 512
    // times), at least 100,000, and never more than max_tets' vertices (5 tets a vertex or so).
    // (CGAL reads a budget of 0 as none.)
    const auto budget = std::max<std::size_t>(
        1, static_cast<std::size_t>(std::min(static_cast<double>(options.max_tets) / 5,
                                             std::max(100'000.0, 200 * estimate))));
    CGAL::Mesh_error_code stopped = CGAL::CGAL_MESH_3_NO_ERROR;
    try {
      Complex made = CGAL::make_mesh_3<Complex>(
          domain, criteria, no_perturb(), no_exude(), manifold(),
          mesh_3_options(maximal_number_of_vertices = budget, pointer_to_error_code = &stopped));
      if (stopped != CGAL::CGAL_MESH_3_NO_ERROR)
        throw InputError("the tet mesher (CGAL Mesh_3) stopped at " + std::to_string(budget) +
                         " vertices, where a cell of " + std::to_string(cell) +
                         " mm asks for about " +
                         std::to_string(static_cast<std::uint64_t>(estimate / 5)) +
                         ": the surface holds features far finer than the cell (slivers or "
                         "near-touching sheets), which it refines without end; remesh the "
                         "surface near its shortest edges");
      return made;
    } catch (const CGAL::Failure_exception& e) {
      std::error_code ignored;
      if (!dumped_before)
        for (const auto& d : dumps) std::filesystem::remove(d, ignored);
      std::string sentence = e.message().empty() ? e.expression() : e.message();
      sentence = sentence.substr(0, sentence.find('\n'));
      while (!sentence.empty() && (sentence.back() == '.' || sentence.back() == ' '))
        sentence.pop_back();
      throw InputError("the tet mesher (CGAL Mesh_3) failed: " + sentence +
                       (options.feature_angle < 180
                            ? "; it was keeping the edges sharper than " +
                                  std::to_string(std::lround(options.feature_angle)) +
                                  "°: try a feature angle of 180 (none, as for an organic scan)"
                            : "; try another cell size"));
    }
  }();

  TetMesh tets;
  std::unordered_map<Triangulation::Vertex_handle, std::uint32_t, CGAL::Handle_hash_function> index;
  for (auto cell_it = complex.cells_in_complex_begin(); cell_it != complex.cells_in_complex_end();
       ++cell_it) {
    Tet tet{};
    for (int k = 0; k < 4; ++k) {
      const auto vertex = cell_it->vertex(k);
      const auto [at, added] =
          index.emplace(vertex, static_cast<std::uint32_t>(tets.points.size()));
      if (added) {
        const auto p = complex.triangulation().point(vertex);
        tets.points.push_back({p.x(), p.y(), p.z()});
      }
      tet[k] = at->second;
    }
    tets.tets.push_back(tet);
  }
  if (tets.tets.empty())
    throw InputError("Mesh_3 made no tets (the surface may be too thin for cell_size " +
                     std::to_string(cell) + " mm)");
  // CGAL's cells are positive in its own convention; check ours and turn if needed.
  detail::report_or_cancel(options.progress, 1.0);
  const TetMeshReport report = check_tet_mesh(tets);
  return with_positive_tets(std::move(tets), report);
}

}  // namespace tpmsfill
