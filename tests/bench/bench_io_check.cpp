// Benchmark: reading each format and checking a large mesh made in code.
//
//   bench_io_check [LEVELS] [DIR]
//
// Builds an icosphere subdivided LEVELS times (20·4^LEVELS triangles; 7 gives 327,680),
// writes it in every format to DIR, then times read_mesh on each file and check_mesh on the
// soup. Prints a markdown table (wall time, file size, throughput, peak RSS so far).

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <string>
#include <tpmsfill/check.hpp>
#include <tpmsfill/io.hpp>
#include <tpmsfill/report.hpp>

#include "../test_util.hpp"

using namespace tpmsfill;
namespace fs = std::filesystem;

int main(int argc, char** argv) {
  const int levels = argc > 1 ? std::atoi(argv[1]) : 7;
  const fs::path dir = argc > 2 ? fs::path(argv[2]) : fs::temp_directory_path() / "tpmsfill-bench";
  fs::create_directories(dir);

  const TriangleSoup sphere = test::make_sphere({0, 0, 0}, 10.0, levels);
  std::printf("icosphere, %d levels: %zu triangles, %zu points\n\n", levels,
              sphere.triangles.size(), sphere.points.size());
  std::printf("| step | file MB | wall s | MB/s | peak RSS MB |\n|---|---:|---:|---:|---:|\n");

  struct Case {
    const char* name;
    MeshFormat format;
    const char* extension;
  };
  const Case cases[] = {{"STL binary", MeshFormat::StlBinary, ".stl"},
                        {"STL ASCII", MeshFormat::StlAscii, ".stl"},
                        {"OBJ", MeshFormat::Obj, ".obj"},
                        {"PLY binary", MeshFormat::Ply, ".ply"},
                        {"OFF", MeshFormat::Off, ".off"}};
  for (const Case& c : cases) {
    const fs::path file =
        dir / (std::string("sphere-") + format_name(c.format).data() + c.extension);
    auto t0 = std::chrono::steady_clock::now();
    write_mesh(file, sphere, {.format = c.format});
    const double write_s = test::seconds_since(t0);
    const double mb = static_cast<double>(fs::file_size(file)) / 1e6;
    t0 = std::chrono::steady_clock::now();
    const TriangleSoup back = read_mesh(file);
    const double read_s = test::seconds_since(t0);
    if (back.triangles.size() != sphere.triangles.size()) {
      std::fprintf(stderr, "%s: read %zu triangles, wrote %zu\n", c.name, back.triangles.size(),
                   sphere.triangles.size());
      return 1;
    }
    std::printf("| write %s | %.1f | %.3f | %.0f | %.0f |\n", c.name, mb, write_s, mb / write_s,
                peak_memory_mb());
    std::printf("| read %s | %.1f | %.3f | %.0f | %.0f |\n", c.name, mb, read_s, mb / read_s,
                peak_memory_mb());
  }

  const TriangleSoup stl = read_mesh(dir / "sphere-stl-binary.stl");
  for (bool self_intersections : {false, true}) {
    auto t0 = std::chrono::steady_clock::now();
    const MeshCheck check = check_mesh(stl, {.self_intersections = self_intersections});
    const double s = test::seconds_since(t0);
    std::printf("| check_mesh (STL soup%s) | | %.3f | | %.0f |\n",
                self_intersections ? ", with self-intersections" : ", no self-intersections", s,
                peak_memory_mb());
    if (!check.valid()) {
      std::fprintf(stderr, "the sphere should be valid\n");
      return 1;
    }
  }
  fs::remove_all(dir);
  return 0;
}
