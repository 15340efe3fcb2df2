// The start of the material pipeline (seed 001): a closed genus-0 surface filled with tets,
// checked, and mapped onto the unit cube, the domain the material spline is fitted over.
//
//   06_cube_map SURFACE [CELL_MM] [OUT.vtk]
//
// Prints the tet mesh's figures and the map's: flipped boundary faces and inverted tets (a 3D
// harmonic map need not be a bijection, so they are counted). OUT.vtk holds the tets with u as
// their material, to look at in ParaView.
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <tpmsfill/error.hpp>
#include <tpmsfill/io.hpp>
#include <tpmsfill/solid/cube_map.hpp>
#include <tpmsfill/solid/tet_mesh.hpp>
#include <tpmsfill/solid/tetrahedralize.hpp>

using namespace tpmsfill;

namespace {
double seconds_since(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}
}  // namespace

int main(int argc, char** argv) {
  if (argc < 2) {
    std::fprintf(stderr, "usage: 06_cube_map SURFACE [CELL_MM] [OUT.vtk]\n");
    return 2;
  }
  try {
    auto start = std::chrono::steady_clock::now();
    const TriangleSoup surface = read_mesh(argv[1]);
    const double cell = argc > 2 ? std::atof(argv[2]) : 0.0;  // 0: diagonal / 30
    // Chords split: an edge inside whose two ends land on one cube face can only map flat.
    const TetMesh tets = with_chords_split(tetrahedralize(surface, {.cell_size = cell}));
    const TetMeshReport report = check_tet_mesh(tets);
    std::printf("%zu triangles -> %zu points, %zu tets, %.4g mm3, genus %lld (%.2f s)\n",
                surface.triangles.size(), tets.points.size(), tets.tets.size(), report.volume,
                static_cast<long long>(report.genus.value_or(-1)), seconds_since(start));
    if (const auto problem = ball_problem(report)) {
      std::fprintf(stderr, "cannot map onto the cube: %s\n", problem->c_str());
      return 1;
    }
    start = std::chrono::steady_clock::now();
    const CubeMap map = map_to_cube(tets);
    std::printf(
        "cube map: %llu of %llu boundary faces flipped, %llu of %llu tets inverted (%llu "
        "before untangling), %llu interior points (%.2f s)\n",
        static_cast<unsigned long long>(map.flipped_boundary_faces),
        static_cast<unsigned long long>(map.boundary_faces),
        static_cast<unsigned long long>(map.inverted_tets),
        static_cast<unsigned long long>(map.tets),
        static_cast<unsigned long long>(map.harmonic_inverted_tets),
        static_cast<unsigned long long>(map.interior_points), seconds_since(start));
    if (argc > 3) {
      TetMesh shown = tets;
      shown.material.clear();
      for (const auto& p : map.uvw) shown.material.push_back(p[0]);
      write_tet_mesh(argv[3], shown);
    }
    return 0;
  } catch (const Error& e) {
    std::fprintf(stderr, "error: %s\n", e.what());
    return 1;
  }
}
