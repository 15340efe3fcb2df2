// G⁻¹(p) by Newton from the nearest sampled image (solid_inverse.hpp).
#include "tpmsfill/solid/solid_inverse.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>

#include "core/parallel.hpp"

namespace tpmsfill {
namespace {

std::array<int, 3> bucket_of(const SolidLocator& l, Vec3 p) {
  const double x[3] = {p.x - l.origin.x, p.y - l.origin.y, p.z - l.origin.z};
  std::array<int, 3> b{};
  for (int a = 0; a < 3; ++a)
    b[a] = static_cast<int>(std::clamp(std::floor(x[a] / l.bucket), 0.0, l.buckets[a] - 1.0));
  return b;
}

// The `count` starts nearest to p, nearest first (ties by id): rings of buckets outwards until
// the ring is further than the count-th best.
std::vector<std::uint32_t> nearest_starts(const SolidLocator& l, Vec3 p, int count) {
  std::vector<std::pair<double, std::uint32_t>> best;
  const std::array<int, 3> centre = bucket_of(l, p);
  const int widest = std::max({l.buckets[0], l.buckets[1], l.buckets[2]});
  for (int ring = 0; ring <= widest; ++ring) {
    for (int k = centre[2] - ring; k <= centre[2] + ring; ++k)
      for (int j = centre[1] - ring; j <= centre[1] + ring; ++j)
        for (int i = centre[0] - ring; i <= centre[0] + ring; ++i) {
          if (std::max({std::abs(i - centre[0]), std::abs(j - centre[1]),
                        std::abs(k - centre[2])}) != ring)
            continue;  // inside rings already seen
          if (i < 0 || j < 0 || k < 0 || i >= l.buckets[0] || j >= l.buckets[1] ||
              k >= l.buckets[2])
            continue;
          const std::size_t b =
              std::size_t(i) +
              std::size_t(l.buckets[0]) * (std::size_t(j) + std::size_t(l.buckets[1]) * k);
          for (std::uint32_t t = l.bucket_start[b]; t < l.bucket_start[b + 1]; ++t) {
            const std::uint32_t s = l.bucket_items[t];
            best.emplace_back(norm(l.image[s] - p), s);
          }
        }
    std::sort(best.begin(), best.end());
    if (best.size() > std::size_t(count)) best.resize(std::size_t(count));
    // Every start not yet seen lies at least `ring` buckets away from p's bucket.
    if (best.size() == std::size_t(count) && best.back().first <= ring * l.bucket) break;
  }
  std::vector<std::uint32_t> out;
  for (const auto& [d, s] : best) out.push_back(s);
  return out;
}

// Solves J d = r (J's columns G_u, G_v, G_w) by Cramer's rule; false when J is singular.
bool solve(const std::array<Vec3, 3>& j, Vec3 r, std::array<double, 3>& d) {
  const double det = dot(j[0], cross(j[1], j[2]));
  if (!(std::abs(det) > 0) || !std::isfinite(det)) return false;
  d = {dot(r, cross(j[1], j[2])) / det, dot(j[0], cross(r, j[2])) / det,
       dot(j[0], cross(j[1], r)) / det};
  return true;
}

}  // namespace

SolidLocator build_solid_locator(const SolidSpline& spline) {
  SolidLocator l;
  const std::size_t n = spline.basis.elements.size();
  l.uvw.resize(n);
  l.image.resize(n);
  detail::parallel_for(n, 256, [&](std::size_t begin, std::size_t end) {
    for (std::size_t e = begin; e < end; ++e) {
      const OctreeCell& c = spline.basis.elements[e];
      const double h = 1.0 / spline.basis.spans[c.level];
      for (int a = 0; a < 3; ++a) l.uvw[e][a] = (c.index[a] + 0.5) * h;
      l.image[e] = evaluate_solid(spline, l.uvw[e]).position;
    }
  });
  Vec3 lo{1e300, 1e300, 1e300}, hi{-1e300, -1e300, -1e300};
  for (const Vec3& p : l.image) {
    lo = {std::min(lo.x, p.x), std::min(lo.y, p.y), std::min(lo.z, p.z)};
    hi = {std::max(hi.x, p.x), std::max(hi.y, p.y), std::max(hi.z, p.z)};
  }
  const Vec3 extent = hi - lo;
  l.size = std::max(norm(extent), 1e-300);
  // About two starts per bucket.
  const double volume = std::max(extent.x, 1e-9 * l.size) * std::max(extent.y, 1e-9 * l.size) *
                        std::max(extent.z, 1e-9 * l.size);
  l.bucket = std::max(std::cbrt(2 * volume / std::max<std::size_t>(n, 1)), 1e-9 * l.size);
  l.origin = lo;
  for (int a = 0; a < 3; ++a)
    l.buckets[a] = std::clamp(static_cast<int>(std::ceil((&extent.x)[a] / l.bucket)), 1, 512);
  const std::size_t total = std::size_t(l.buckets[0]) * l.buckets[1] * l.buckets[2];
  l.bucket_start.assign(total + 1, 0);
  std::vector<std::size_t> of(n);
  for (std::size_t s = 0; s < n; ++s) {
    const std::array<int, 3> b = bucket_of(l, l.image[s]);
    of[s] = std::size_t(b[0]) +
            std::size_t(l.buckets[0]) * (std::size_t(b[1]) + std::size_t(l.buckets[1]) * b[2]);
    ++l.bucket_start[of[s] + 1];
  }
  for (std::size_t b = 0; b < total; ++b) l.bucket_start[b + 1] += l.bucket_start[b];
  l.bucket_items.resize(n);
  std::vector<std::uint32_t> fill(l.bucket_start.begin(), l.bucket_start.end() - 1);
  for (std::size_t s = 0; s < n; ++s) l.bucket_items[fill[of[s]]++] = static_cast<std::uint32_t>(s);
  return l;
}

Preimage invert_solid(const SolidSpline& spline, const SolidLocator& locator, Vec3 p,
                      const InverseOptions& options,
                      const std::optional<std::array<double, 3>>& start) {
  const double tolerance = options.tolerance * locator.size;
  Preimage best;
  best.distance = std::numeric_limits<double>::infinity();
  int steps = 0;
  std::vector<std::array<double, 3>> starts;
  if (start) starts.push_back(*start);
  // The caller's start usually converges (a neighbour's preimage): look no further then.
  auto nearest = [&] {
    for (std::uint32_t s : nearest_starts(locator, p, options.max_starts))
      starts.push_back(locator.uvw[s]);
  };
  if (!start) nearest();
  for (std::size_t next = 0; next < starts.size(); ++next) {
    std::array<double, 3> x = starts[next];
    for (int it = 0; it <= options.max_iterations; ++it) {
      const SolidPoint g = evaluate_solid(spline, x);
      const double distance = norm(g.position - p);
      if (distance < best.distance) best.uvw = x, best.distance = distance;
      if (distance <= tolerance || it == options.max_iterations) break;
      std::array<double, 3> d{};
      if (!solve(g.jacobian, g.position - p, d)) break;
      ++steps;
      const std::array<double, 3> before = x;
      for (int a = 0; a < 3; ++a) x[a] = std::clamp(x[a] - d[a], 0.0, 1.0);
      if (x == before) break;  // pressed against the cube's faces: p lies beyond them
    }
    if (best.distance <= tolerance) break;
    if (next == 0 && start) nearest();
  }
  best.inside = best.distance <= tolerance;
  best.iterations = steps;
  return best;
}

std::optional<double> material_at(const SolidSpline& spline, const SolidLocator& locator, Vec3 p,
                                  const InverseOptions& options) {
  if (spline.material.empty()) return std::nullopt;
  const Preimage x = invert_solid(spline, locator, p, options);
  if (!x.inside) return std::nullopt;
  return evaluate_solid(spline, x.uvw).material;
}

}  // namespace tpmsfill
