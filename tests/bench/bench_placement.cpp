// Every mesh where a printer puts it: each file filled at its own position and moved by
// (150, 150, 0) and (0, 0, -1000), to binary STL (floats) as the command line writes it, and
// the written file read back and checked. Prints one Markdown row a mesh.
//
//   bench_placement [--valid-only] MESH...
//
// Settings as docs/benchmarks.md §6: gyroid network, cell = longest side / 15, voxel = cell /
// 10 (the lattice scales with the mesh, so tiny and huge files alike make a job of seconds).
// --valid-only skips meshes `tpmsfill check` does not call valid (the Debian packages' files
// include open and broken ones on purpose); without it every readable mesh is filled, as fill
// takes messy scans.
// GCC 12 reports a false -Wrestrict inside std::string concatenation here (GCC bug 105329).
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC diagnostic ignored "-Wrestrict"
#endif
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <exception>
#include <filesystem>
#include <string>
#include <tpmsfill/check.hpp>
#include <tpmsfill/fill.hpp>
#include <tpmsfill/io.hpp>
#include <vector>

#include "../test_util.hpp"

using namespace tpmsfill;

namespace {

// "valid, 123456 tri, 0.52 s" for a file that reads back valid, else what went wrong.
std::string fill_at(const TriangleSoup& mesh, Vec3 offset, const FillOptions& options,
                    const std::filesystem::path& out, bool& valid) {
  TriangleSoup moved = mesh;
  for (Vec3& p : moved.points) p = p + offset;
  valid = false;
  const auto t0 = std::chrono::steady_clock::now();
  try {
    fill_to_file(moved, options, out);
  } catch (const std::exception& e) {
    std::string why = e.what();
    if (why.size() > 90) why = why.substr(0, 87) + "...";
    return "refused: " + why;
  }
  const double seconds = test::seconds_since(t0);
  const MeshCheck check = check_mesh(read_mesh(out));
  std::filesystem::remove(out);
  char text[160];
  valid = check.valid();
  std::snprintf(text, sizeof text, "%s, %llu tri, %.2f s", valid ? "valid" : "NOT VALID",
                static_cast<unsigned long long>(check.triangles), seconds);
  return text;
}

}  // namespace

int main(int argc, char** argv) {
  bool valid_only = false;
  std::vector<std::filesystem::path> files;
  for (int i = 1; i < argc; ++i) {
    if (std::string(argv[i]) == "--valid-only")
      valid_only = true;
    else
      files.emplace_back(argv[i]);
  }
  if (files.empty()) {
    std::fprintf(stderr, "usage: bench_placement [--valid-only] MESH...\n");
    return 2;
  }
  const std::filesystem::path dir = test::scratch_dir();
  const Vec3 offsets[] = {{0, 0, 0}, {150, 150, 0}, {0, 0, -1000}};
  std::printf("| file | triangles | at its place | + (150, 150, 0) | + (0, 0, -1000) |\n");
  std::printf("|---|---:|---|---|---|\n");
  int rows = 0, all_valid = 0, skipped = 0;
  for (const std::filesystem::path& file : files) {
    TriangleSoup mesh;
    try {
      mesh = read_mesh(file);
      if (valid_only && !check_mesh(mesh, {.self_intersections = true}).valid()) {
        ++skipped;
        continue;
      }
    } catch (const std::exception&) {
      ++skipped;
      continue;
    }
    const Vec3 size = bounding_box(mesh).size();
    const double cell = std::max({size.x, size.y, size.z}) / 15;
    FillOptions options = test::gyroid_options(cell, cell / 10);
    options.rounding = CoordinateRounding::Float;  // binary STL, as the command line writes it
    std::string row =
        "| " + file.filename().string() + " | " + std::to_string(mesh.triangles.size()) + " |";
    int valid_here = 0;
    for (const Vec3& offset : offsets) {
      bool valid = false;
      row += " " + fill_at(mesh, offset, options, dir / "out.stl", valid) + " |";
      valid_here += valid;
    }
    std::printf("%s\n", row.c_str());
    std::fflush(stdout);
    ++rows;
    all_valid += valid_here == 3;
  }
  std::printf("\n%d meshes, %d valid at all three places; %d skipped (%s)\n", rows, all_valid,
              skipped, valid_only ? "unreadable or not valid" : "unreadable");
  std::filesystem::remove_all(dir);
  return 0;
}
