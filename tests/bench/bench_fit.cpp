// Seed 003's fit at scale (docs/benchmarks.md §14): a sampled gyroid distance field of N³
// cells fitted with M³ coefficients (direct separable solve, then LSPIA for a few iterations),
// and the separable grid evaluation rate of the fitted C. Prints one markdown row per size.
//   bench_fit [N M]...   (default: 256 64)
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <tpmsfill/bspline.hpp>
#include <vector>

using namespace tpmsfill;

namespace {
double seconds(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}
}  // namespace

int main(int argc, char** argv) {
  std::vector<std::pair<int, int>> sizes;
  for (int i = 1; i + 1 < argc; i += 2)
    sizes.emplace_back(std::atoi(argv[i]), std::atoi(argv[i + 1]));
  if (sizes.empty()) sizes = {{128, 32}, {256, 64}};
  std::printf(
      "| grid | coefficients | direct fit s | RMS / range | LSPIA 20 it. s | LSPIA RMS / direct | "
      "evaluate %d³ s | samples/s |\n",
      256);
  std::printf("|---|---|---:|---:|---:|---:|---:|---:|\n");
  for (auto [n, m] : sizes) {
    // Gyroid f̃ with 4 cells across the cube: the sheet distance a scanned scaffold would give.
    const double k = 2 * M_PI * 4;
    std::vector<double> x(std::size_t(n) * n * n);
    std::vector<double> s(n), c(n);
    for (int i = 0; i < n; ++i)
      s[i] = std::sin(k * (i + 0.5) / n), c[i] = std::cos(k * (i + 0.5) / n);
    for (int z = 0; z < n; ++z)
      for (int y = 0; y < n; ++y)
        for (int i = 0; i < n; ++i)
          x[i + std::size_t(n) * (y + std::size_t(n) * z)] =
              (s[i] * c[y] + s[y] * c[z] + s[z] * c[i]) / k;
    const std::array<int, 3> dims{n, n, n}, counts{m, m, m};
    auto t0 = std::chrono::steady_clock::now();
    const FitResult direct = fit_bspline(x, dims, counts);
    const double t_direct = seconds(t0);
    FitOptions o;
    o.method = FitMethod::Lspia;
    o.max_iterations = 20;
    t0 = std::chrono::steady_clock::now();
    const FitResult lspia = fit_bspline(x, dims, counts, o);
    const double t_lspia = seconds(t0);
    t0 = std::chrono::steady_clock::now();
    const std::vector<double> grid = evaluate_bspline_grid(direct.volume, {256, 256, 256});
    const double t_eval = seconds(t0);
    const double range = 2 * 1.5 / k;
    std::printf("| %d³ | %d³ | %.3f | %.3f %% | %.2f | %.3f | %.3f | %.3g |\n", n, m, t_direct,
                100 * direct.report.rms / range, t_lspia, lspia.report.rms / direct.report.rms,
                t_eval, double(grid.size()) / t_eval);
  }
}
