// The fill pipeline as its stages, one call each: what fill() does, for callers who want to
// change a stage (their own field, another band width, their own checks).
//
//   03_stage_by_stage MESH [OUT.stl]
#include <cstdio>
#include <tpmsfill/error.hpp>
#include <tpmsfill/grid.hpp>
#include <tpmsfill/io.hpp>
#include <tpmsfill/lattice/compose.hpp>
#include <tpmsfill/lattice/tpms.hpp>
#include <tpmsfill/mesh/clean.hpp>
#include <tpmsfill/mesh/validate.hpp>
#include <tpmsfill/sampling/classify.hpp>
#include <tpmsfill/sampling/distance.hpp>
#include <tpmsfill/sampling/marching_cubes.hpp>
#include <tpmsfill/sampling/spatial.hpp>
#include <tpmsfill/sampling/voxel.hpp>

using namespace tpmsfill;

int main(int argc, char** argv) {
  if (argc < 2) {
    std::fprintf(stderr, "usage: 03_stage_by_stage MESH [OUT.stl]\n");
    return 2;
  }
  try {
    const TriangleSoup model = read_mesh(argv[1]);  // read
    const CleanResult clean = clean_soup(model);    // oriented, capped
    const MeshIndex index = build_index(clean.soup, {.hole_caps = &clean.caps});  // AABB tree
    const Grid grid = make_grid(index.bounds(), {.voxel_size = 0.5});             // padded grid
    const Occupancy occupancy = classify_grid(index, grid);                       // winding ≥ ½
    const Band band = band_voxels(occupancy.inside);                              // eq. 6–7
    const auto distance = band_distances(index, occupancy.inside, band);          // eq. 8–9
    const FieldSource lattice = tpms_source({.type = TpmsType::Diamond, .cell = {4, 4, 4}});
    const Field phi = compose_field(occupancy.inside, band, distance, lattice);  // eq. 5, 10
    const TriangleSoup mesh = marching_cubes(phi);                               // iso-surface
    const MeshValidity check = validate_mesh(mesh, {.cell_grid = grid});         // proof
    std::printf(
        "grid %d x %d x %d, %zu band nodes of %zu, %zu triangles, volume %.1f of %.1f "
        "mm3: %s\n",
        grid.dims[0], grid.dims[1], grid.dims[2], band.nodes.size(), grid.node_count(),
        mesh.triangles.size(), check.volume.value_or(0), occupancy.volume,
        check.valid() ? "valid" : check.problems().front().c_str());
    if (argc > 2 && check.valid()) write_mesh(argv[2], mesh);
    return check.valid() ? 0 : 1;
  } catch (const Error& e) {
    std::fprintf(stderr, "error: %s\n", e.what());
    return 1;
  }
}
