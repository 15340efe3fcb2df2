// Benchmark: what the field stages could reach on this machine, to put fill's stage times
// beside (docs/benchmarks.md §32).
//
//   bench_field_bounds [NX NY NZ]
//
// 1. Memory bandwidth: writing, reading and copying a 1 GiB buffer (touched beforehand, so no
//    page faults are timed), on one core and on every core TBB may use. Best of 5.
// 2. A one-core, trig-free lower bound for a gyroid field on an NX × NY × NZ grid (default
//    285 × 242 × 705, the femur at 35 mm and 0.05 mm): sin and cos tabulated per axis, so each
//    sample costs three products, two sums and one float store, the least any evaluation of
//    sin x cos y + sin y cos z + sin z cos x on a grid can do. Best of 5, in ns a sample.
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_reduce.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <bit>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <functional>
#include <numbers>
#include <vector>

namespace {

double best_of(int runs, const std::function<void()>& work) {
  double best = 1e300;
  for (int r = 0; r < runs; ++r) {
    const auto t0 = std::chrono::steady_clock::now();
    work();
    best = std::min(best,
                    std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
  }
  return best;
}

}  // namespace

int main(int argc, char** argv) {
  const std::size_t n = std::size_t{1} << 28;  // floats: 1 GiB
  std::vector<float> a(n, 1.0f), b(n, 2.0f);
  volatile double sink = 0;
  const double gib = static_cast<double>(n * sizeof(float)) / (1 << 30);
  const int cores = tbb::this_task_arena::max_concurrency();
  std::printf("| bandwidth, GiB/s | 1 core | %d cores |\n|---|---:|---:|\n", cores);
  auto parallel = [&](const std::function<void(std::size_t, std::size_t)>& f) {
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, n / (8 * cores)),
                      [&](const tbb::blocked_range<std::size_t>& r) { f(r.begin(), r.end()); });
  };
  // Integer sums of the floats' bits: they vectorise (a float sum would be bound by the adds'
  // latency, not by memory).
  auto sum = [&](std::size_t b0, std::size_t e0) {
    std::uint64_t s = 0;
    for (std::size_t i = b0; i < e0; ++i) s += std::bit_cast<std::uint32_t>(a[i]);
    return static_cast<double>(s);
  };
  const double write1 = best_of(5, [&] { std::fill(a.begin(), a.end(), 3.0f); });
  const double writen = best_of(5, [&] {
    parallel([&](std::size_t s, std::size_t e) { std::fill(a.begin() + s, a.begin() + e, 4.0f); });
  });
  const double read1 = best_of(5, [&] { sink = sum(0, n); });
  const double readn = best_of(5, [&] {
    sink = tbb::parallel_reduce(
        tbb::blocked_range<std::size_t>(0, n, n / (8 * cores)), 0.0,
        [&](const tbb::blocked_range<std::size_t>& r, double s) {
          return s + sum(r.begin(), r.end());
        },
        std::plus<>());
  });
  const double copy1 = best_of(5, [&] { std::memcpy(b.data(), a.data(), n * sizeof(float)); });
  const double copyn = best_of(5, [&] {
    parallel([&](std::size_t s, std::size_t e) {
      std::memcpy(b.data() + s, a.data() + s, (e - s) * sizeof(float));
    });
  });
  std::printf("| write | %.1f | %.1f |\n", gib / write1, gib / writen);
  std::printf("| read | %.1f | %.1f |\n", gib / read1, gib / readn);
  std::printf("| copy (read + write) | %.1f | %.1f |\n\n", 2 * gib / copy1, 2 * gib / copyn);

  const int nx = argc > 3 ? std::atoi(argv[1]) : 285;
  const int ny = argc > 3 ? std::atoi(argv[2]) : 242;
  const int nz = argc > 3 ? std::atoi(argv[3]) : 705;
  const std::size_t samples = std::size_t(nx) * ny * nz;
  const double k = 2 * std::numbers::pi / 2.0 * 0.05;  // 2 mm cells, 0.05 mm voxels
  auto table = [&](int m, double (*f)(double)) {
    std::vector<float> t(m);
    for (int i = 0; i < m; ++i) t[i] = static_cast<float>(f(k * i));
    return t;
  };
  const std::vector<float> sx = table(nx, std::sin), cx = table(nx, std::cos);
  const std::vector<float> sy = table(ny, std::sin), cy = table(ny, std::cos);
  const std::vector<float> sz = table(nz, std::sin), cz = table(nz, std::cos);
  std::vector<float> phi(samples, 0.0f);
  const double field = best_of(5, [&] {
    float* out = phi.data();
    for (int z = 0; z < nz; ++z)
      for (int y = 0; y < ny; ++y) {
        const float syz = sy[y] * cz[z], cyv = cy[y], szv = sz[z];
        for (int x = 0; x < nx; ++x) *out++ = sx[x] * cyv + syz + szv * cx[x];
      }
  });
  sink = phi[samples / 3];
  std::printf(
      "gyroid, trig-free, 1 core: %d x %d x %d = %zu samples in %.3f s, %.2f ns a sample "
      "(%.2f GiB/s of float stores)\n",
      nx, ny, nz, samples, field, 1e9 * field / samples, samples * 4.0 / (1 << 30) / field);
  return 0;
}
