// Seed 003's fit at scale (docs/benchmarks.md §14): a sampled gyroid distance field of N³
// cells fitted with M³ coefficients (direct separable solve, then LSPIA for a few iterations),
// and the separable grid evaluation rate of the fitted C. Prints one markdown row per size.
//   bench_fit [N M]...   (default: 256 64)
#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <tpmsfill/sampling/marching_cubes.hpp>
#include <tpmsfill/scan/bspline.hpp>
#include <vector>

#include "mesh/surface_deviation.hpp"

using namespace tpmsfill;

namespace {
double seconds(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}
}  // namespace

// The iso-surface of values on a grid of `dims` nodes from `origin`, `spacing` apart.
TriangleSoup iso_surface(std::vector<double> values, int dims, double origin, double spacing) {
  Field f;
  f.grid.origin = {origin, origin, origin};
  f.grid.spacing = spacing;
  f.grid.dims = {dims, dims, dims};
  f.values.assign(values.begin(), values.end());
  return marching_cubes(f);
}

// C at the nodes of a grid twice as fine as the n³ cell centres, over the same extent.
std::vector<double> fine_values(const BSplineVolume& c, int n) {
  const int m = 2 * n - 1;
  std::vector<double> u(m), out(std::size_t(m) * m * m);
  for (int i = 0; i < m; ++i) u[i] = (0.5 + 0.5 * i) / n;
  for (int k = 0; k < m; ++k)
    for (int j = 0; j < m; ++j)
      bspline_line(c, u, u[j], u[k], out.data() + std::size_t(m) * (j + std::size_t(m) * k));
  return out;
}

// Ground truth (seed 003's "known fields"): a sampled field of n³ cells is fitted with m³
// coefficients; the Hausdorff distance between the iso-surface of the grid and that of the
// fit (evaluated on a grid twice as fine) is reported in voxels of the grid.
void ground_truth(const char* name, const std::vector<double>& x, int n) {
  for (int m : {n / 4, n / 2, 3 * n / 4}) {
    const FitResult fit = fit_bspline(x, {n, n, n}, {m, m, m});
    const TriangleSoup grid = iso_surface(x, n, 0.5 / n, 1.0 / n);
    const TriangleSoup fitted =
        iso_surface(fine_values(fit.volume, n), 2 * n - 1, 0.5 / n, 0.5 / n);
    const detail::DistanceStats a = detail::surface_distances(grid, fitted);
    const detail::DistanceStats b = detail::surface_distances(fitted, grid);
    const auto [lo, hi] = std::minmax_element(x.begin(), x.end());
    std::printf("| %s | %d³ | %d³ | %.2f %% | %.2f | %.2f |\n", name, n, m,
                100 * fit.report.rms / (*hi - *lo), n * std::max(a.max, b.max),
                n * std::max(a.p95, b.p95));
  }
}

void ground_truths() {
  const int n = 96;
  std::vector<double> gyroid, sponge;
  const double k = 2 * M_PI * 3;  // three cells across
  std::vector<std::array<double, 3>> centres;
  unsigned seed = 2024;
  auto next = [&] { return (seed = seed * 1103515245u + 12345u) / 4294967296.0; };
  for (int p = 0; p < 60; ++p) centres.push_back({next(), next(), next()});
  for (int z = 0; z < n; ++z)
    for (int y = 0; y < n; ++y)
      for (int i = 0; i < n; ++i) {
        const double u = (i + 0.5) / n, v = (y + 0.5) / n, w = (z + 0.5) / n;
        gyroid.push_back((std::sin(k * u) * std::cos(k * v) + std::sin(k * v) * std::cos(k * w) +
                          std::sin(k * w) * std::cos(k * u)) /
                         k);
        double best = 1e9;
        for (const auto& c : centres)
          best = std::min(best, std::hypot(u - c[0], v - c[1], w - c[2]));
        sponge.push_back(best - 0.11);
      }
  std::printf(
      "\n| field | grid | coefficients | RMS / range | Hausdorff, voxels | p95, voxels |\n");
  std::printf("|---|---|---|---:|---:|---:|\n");
  ground_truth("gyroid network distance", gyroid, n);
  ground_truth("random sphere pack (60 pores)", sponge, n);
}

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
  if (argc == 1) ground_truths();
}
