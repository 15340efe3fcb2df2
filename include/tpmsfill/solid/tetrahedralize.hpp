/// @file tetrahedralize.hpp
/// @brief Stage "tetrahedralize" of the material pipeline: a closed surface mesh
/// filled with tets by CGAL's 3D mesh generation (Mesh_3, Delaunay refinement of a polyhedral
/// domain), for parts that come as a surface rather than a tet mesh.
///
/// The tets' boundary approximates the surface (within facet_distance), it does not keep its
/// triangles: Mesh_3 places new vertices on the surface by the sizes asked, and keeps the sharp
/// edges it detects (feature_angle) as polylines of tet edges. The result is manifold (CGAL's
/// manifold option) with positive tets; the run is deterministic.
#pragma once

#include <cstdint>
#include <vector>

#include "tpmsfill/progress.hpp"
#include "tpmsfill/solid/tet_mesh.hpp"
#include "tpmsfill/types.hpp"

namespace tpmsfill {

/// A ball of the solid to mesh finer than the rest.
struct FinerRegion {
  Vec3 centre{};
  double radius = 0;  ///< mm
  double size = 0;    ///< largest tet circumradius and boundary-triangle size inside, mm
};

struct TetrahedralizeOptions {
  /// Largest tet circumradius and boundary-triangle size, mm; 0: the bounding box's diagonal / 30.
  double cell_size = 0;
  /// Parts thinner than cell_size get smaller tets, about this many across their thickness
  /// (measured inward from each boundary face), down to cell_size / 8; 0: one size everywhere.
  /// Mesh_3 drops a tet whose circumcentre lies outside, so without it a flap thinner than
  /// the tets loses area in the sections of a model fitted to them.
  double cells_across_thin_parts = 2;
  /// Largest distance between a boundary triangle's centre and the surface, mm; 0: cell_size / 10.
  double facet_distance = 0;
  /// Edges where the surface's normal turns by more than this many degrees are kept as sharp
  /// edges of the tets' boundary (CGAL's detect_features); 180: none kept (everything smooth).
  double feature_angle = 60;
  /// Balls where tets and boundary triangles are at most their size (not under cell_size / 8):
  /// where a map made from the tets folds (map_to_cube()), smaller tets give it room.
  std::vector<FinerRegion> finer = {};
  /// Refuse when cell_size would make more tets than this (estimated as 5 V / cell_size³
  /// before meshing): memory and time grow with the count.
  std::uint64_t max_tets = 20'000'000;
  Progress* progress = nullptr;  ///< reports the stage's start and end
};

/// Fills a closed surface with tets.
/// @param[in] surface  a closed, oriented 2-manifold without self-intersections (inward normals
///                     are turned), one or more shells
/// @throws InputError  no triangles; the surface is not a closed 2-manifold (the sentence says
///                     why) or intersects itself; sizes that are not positive and finite, an angle
///                     outside (0, 180], a negative cells_across_thin_parts; Mesh_3 made no tets
///                     or passed its vertex budget (200 times the estimated tets, at least
///                     100,000, at most max_tets / 5: slivers far finer than the cell)
/// @throws Cancelled   options.progress asked to stop (checked before and after)
TetMesh tetrahedralize(const TriangleSoup& surface, const TetrahedralizeOptions& options = {});

}  // namespace tpmsfill
