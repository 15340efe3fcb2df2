// Writes the two inputs of the fill benchmark (docs/benchmarks.md) as binary STL:
//
//   bench_fill_inputs FEMUR_OFF DIR
//
//   DIR/femur35.stl  Debian libcgal-demo's femur.off, scaled uniformly so its longest side is
//                    35 mm (the paper's femur case at our scale)
//   DIR/tube.stl     a thin-walled tube 40 mm across, 20 mm high, 2 mm wall, 2,048 segments
//                    x 573 rings (4.7 million triangles), stored unwelded as STL does
//
// scripts/bench.sh then times `tpmsfill fill` on each in its own process, so reading, the
// AABB tree and peak memory are measured as a user meets them.
#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <tpmsfill/io.hpp>

#include "../test_util.hpp"

using namespace tpmsfill;

int main(int argc, char** argv) {
  if (argc != 3) {
    std::fprintf(stderr, "usage: bench_fill_inputs FEMUR_OFF DIR\n");
    return 2;
  }
  const std::filesystem::path dir = argv[2];
  std::filesystem::create_directories(dir);

  TriangleSoup femur = read_mesh(argv[1]);
  const Box3 box = bounding_box(femur);
  const Vec3 size = box.size();
  const double scale = 35.0 / std::max({size.x, size.y, size.z});
  for (Vec3& p : femur.points) p = scale * (p - box.min);
  write_mesh(dir / "femur35.stl", femur);
  std::printf("femur35.stl: %zu triangles, scale %.6g\n", femur.triangles.size(), scale);

  const TriangleSoup tube = test::make_tube(20.0, 18.0, 20.0, 2048, 573);
  write_mesh(dir / "tube.stl", tube);
  std::printf("tube.stl: %zu triangles\n", tube.triangles.size());
  return 0;
}
