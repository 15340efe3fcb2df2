// Seed 001's direct slicing against the input surface's own cross-sections (docs/benchmarks.md
// §22): a fitted model (.tsm) sliced at heights across its box with several tau, each section's
// area compared with the closed surface's section at the same height (each triangle's crossing
// segment, oriented by its normal, summed by the shoelace rule: exact for a closed surface).
//
//   bench_solid_slice MODEL.tsm SURFACE TETS|- TAU...
//
// TETS (the tets the model was fitted to, as `material info --tets` writes them) adds their own
// section's area (each tet's section polygon), which the fit saw.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <tpmsfill/io.hpp>
#include <tpmsfill/solid/solid_model.hpp>
#include <tpmsfill/solid/solid_slice.hpp>
#include <tpmsfill/solid/tet_mesh.hpp>

#include <vector>
#include "../test_util.hpp"

using namespace tpmsfill;

int main(int argc, char** argv) {
  if (argc < 5) {
    std::fprintf(stderr, "usage: bench_solid_slice MODEL.tsm SURFACE TETS|- TAU...\n");
    return 2;
  }
  const SolidModel model = read_solid_model(argv[1]);
  const TriangleSoup surface = read_mesh(argv[2]);
  const bool with_tets = std::string(argv[3]) != "-";
  const TetMesh tets = with_tets ? read_tet_mesh(argv[3]) : TetMesh{};
  const Box3 box = solid_box(model.fit.spline);
  std::printf(
      "| height (share of the box) | tau | level | triangles | area | surface's area | "
      "difference | tets' area | difference | flipped | seconds |\n"
      "|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n");
  for (double share : {0.2, 0.4, 0.6, 0.8}) {
    const double z = box.min.z + share * (box.max.z - box.min.z);
    const double expected = test::section_area(surface, z);
    const double tet_area = with_tets ? test::tet_section_area(tets, z) : std::nan("");
    for (int k = 4; k < argc; ++k) {
      const double tau = std::atof(argv[k]);
      const auto t0 = std::chrono::steady_clock::now();
      const SolidSection s = slice_solid(model.fit.spline, z, {.tau = tau});
      const double seconds =
          std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
      std::printf(
          "| %.4g (%.1f) | %.3g | %d | %zu | %.5g | %.5g | %+.2f %% | %.5g | %+.2f %% | %zu | "
          "%.3f |\n",
          z, share, tau, s.mesh.level, s.mesh.triangles.size(), s.area, expected,
          100 * (s.area / expected - 1), tet_area, 100 * (s.area / tet_area - 1), s.flipped,
          seconds);
    }
  }
  return 0;
}
