// Classification time, winding number against parity (docs/benchmarks.md, section 7):
//
//   bench_classify FEMUR_OFF [RUNS]
//
// The femur of Debian's libcgal-demo, scaled so its longest side is 35 mm, on the fill
// benchmark's grid (a = 0.1 mm, 2 voxels of padding). For each case the median of RUNS
// (default 5) timings is printed:
//   - parity: classify_grid(..., Parity) on the index of the mesh as read;
//   - winding: clean_soup + classify_grid(..., Winding) on the cleaned mesh with its caps
//     (the index build is timed separately, as fill's "spatial" stage);
//   - the same femur with three holes cut into it (triangles near three surface points
//     removed, 2 to 4 mm across), where the caps' rims must be evaluated: its nodes are
//     compared with the intact femur's parity classification.
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <functional>
#include <tpmsfill/grid.hpp>
#include <tpmsfill/io.hpp>
#include <tpmsfill/mesh/clean.hpp>
#include <tpmsfill/sampling/classify.hpp>
#include <tpmsfill/sampling/spatial.hpp>
#include <vector>

using namespace tpmsfill;

namespace {

double median_seconds(int runs, const std::function<void()>& work) {
  std::vector<double> t;
  for (int r = 0; r < runs; ++r) {
    const auto t0 = std::chrono::steady_clock::now();
    work();
    t.push_back(std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
  }
  std::sort(t.begin(), t.end());
  return t[t.size() / 2];
}

std::size_t count(const Mask& m) {
  std::size_t n = 0;
  for (std::uint8_t v : m.values) n += v;
  return n;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 2) {
    std::fprintf(stderr, "usage: bench_classify FEMUR_OFF [RUNS]\n");
    return 2;
  }
  const int runs = argc > 2 ? std::max(1, std::atoi(argv[2])) : 5;
  TriangleSoup femur = read_mesh(argv[1]);
  const Box3 box = bounding_box(femur);
  const Vec3 size = box.size();
  const double scale = 35.0 / std::max({size.x, size.y, size.z});
  for (Vec3& p : femur.points) p = scale * (p - box.min);
  const Grid grid = make_grid(bounding_box(femur), {.voxel_size = 0.1, .padding = 2});

  const MeshIndex plain = build_index(femur);
  Occupancy parity;
  const double t_parity = median_seconds(
      runs, [&] { parity = classify_grid(plain, grid, {.rule = InsideRule::Parity}); });

  CleanResult cleaned;
  const double t_clean = median_seconds(runs, [&] { cleaned = clean_soup(femur); });
  const MeshIndex capped = build_index(cleaned.soup, {.hole_caps = &cleaned.caps});
  Occupancy winding;
  const double t_winding = median_seconds(
      runs, [&] { winding = classify_grid(capped, grid, {.rule = InsideRule::Winding}); });

  // Three holes: triangles with a corner within r of three surface points.
  TriangleSoup holes;
  holes.points = femur.points;
  const Vec3 centres[3] = {femur.points[0], femur.points[femur.points.size() / 3],
                           femur.points[2 * femur.points.size() / 3]};
  const double radii[3] = {1.0, 1.5, 2.0};
  for (const Triangle& t : femur.triangles) {
    bool cut = false;
    for (int h = 0; h < 3; ++h)
      for (std::uint32_t v : t) cut = cut || norm(femur.points[v] - centres[h]) < radii[h];
    if (!cut) holes.triangles.push_back(t);
  }
  CleanResult holes_cleaned;
  const double t_holes_clean = median_seconds(runs, [&] { holes_cleaned = clean_soup(holes); });
  const MeshIndex holes_index = build_index(holes_cleaned.soup, {.hole_caps = &holes_cleaned.caps});
  Occupancy holes_winding, holes_parity;
  const double t_holes = median_seconds(runs, [&] {
    holes_winding = classify_grid(holes_index, grid, {.rule = InsideRule::Winding});
  });
  holes_parity = classify_grid(build_index(holes), grid, {.rule = InsideRule::Parity});
  auto agreement = [&](const Mask& m) {
    std::size_t same = 0;
    for (std::size_t i = 0; i < m.values.size(); ++i)
      same += m.values[i] == parity.inside.values[i];
    return 100.0 * static_cast<double>(same) / static_cast<double>(m.values.size());
  };

  std::printf(
      "femur 35 mm, %zu triangles; grid %d x %d x %d = %zu nodes at 0.1 mm; median of %d\n\n",
      femur.triangles.size(), grid.dims[0], grid.dims[1], grid.dims[2], grid.node_count(), runs);
  std::printf(
      "| case | clean s | classify s | classify / parity | inside nodes | rim evaluations | nodes "
      "agreeing with the intact femur |\n");
  std::printf("|---|---:|---:|---:|---:|---:|---:|\n");
  std::printf("| parity, femur as read | - | %.4f | 1.00 | %zu | - | 100 %% |\n", t_parity,
              count(parity.inside));
  std::printf("| winding, femur as read | %.4f | %.4f | %.2f | %zu | %llu | %.4f %% |\n", t_clean,
              t_winding, t_winding / t_parity, count(winding.inside),
              static_cast<unsigned long long>(winding.cap_evaluations), agreement(winding.inside));
  std::printf(
      "| winding, femur with 3 holes (%llu capped) | %.4f | %.4f | %.2f | %zu | %llu | %.4f %% |\n",
      static_cast<unsigned long long>(holes_cleaned.report.holes), t_holes_clean, t_holes,
      t_holes / t_parity, count(holes_winding.inside),
      static_cast<unsigned long long>(holes_winding.cap_evaluations),
      agreement(holes_winding.inside));
  std::printf("| parity, femur with 3 holes | - | - | - | %zu | - | %.4f %% |\n",
              count(holes_parity.inside), agreement(holes_parity.inside));
  return 0;
}
