// Repair's volumetric route (see repair/internal/winding_solid.hpp): the pieces fill already has
// (clean, index, classify, band, distance, marching cubes) put to remaking one surface.
#include <algorithm>
#include <string>
#include <vector>

#include "repair/internal/winding_solid.hpp"
#include "tpmsfill/error.hpp"
#include "tpmsfill/grid.hpp"
#include "tpmsfill/mesh/clean.hpp"
#include "tpmsfill/sampling/classify.hpp"
#include "tpmsfill/sampling/distance.hpp"
#include "tpmsfill/sampling/marching_cubes.hpp"
#include "tpmsfill/sampling/spatial.hpp"
#include "tpmsfill/sampling/voxel.hpp"

namespace tpmsfill::detail {

TriangleSoup winding_solid_surface(const TriangleSoup& soup, double voxel,
                                   CoordinateRounding rounding, Progress* progress) {
  const GridOptions grid_options{.voxel_size = voxel, .padding = 2};
  const Box3 box = bounding_box(soup);
  const std::uint64_t nodes = grid_node_count(box, grid_options);
  if (nodes > kMaxWindingSolidNodes)
    throw ResourceError("a " + std::to_string(voxel) + " mm voxel needs " + std::to_string(nodes) +
                        " grid nodes, more than the " + std::to_string(kMaxWindingSolidNodes) +
                        " the volumetric repair samples");
  const Grid grid = make_grid(box, grid_options);
  const CleanResult cleaned = clean_soup(soup);
  const MeshIndex index = build_index(cleaned.soup, {.hole_caps = &cleaned.caps});
  const Occupancy occupancy =
      classify_grid(index, grid, {.rule = InsideRule::Winding, .progress = progress});
  if (std::find(occupancy.inside.values.begin(), occupancy.inside.values.end(), 1) ==
      occupancy.inside.values.end())
    throw InputError("no grid node lies inside the mesh");
  // Only cells with inside and outside corners make triangles, and all their corners are in
  // the band: elsewhere any value of the node's side will do.
  const Band band = band_voxels(occupancy.inside);
  const std::vector<float> distances =
      band_distances(index, occupancy.inside, band, {.progress = progress});
  Field field{grid, std::vector<float>(grid.node_count())};
  const auto far = static_cast<float>(2 * voxel);
  for (std::size_t n = 0; n < field.values.size(); ++n)
    field.values[n] = occupancy.inside.values[n] ? -far : far;
  for (std::size_t b = 0; b < band.nodes.size(); ++b) field.values[band.nodes[b]] = distances[b];
  return marching_cubes(field, {.progress = progress, .rounding = rounding});
}

double winding_solid_volume(const TriangleSoup& soup, const Grid& grid, Progress* progress) {
  const CleanResult cleaned = clean_soup(soup);
  const MeshIndex index = build_index(cleaned.soup, {.hole_caps = &cleaned.caps});
  return classify_grid(index, grid, {.rule = InsideRule::Winding, .progress = progress}).volume;
}

}  // namespace tpmsfill::detail
