// Example 01: make a mesh in code, write it, read it back and check it.
//
//   01_check_mesh box.stl          writes box.stl, reads it, prints the verdict
//
// Exit code 0 when the mesh read back is a valid closed 2-manifold (it should be).
#include <cstdio>
#include <tpmsfill/check.hpp>
#include <tpmsfill/error.hpp>
#include <tpmsfill/io.hpp>

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: %s OUT.stl|obj|ply|off\n", argv[0]);
    return 2;
  }
  // A 10 x 20 x 30 mm box: 8 corners, 12 triangles wound counter-clockwise seen from outside.
  tpmsfill::TriangleSoup box;
  for (int i = 0; i < 8; ++i)
    box.points.push_back({10.0 * (i & 1), 20.0 * ((i >> 1) & 1), 30.0 * ((i >> 2) & 1)});
  box.triangles = {{0, 2, 1}, {1, 2, 3}, {4, 5, 6}, {5, 7, 6}, {0, 1, 4}, {1, 5, 4},
                   {2, 6, 3}, {3, 6, 7}, {0, 4, 2}, {2, 4, 6}, {1, 3, 5}, {3, 7, 5}};
  try {
    tpmsfill::write_mesh(argv[1], box);
    const tpmsfill::TriangleSoup read_back = tpmsfill::read_mesh(argv[1]);
    const tpmsfill::MeshCheck check = tpmsfill::check_mesh(read_back);
    std::printf("%s: %llu triangles, %llu vertices, volume %.3f mm^3: %s\n", argv[1],
                static_cast<unsigned long long>(check.triangles),
                static_cast<unsigned long long>(check.vertices), check.volume.value_or(0.0),
                check.valid() ? "a valid closed 2-manifold" : "NOT valid");
    for (const std::string& problem : check.problems()) std::printf("  - %s\n", problem.c_str());
    return check.valid() ? 0 : 1;
  } catch (const tpmsfill::Error& e) {
    std::fprintf(stderr, "error: %s\n", e.what());
    return 2;
  }
}
