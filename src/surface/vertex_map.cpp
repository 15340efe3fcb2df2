// Seed 004's vertex map: the slab's mesh carried onto the surface (vertex_map.hpp).
#include "tpmsfill/conformal.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <unordered_map>

#include "mesh/edge_key.hpp"
#include "surface/surface_normals.hpp"
#include "tpmsfill/error.hpp"

namespace tpmsfill {
namespace {

using detail::edge_key;

// The layout's triangles in square buckets of the unit square: (u, v) → triangle and λ.
class UvLocator {
 public:
  explicit UvLocator(const SurfaceParameterization& p) : p_(p) {
    n_ = std::clamp(static_cast<int>(std::sqrt(double(p.mesh.triangles.size()) / 2)), 1, 1024);
    buckets_.resize(std::size_t(n_) * n_);
    for (std::uint32_t t = 0; t < p.mesh.triangles.size(); ++t) {
      double lo[2] = {1, 1}, hi[2] = {0, 0};
      for (std::uint32_t v : p.mesh.triangles[t])
        for (int a = 0; a < 2; ++a)
          lo[a] = std::min(lo[a], p.uv[v][a]), hi[a] = std::max(hi[a], p.uv[v][a]);
      for (int j = cell(lo[1]); j <= cell(hi[1]); ++j)
        for (int i = cell(lo[0]); i <= cell(hi[0]); ++i)
          buckets_[i + std::size_t(n_) * j].push_back(t);
    }
  }

  // The triangle holding (u, v) (in the unit square) and its barycentric coordinates; where
  // rounding leaves (u, v) just outside every triangle, the one it is least outside.
  std::pair<std::uint32_t, std::array<double, 3>> locate(double u, double v) const {
    std::uint32_t best = 0;
    std::array<double, 3> best_l{1, 0, 0};
    double best_min = -std::numeric_limits<double>::infinity();
    for (std::uint32_t t : buckets_[cell(u) + std::size_t(n_) * cell(v)]) {
      const auto l = barycentric(t, u, v);
      const double m = std::min({l[0], l[1], l[2]});
      if (m > best_min) best_min = m, best = t, best_l = l;
      if (m >= 0) break;
    }
    for (double& x : best_l) x = std::max(x, 0.0);
    const double sum = best_l[0] + best_l[1] + best_l[2];
    for (double& x : best_l) x /= sum;
    return {best, best_l};
  }

 private:
  int cell(double x) const { return std::clamp(static_cast<int>(x * n_), 0, n_ - 1); }
  std::array<double, 3> barycentric(std::uint32_t t, double u, double v) const {
    const Triangle& tri = p_.mesh.triangles[t];
    const auto a = p_.uv[tri[0]], b = p_.uv[tri[1]], c = p_.uv[tri[2]];
    const double det = (b[0] - a[0]) * (c[1] - a[1]) - (c[0] - a[0]) * (b[1] - a[1]);
    if (det == 0) return {-1, -1, -1};
    const double l1 = ((u - a[0]) * (c[1] - a[1]) - (c[0] - a[0]) * (v - a[1])) / det;
    const double l2 = ((b[0] - a[0]) * (v - a[1]) - (u - a[0]) * (b[1] - a[1])) / det;
    return {1 - l1 - l2, l1, l2};
  }

  const SurfaceParameterization& p_;
  int n_ = 1;
  std::vector<std::vector<std::uint32_t>> buckets_;
};

}  // namespace

TriangleSoup map_slab_vertices(const TriangleSoup& slab, const SurfaceParameterization& layout,
                               std::array<double, 2> lengths, const ConformalOptions& layer,
                               const VertexMapOptions& options, VertexMapReport* report) {
  if (layout.periodic_u)
    throw InputError(
        "the vertex map takes disks only: a tube's slab has walls at u = 0 and "
        "u = 1 that land on the same seam (use the field-space map)");
  if (layout.method != LayoutMethod::Square)
    throw InputError(
        "the vertex map lifts the slab's box, which only the square layout fills (lay the "
        "surface out with LayoutMethod::Square, --layout square)");
  if (!(lengths[0] > 0) || !(lengths[1] > 0))
    throw InputError("the slab's lengths must be positive");
  const UvLocator locator(layout);
  const std::vector<Vec3> normals = detail::angle_weighted_normals(layout.mesh);
  const double side = (layer.side == SurfaceSide::Out ? 1 : -1) * layer.normal_scale;
  VertexMapReport r;
  auto map = [&](Vec3 s, bool count) {
    double u = s.x / lengths[0], v = s.y / lengths[1];
    if (count && (u < 0 || u > 1 || v < 0 || v > 1)) ++r.clamped;
    u = std::clamp(u, 0.0, 1.0), v = std::clamp(v, 0.0, 1.0);
    const auto [t, l] = locator.locate(u, v);
    const Triangle& tri = layout.mesh.triangles[t];
    Vec3 p{}, n{};
    for (int c = 0; c < 3; ++c)
      p = p + l[c] * layout.mesh.points[tri[c]], n = n + l[c] * normals[tri[c]];
    return p + (side * s.z) * detail::unit_or_zero(n);
  };
  // Slab positions (kept for splitting) and their images.
  std::vector<Vec3> source = slab.points, image(slab.points.size());
  for (std::size_t i = 0; i < source.size(); ++i) image[i] = map(source[i], true);
  std::vector<Triangle> triangles = slab.triangles;
  const double tolerance =
      options.chord_tolerance > 0 ? options.chord_tolerance : layer.height / 50;
  for (int pass = 0; pass < options.max_passes; ++pass) {
    // Edges to split, each once, with its midpoint's index.
    std::unordered_map<std::uint64_t, std::uint32_t> middle;
    for (const Triangle& t : triangles)
      for (int c = 0; c < 3; ++c) {
        const std::uint32_t a = t[c], b = t[(c + 1) % 3];
        const std::uint64_t k = edge_key(a, b);
        if (middle.count(k)) continue;
        const Vec3 m = 0.5 * (source[a] + source[b]);
        const Vec3 mapped = map(m, false);
        if (norm(mapped - 0.5 * (image[a] + image[b])) <= tolerance) continue;
        middle[k] = static_cast<std::uint32_t>(source.size());
        source.push_back(m), image.push_back(mapped);
      }
    if (middle.empty()) break;
    r.split_edges += middle.size();
    // Each triangle by its split edges: one (two triangles), two (three) or three (four),
    // corners kept in order so the orientation stays.
    std::vector<Triangle> next;
    next.reserve(triangles.size() * 2);
    for (const Triangle& t : triangles) {
      std::array<std::uint32_t, 3> mid;
      int split = 0;
      for (int c = 0; c < 3; ++c) {
        const auto it = middle.find(edge_key(t[c], t[(c + 1) % 3]));
        mid[c] = it == middle.end() ? UINT32_MAX : it->second;
        split += it != middle.end();
      }
      if (split == 0) {
        next.push_back(t);
      } else if (split == 3) {
        next.push_back({t[0], mid[0], mid[2]});
        next.push_back({mid[0], t[1], mid[1]});
        next.push_back({mid[2], mid[1], t[2]});
        next.push_back({mid[0], mid[1], mid[2]});
      } else {
        // Rotate so that edge 0 (t0 → t1) is split; then edge 1 or 2 may be as well.
        int c = 0;
        while (mid[c] == UINT32_MAX) ++c;
        const std::uint32_t a = t[c], b = t[(c + 1) % 3], d = t[(c + 2) % 3];
        const std::uint32_t mab = mid[c], mbd = mid[(c + 1) % 3], mda = mid[(c + 2) % 3];
        if (split == 1) {
          next.push_back({a, mab, d});
          next.push_back({mab, b, d});
        } else if (mbd != UINT32_MAX) {
          next.push_back({a, mab, d});
          next.push_back({mab, b, mbd});
          next.push_back({mab, mbd, d});
        } else {
          next.push_back({a, mab, mda});
          next.push_back({mab, b, d});
          next.push_back({mab, d, mda});
        }
      }
    }
    triangles = std::move(next);
  }
  for (const Triangle& t : triangles)
    for (int c = 0; c < 3; ++c) {
      const std::uint32_t a = t[c], b = t[(c + 1) % 3];
      r.chord_error = std::max(r.chord_error, norm(map(0.5 * (source[a] + source[b]), false) -
                                                   0.5 * (image[a] + image[b])));
    }
  TriangleSoup out{std::move(image), std::move(triangles)};
  if (layer.side == SurfaceSide::In)  // z against the normal mirrors the slab: keep it outward
    for (Triangle& t : out.triangles) std::swap(t[1], t[2]);
  if (report) *report = r;
  return out;
}

}  // namespace tpmsfill
