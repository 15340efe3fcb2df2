// A fitted solid's material sampled onto a volume for grading (docs/benchmarks.md §23): for
// several sample counts, the time, the samples inside, and the trilinear volume's error against
// m(p) = M(G⁻¹(p)) itself at random points inside the solid (the same points for every count).
//
//   bench_material_volume MODEL.tsm CELLS...
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <tpmsfill/solid/material_volume.hpp>
#include <tpmsfill/solid/solid_inverse.hpp>
#include <tpmsfill/solid/solid_model.hpp>
#include <vector>

using namespace tpmsfill;

int main(int argc, char** argv) {
  if (argc < 3) {
    std::fprintf(stderr, "usage: bench_material_volume MODEL.tsm CELLS...\n");
    return 2;
  }
  const SolidSpline spline = read_solid_model(argv[1]).fit.spline;
  const Box3 box = solid_box(spline);
  const SolidLocator locator = build_solid_locator(spline);
  // 2000 points inside the solid, drawn uniformly from its box (a fixed sequence).
  std::vector<std::pair<Vec3, double>> probes;
  std::uint64_t seed = 7;
  auto next = [&] {
    seed = seed * 6364136223846793005ULL + 1442695040888963407ULL;
    return static_cast<double>(seed >> 11) / static_cast<double>(1ULL << 53);
  };
  double lo = HUGE_VAL, hi = -HUGE_VAL;
  for (int tries = 0; probes.size() < 2000 && tries < 200000; ++tries) {
    const Vec3 s = box.size();
    const Vec3 p = box.min + Vec3{s.x * next(), s.y * next(), s.z * next()};
    if (const std::optional<double> m = material_at(spline, locator, p)) {
      probes.emplace_back(p, *m);
      lo = std::fmin(lo, *m), hi = std::fmax(hi, *m);
    }
  }
  std::printf("%zu probes inside, material %.4g to %.4g\n\n", probes.size(), lo, hi);
  std::printf(
      "| cells (longest side) | samples | inside | seconds | max error | rms error | "
      "max error / range |\n|---:|---:|---:|---:|---:|---:|---:|\n");
  for (int a = 2; a < argc; ++a) {
    const int cells = std::atoi(argv[a]);
    const auto start = std::chrono::steady_clock::now();
    const MaterialVolume mv = material_volume(spline, {.cells = cells});
    const double seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    double worst = 0, sum = 0;
    for (const auto& [p, m] : probes) {
      const double e = std::fabs(sample_volume(mv.volume, p) - m);
      worst = std::fmax(worst, e), sum += e * e;
    }
    std::printf("| %d | %zu | %zu | %.2f | %.3g | %.3g | %.2f %% |\n", cells, mv.volume.count(),
                mv.inside, seconds, worst, std::sqrt(sum / std::max<std::size_t>(probes.size(), 1)),
                100 * worst / std::fmax(hi - lo, 1e-300));
  }
  return 0;
}
