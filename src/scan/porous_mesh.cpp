// The open surface C = t0 of a porous structure: marching cubes and validation, kept apart
// from porous.cpp so that the ITDF reader's fuzzer builds without CGAL.
#include <cmath>

#include "tpmsfill/error.hpp"
#include "tpmsfill/grid.hpp"
#include "tpmsfill/mesh/validate.hpp"
#include "tpmsfill/sampling/marching_cubes.hpp"
#include "tpmsfill/scan/porous.hpp"

namespace tpmsfill {

OpenSurface porous_surface_mesh(const PorousStructure& s, const Box3& box, double voxel) {
  if (s.type != StructureType::Surface) throw InputError("an open surface needs a surface type");
  if (!(voxel > 0) || !std::isfinite(voxel)) throw InputError("the voxel size must be > 0");
  PorousStructure open = s;
  open.sheet_thickness = 0;
  for (int a = 0; a < 3; ++a)
    if (!(box.max[a] - box.min[a] > 0)) throw InputError("the box to mesh the surface in is empty");
  // No padding: the surface is cut open at the box's faces.
  const Grid grid = make_grid(box, {.voxel_size = voxel, .padding = 0});
  for (int a = 0; a < 3; ++a)
    if (grid.dims[a] > (1 << 15) + 1) throw InputError("the voxel size is too small for the box");
  const FieldSource source = porous_source(open, unit_cube_map(open, box));
  OpenSurface out;
  out.mesh = marching_cubes(source, grid);
  const MeshValidity v = validate_mesh(out.mesh, {.cell_grid = grid});
  if (!v.manifold() || v.inconsistent_edges || v.degenerate_triangles ||
      v.self_intersecting_pairs.value_or(0))
    throw ValidationError("the open surface is not a valid 2-manifold with boundary");
  out.border_edges = v.border_edges;
  out.components = v.components;
  out.area = v.area;
  return out;
}

}  // namespace tpmsfill
