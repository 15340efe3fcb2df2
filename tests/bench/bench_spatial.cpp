// Benchmark: spatial index, classification and band distances on a thin-walled tube.
//
//   bench_spatial [SEGMENTS] [RINGS] [SPACING]
//
// The tube is 40 mm across, 20 mm high with a 2 mm wall: outer and inner cylinder walls plus
// top and bottom annuli, outward, closed; 2,048 segments × 573 rings give 4.7×10⁶ triangles.
// It is unwelded as an STL file stores it (three points per triangle). The grid has SPACING
// (0.1 mm) and 2 voxels of padding; the band is every inside node with an outside
// 26-neighbour and every outside node with an inside one. Prints wall times, peak RSS and
// throughput; asserts nothing.
#include <tbb/parallel_for.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <numbers>
#include <tpmsfill/report.hpp>
#include <tpmsfill/sampling/classify.hpp>
#include <tpmsfill/sampling/distance.hpp>
#include <tpmsfill/sampling/spatial.hpp>
#include <tpmsfill/sampling/voxel.hpp>

#include "../test_util.hpp"

using namespace tpmsfill;

namespace {

double current_rss_mb() {
  long pages = 0, resident = 0;
  if (FILE* f = std::fopen("/proc/self/statm", "r")) {
    if (std::fscanf(f, "%ld %ld", &pages, &resident) != 2) resident = 0;
    std::fclose(f);
  }
  return static_cast<double>(resident) * 4096.0 / (1024.0 * 1024.0);
}

}  // namespace

int main(int argc, char** argv) {
  const int segments = argc > 1 ? std::atoi(argv[1]) : 2048;
  const int rings = argc > 2 ? std::atoi(argv[2]) : 573;
  const double spacing = argc > 3 ? std::atof(argv[3]) : 0.1;

  TriangleSoup soup = test::unshare_points(test::make_tube(20, 18, 20, segments, rings));
  std::printf("tube: %zu triangles, %zu points (unwelded); RSS %.0f MB\n", soup.triangles.size(),
              soup.points.size(), current_rss_mb());
  const double rss_soup = current_rss_mb();

  auto t0 = std::chrono::steady_clock::now();
  const MeshIndex index = build_index(soup);
  const double t_build = test::seconds_since(t0);
  std::printf("build_index: %.3f s, %zu triangles; RSS %.0f MB (+%.0f), peak %.0f MB\n", t_build,
              index.triangle_count(), current_rss_mb(), current_rss_mb() - rss_soup,
              peak_memory_mb());

  const Box3 box = index.bounds();
  Grid grid;
  grid.spacing = spacing;
  grid.origin = box.min - Vec3{2 * spacing, 2 * spacing, 2 * spacing};
  for (int a = 0; a < 3; ++a)
    grid.dims[a] = static_cast<int>(std::ceil((box.max[a] - box.min[a]) / spacing)) + 5;

  t0 = std::chrono::steady_clock::now();
  const Occupancy occ = classify_grid(index, grid);
  const double t_classify = test::seconds_since(t0);
  std::printf(
      "classify_grid: %.3f s, %d x %d x %d nodes, %llu rays (%.2f M rays/s), %llu crossings, "
      "%llu odd rays, volume %.3f mm^3 (exact %.3f); peak RSS %.0f MB\n",
      t_classify, grid.dims[0], grid.dims[1], grid.dims[2],
      static_cast<unsigned long long>(occ.rows), occ.rows / t_classify / 1e6,
      static_cast<unsigned long long>(occ.crossings), static_cast<unsigned long long>(occ.odd_rows),
      occ.volume, test::signed_volume(soup), peak_memory_mb());

  t0 = std::chrono::steady_clock::now();
  const Band band = band_voxels(occ.inside);
  std::printf("band (test helper, not a stage): %zu nodes, %.3f s\n", band.nodes.size(),
              test::seconds_since(t0));

  for (bool hints : {true, false}) {
    t0 = std::chrono::steady_clock::now();
    const std::vector<float> d = band_distances(index, occ.inside, band, {.reuse_hints = hints});
    const double t_dist = test::seconds_since(t0);
    float lo = 0, hi = 0;
    for (float v : d) lo = std::min(lo, v), hi = std::max(hi, v);
    std::printf(
        "band_distances (hints %s): %.3f s, %zu queries, %.2f M queries/s, d in [%.4f, %.4f]; "
        "peak RSS %.0f MB\n",
        hints ? "on" : "off", t_dist, d.size(), d.size() / t_dist / 1e6, lo, hi, peak_memory_mb());
  }
  return 0;
}
