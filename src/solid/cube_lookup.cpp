// The cube map's inverse (cube_lookup.hpp): buckets over the cube, barycentric weights.
#include "solid/cube_lookup.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "mesh/exact_orientation.hpp"

namespace tpmsfill {

namespace {

using Uvw = std::array<double, 3>;

Vec3 as_vec(const Uvw& p) {
  return {p[0], p[1], p[2]};
}

int bucket_of(double x, int buckets) {
  return std::clamp(static_cast<int>(x * buckets), 0, buckets - 1);
}

// Barycentric weights of x in the tet's image; all ≥ 0 inside. False for a flat image.
bool barycentric(const CubeLookup& l, const Tet& t, Vec3 x, std::array<double, 4>& w) {
  const Vec3 a = as_vec(l.uvw[t[0]]), b = as_vec(l.uvw[t[1]]) - a, c = as_vec(l.uvw[t[2]]) - a,
             d = as_vec(l.uvw[t[3]]) - a, p = x - a;
  const double det = dot(b, cross(c, d));
  if (det == 0 || !std::isfinite(det)) return false;
  w[1] = dot(p, cross(c, d)) / det;
  w[2] = dot(b, cross(p, d)) / det;
  w[3] = dot(b, cross(c, p)) / det;
  w[0] = 1 - w[1] - w[2] - w[3];
  return true;
}

CubeSample sample(const CubeLookup& l, std::uint32_t tet, std::array<double, 4> w, bool inside) {
  CubeSample s;
  s.tet = tet;
  s.inside = inside;
  if (!inside) {  // clamped onto the tet
    double sum = 0;
    for (double& x : w) sum += (x = std::max(x, 0.0));
    for (double& x : w) x /= sum;
  }
  s.weights = w;
  for (int k = 0; k < 4; ++k) {
    const std::uint32_t v = l.tets[tet][k];
    s.position = s.position + w[k] * l.points[v];
    if (!l.material.empty()) s.material += w[k] * l.material[v];
  }
  return s;
}

}  // namespace

CubeLookup build_cube_lookup(const TetMesh& mesh, const CubeMap& map) {
  CubeLookup l;
  l.uvw = map.uvw;
  l.points = mesh.points;
  l.material = mesh.material;
  l.tets = mesh.tets;
  l.buckets = std::clamp(static_cast<int>(std::cbrt(mesh.tets.size() / 2.0)), 1, 256);
  const int n = l.buckets;
  std::vector<std::array<int, 6>> range(mesh.tets.size());  // bucket box per tet, or empty
  std::vector<std::uint32_t> count(std::size_t(n) * n * n + 1, 0);
  auto for_each_bucket = [&](const std::array<int, 6>& r, auto&& f) {
    for (int k = r[2]; k <= r[5]; ++k)
      for (int j = r[1]; j <= r[4]; ++j)
        for (int i = r[0]; i <= r[3]; ++i)
          f(std::size_t(i) + std::size_t(n) * (j + std::size_t(n) * k));
  };
  for (std::size_t t = 0; t < mesh.tets.size(); ++t) {
    const Tet& c = mesh.tets[t];
    const int sign = detail::orientation_3(as_vec(l.uvw[c[0]]), as_vec(l.uvw[c[1]]),
                                           as_vec(l.uvw[c[2]]), as_vec(l.uvw[c[3]]));
    if (sign == 0) {
      range[t] = {0, 0, 0, -1, -1, -1};
      continue;
    }
    for (int a = 0; a < 3; ++a) {
      double lo = HUGE_VAL, hi = -HUGE_VAL;
      for (std::uint32_t v : c) lo = std::min(lo, l.uvw[v][a]), hi = std::max(hi, l.uvw[v][a]);
      range[t][a] = bucket_of(lo, n);
      range[t][a + 3] = bucket_of(hi, n);
    }
    for_each_bucket(range[t], [&](std::size_t b) { ++count[b + 1]; });
  }
  for (std::size_t b = 1; b < count.size(); ++b) count[b] += count[b - 1];
  l.bucket_start = count;
  l.bucket_tets.resize(count.back());
  for (std::size_t t = 0; t < mesh.tets.size(); ++t)
    for_each_bucket(range[t], [&](std::size_t b) {
      l.bucket_tets[count[b]++] = static_cast<std::uint32_t>(t);
    });
  return l;
}

CubeSample cube_lookup(const CubeLookup& l, std::array<double, 3> uvw) {
  for (double& x : uvw) x = std::clamp(x, 0.0, 1.0);
  const Vec3 x = as_vec(uvw);
  const int n = l.buckets;
  const int at[3] = {bucket_of(uvw[0], n), bucket_of(uvw[1], n), bucket_of(uvw[2], n)};
  std::array<double, 4> w{}, best_w{};
  double best_outside = -std::numeric_limits<double>::infinity();
  std::uint32_t best = 0;
  // Rings of buckets around x until a tet is found (a gap can be wider than one bucket).
  for (int ring = 0; ring < n; ++ring) {
    for (int k = std::max(at[2] - ring, 0); k <= std::min(at[2] + ring, n - 1); ++k)
      for (int j = std::max(at[1] - ring, 0); j <= std::min(at[1] + ring, n - 1); ++j)
        for (int i = std::max(at[0] - ring, 0); i <= std::min(at[0] + ring, n - 1); ++i) {
          if (std::max({std::abs(i - at[0]), std::abs(j - at[1]), std::abs(k - at[2])}) != ring)
            continue;
          const std::size_t b = std::size_t(i) + std::size_t(n) * (j + std::size_t(n) * k);
          for (std::uint32_t q = l.bucket_start[b]; q < l.bucket_start[b + 1]; ++q) {
            const std::uint32_t t = l.bucket_tets[q];
            if (!barycentric(l, l.tets[t], x, w)) continue;
            const double least = *std::min_element(w.begin(), w.end());
            if (least >= 0) return sample(l, t, w, true);
            if (least > best_outside) best_outside = least, best = t, best_w = w;
          }
        }
    if (best_outside > -HUGE_VAL) break;  // the nearest is within this ring, near enough
  }
  return sample(l, best, best_w, false);
}

}  // namespace tpmsfill
