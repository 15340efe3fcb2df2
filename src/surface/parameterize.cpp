// Stage "parameterize": mean-value coordinates on the unit square (parameterize.hpp).
//
// The topology (welding, manifold and orientation checks, loops, the seam cut, corners) is
// plain index work on directed edges; the mean-value system is the one Dirichlet solve
// (mesh/dirichlet.hpp) that the cube map's patches use too.

#include "tpmsfill/surface/parameterize.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <numbers>
#include <queue>
#include <string>
#include <unordered_map>

#include "tpmsfill/error.hpp"

#include "core/names.hpp"
#include "mesh/dirichlet.hpp"
#include "surface/internal/arap.hpp"

namespace tpmsfill {
namespace {

using Edges = std::unordered_map<std::uint64_t, std::uint32_t>;  // directed edge -> triangle

std::uint64_t key(std::uint32_t a, std::uint32_t b) {
  return (std::uint64_t(a) << 32) | b;
}

// Points with bit-identical coordinates merged, triangles with a repeated corner dropped;
// `merged[i]` is the new index of input point i.
struct Welded {
  TriangleSoup mesh;
  std::vector<std::uint32_t> source_triangle, merged;
};

Welded weld(const TriangleSoup& in) {
  // Points keep their order (a clean mesh keeps its indices), the first of each position wins.
  Welded w;
  std::vector<bool> used(in.points.size(), false);
  for (const Triangle& t : in.triangles)
    for (std::uint32_t v : t) used[v] = true;
  std::map<std::array<double, 3>, std::uint32_t> seen;
  w.merged.assign(in.points.size(), UINT32_MAX);
  for (std::size_t i = 0; i < in.points.size(); ++i) {
    if (!used[i]) continue;
    const Vec3 q = in.points[i];
    const auto [it, added] =
        seen.emplace(std::array<double, 3>{q.x, q.y, q.z}, std::uint32_t(w.mesh.points.size()));
    if (added) w.mesh.points.push_back(q);
    w.merged[i] = it->second;
  }
  for (std::size_t t = 0; t < in.triangles.size(); ++t) {
    const Triangle& s = in.triangles[t];
    const Triangle r{w.merged[s[0]], w.merged[s[1]], w.merged[s[2]]};
    if (r[0] == r[1] || r[1] == r[2] || r[2] == r[0]) continue;
    w.mesh.triangles.push_back(r);
    w.source_triangle.push_back(static_cast<std::uint32_t>(t));
  }
  return w;
}

// Directed edges, refusing what is not an oriented 2-manifold with boundary.
Edges directed_edges(const TriangleSoup& m) {
  Edges e;
  std::unordered_map<std::uint64_t, int> uses;
  for (std::uint32_t t = 0; t < m.triangles.size(); ++t)
    for (int c = 0; c < 3; ++c) {
      const std::uint32_t a = m.triangles[t][c], b = m.triangles[t][(c + 1) % 3];
      if (++uses[key(std::min(a, b), std::max(a, b))] > 2)
        throw InputError(
            "the surface is not a manifold: an edge is shared by more than two "
            "triangles (near point " +
            std::to_string(a) + ")");
      if (!e.emplace(key(a, b), t).second)
        throw InputError(
            "the surface's triangles are not consistently oriented (two triangles "
            "run the edge from point " +
            std::to_string(a) + " to " + std::to_string(b) +
            " the same way); reorient it, e.g. tpmsfill "
            "repair");
    }
  return e;
}

// The triangle after `t` turning counter-clockwise about its corner `v` (the one across the
// edge from v to t's last corner), or UINT32_MAX at the boundary.
std::uint32_t next_around(const TriangleSoup& m, const Edges& e, std::uint32_t t, std::uint32_t v) {
  const Triangle& tri = m.triangles[t];
  const int c = tri[0] == v ? 0 : tri[1] == v ? 1 : 2;
  const auto it = e.find(key(v, tri[(c + 2) % 3]));
  return it == e.end() ? UINT32_MAX : it->second;
}

// Every vertex's triangles form one fan; one piece; returns the boundary loops, each as its
// points in order with the surface on the left.
std::vector<std::vector<std::uint32_t>> check_and_loops(const TriangleSoup& m, const Edges& e) {
  const std::size_t n = m.points.size();
  std::vector<std::vector<std::uint32_t>> around(n);
  for (std::uint32_t t = 0; t < m.triangles.size(); ++t)
    for (std::uint32_t v : m.triangles[t]) around[v].push_back(t);
  std::vector<std::uint32_t> boundary_next(n, UINT32_MAX);
  for (const auto& [k, t] : e) {
    const std::uint32_t a = std::uint32_t(k >> 32), b = std::uint32_t(k);
    if (!e.count(key(b, a))) boundary_next[a] = b;  // at most one: fans checked below
  }
  for (std::uint32_t v = 0; v < n; ++v) {
    if (around[v].empty()) continue;
    // Walk the fan from its first triangle (a boundary vertex: from the boundary edge out of v).
    std::uint32_t start = around[v].front();
    if (boundary_next[v] != UINT32_MAX) start = e.at(key(v, boundary_next[v]));
    std::size_t count = 0;
    for (std::uint32_t t = start; t != UINT32_MAX && count <= around[v].size();) {
      ++count;
      t = next_around(m, e, t, v);
      if (t == start) break;
    }
    if (count != around[v].size())
      throw InputError("the surface is not a manifold: two fans of triangles meet at point " +
                       std::to_string(v));
  }
  // One piece: triangles joined through shared edges.
  std::vector<std::uint32_t> parent(m.triangles.size());
  for (std::uint32_t t = 0; t < parent.size(); ++t) parent[t] = t;
  auto find = [&](std::uint32_t t) {
    while (parent[t] != t) t = parent[t] = parent[parent[t]];
    return t;
  };
  std::size_t pieces = parent.size();
  for (const auto& [k, t] : e)
    if (const auto it = e.find(key(std::uint32_t(k), std::uint32_t(k >> 32))); it != e.end())
      if (const std::uint32_t a = find(t), b = find(it->second); a != b) parent[a] = b, --pieces;
  if (pieces != 1)
    throw InputError("the surface has " + std::to_string(pieces) +
                     " separate pieces; lay out one at a time");
  std::vector<std::vector<std::uint32_t>> loops;
  std::vector<bool> done(n, false);
  for (std::uint32_t v = 0; v < n; ++v) {
    if (boundary_next[v] == UINT32_MAX || done[v]) continue;
    loops.emplace_back();
    for (std::uint32_t w = v; !done[w]; w = boundary_next[w])
      done[w] = true, loops.back().push_back(w);
  }
  return loops;
}

// The shortest edge path from loop `a` to loop `b` through interior points (Dijkstra by 3D
// length; ties broken by index, so the seam does not depend on hash order).
std::vector<std::uint32_t> seam_path(const TriangleSoup& m, const Edges& e,
                                     const std::vector<std::uint32_t>& a,
                                     const std::vector<std::uint32_t>& b) {
  const std::size_t n = m.points.size();
  std::vector<int> loop(n, 0);
  for (std::uint32_t v : a) loop[v] = 1;
  for (std::uint32_t v : b) loop[v] = 2;
  std::vector<std::vector<std::uint32_t>> next(n);
  for (const auto& [k, t] : e) {
    const std::uint32_t p = std::uint32_t(k >> 32), q = std::uint32_t(k);
    if (!e.count(key(q, p))) continue;  // a boundary edge cannot be cut
    next[p].push_back(q);
  }
  for (auto& list : next) std::sort(list.begin(), list.end());
  std::vector<double> dist(n, std::numeric_limits<double>::infinity());
  std::vector<std::uint32_t> from(n, UINT32_MAX);
  using Item = std::pair<double, std::uint32_t>;
  std::priority_queue<Item, std::vector<Item>, std::greater<>> queue;
  for (std::uint32_t v : a) dist[v] = 0, queue.push({0, v});
  while (!queue.empty()) {
    const auto [d, v] = queue.top();
    queue.pop();
    if (d > dist[v]) continue;
    if (loop[v] == 2) {
      std::vector<std::uint32_t> path{v};
      while (from[path.back()] != UINT32_MAX) path.push_back(from[path.back()]);
      std::reverse(path.begin(), path.end());
      return path;
    }
    if (loop[v] == 1 && d > 0) continue;
    for (std::uint32_t w : next[v]) {
      if (loop[w] == 1) continue;
      const double nd = d + norm(m.points[w] - m.points[v]);
      if (nd < dist[w]) dist[w] = nd, from[w] = v, queue.push({nd, w});
    }
  }
  throw InputError(
      "no path of interior edges joins the surface's two boundary loops, so it "
      "cannot be cut open along a seam");
}

// Cuts the surface open along `path`: the triangles on the path's left get new copies of its
// points. Returns the copies (copy[i] for path[i]).
std::vector<std::uint32_t> cut_along(TriangleSoup& m, const Edges& e,
                                     const std::vector<std::uint32_t>& path) {
  // Which triangles lie left of the path at each of its points, found on the uncut surface
  // (the edge map speaks of the original corners), then their corners replaced.
  const std::size_t last = path.size() - 1;
  std::vector<std::vector<std::uint32_t>> left(path.size());
  for (std::size_t i = 0; i <= last; ++i) {
    const std::uint32_t v = path[i];
    auto corner = [&](std::uint32_t t) {
      const Triangle& tri = m.triangles[t];
      return tri[0] == v ? 0 : tri[1] == v ? 1 : 2;
    };
    if (i < last) {
      // Counter-clockwise from the edge to the next point, up to the edge from the previous
      // one (or the boundary at the first point).
      for (std::uint32_t t = e.at(key(v, path[i + 1])); t != UINT32_MAX;) {
        left[i].push_back(t);
        if (i > 0 && m.triangles[t][(corner(t) + 2) % 3] == path[i - 1]) break;
        t = next_around(m, e, t, v);
      }
    } else {
      // The last point: clockwise from the triangle left of the edge into it, to the boundary.
      for (std::uint32_t t = e.at(key(path[i - 1], v)); t != UINT32_MAX;) {
        left[i].push_back(t);
        const auto it = e.find(key(m.triangles[t][(corner(t) + 1) % 3], v));
        t = it == e.end() ? UINT32_MAX : it->second;
      }
    }
  }
  std::vector<std::uint32_t> copy(path.size());
  for (std::size_t i = 0; i <= last; ++i) {
    copy[i] = static_cast<std::uint32_t>(m.points.size());
    m.points.push_back(m.points[path[i]]);
    for (std::uint32_t t : left[i])
      for (std::uint32_t& c : m.triangles[t])
        if (c == path[i]) c = copy[i];
  }
  return copy;
}

// The boundary of a disk as points in order, surface on the left.
std::vector<std::uint32_t> disk_boundary(const TriangleSoup& m) {
  const Edges e = directed_edges(m);
  auto loops = check_and_loops(m, e);
  if (loops.size() != 1) throw InputError("the cut surface is not a disk (internal)");
  return loops.front();
}

// How much the boundary turns at each point: π less the triangles' angles there (one pass).
std::vector<double> turning(const TriangleSoup& m) {
  std::vector<double> angle(m.points.size(), std::numbers::pi);
  for (const Triangle& t : m.triangles)
    for (int c = 0; c < 3; ++c) {
      const Vec3 a = m.points[t[(c + 1) % 3]] - m.points[t[c]],
                 b = m.points[t[(c + 2) % 3]] - m.points[t[c]];
      angle[t[c]] -= std::atan2(norm(cross(a, b)), dot(a, b));
    }
  return angle;
}

// Corners in boundary order (surface on the left) at (0,0), (1,0), (1,1), (0,1).
std::array<std::uint32_t, 4> default_corners(const TriangleSoup& m,
                                             const std::vector<std::uint32_t>& loop) {
  std::size_t start = 0;
  double best = -std::numeric_limits<double>::infinity();
  const std::vector<double> turn = turning(m);
  for (std::size_t i = 0; i < loop.size(); ++i)
    if (const double a = turn[loop[i]]; a > best + 1e-12) best = a, start = i;
  std::vector<double> at(loop.size() + 1, 0);
  for (std::size_t i = 0; i < loop.size(); ++i)
    at[i + 1] = at[i] + norm(m.points[loop[(start + i + 1) % loop.size()]] -
                             m.points[loop[(start + i) % loop.size()]]);
  std::array<std::uint32_t, 4> c{loop[start], 0, 0, 0};
  std::size_t previous = 0;
  for (int q = 1; q < 4; ++q) {
    const double target = at.back() * q / 4;
    std::size_t i = previous + 1;
    while (i + 1 < loop.size() - (3 - q) &&
           std::fabs(at[i + 1] - target) < std::fabs(at[i] - target))
      ++i;
    c[q] = loop[(start + i) % loop.size()];
    previous = i;
  }
  return c;
}

// The user's corners put in boundary order: as given when they run with the surface on the
// left, else the reverse from the first (so u and v keep the surface's orientation).
std::array<std::uint32_t, 4> given_corners(const std::array<std::uint32_t, 4>& given,
                                           const std::vector<std::uint32_t>& merged,
                                           const std::vector<std::uint32_t>& loop) {
  std::array<std::size_t, 4> at{};
  std::array<std::uint32_t, 4> c{};
  for (int q = 0; q < 4; ++q) {
    if (given[q] >= merged.size() || merged[given[q]] == UINT32_MAX)
      throw InputError("corner " + std::to_string(given[q]) + " is not a point of the surface");
    c[q] = merged[given[q]];
    const auto it = std::find(loop.begin(), loop.end(), c[q]);
    if (it == loop.end())
      throw InputError("corner " + std::to_string(given[q]) + " is not on the boundary");
    at[q] = static_cast<std::size_t>(it - loop.begin());
  }
  for (int q = 1; q < 4; ++q) at[q] = (at[q] + loop.size() - at[0]) % loop.size();
  if (at[1] < at[2] && at[2] < at[3] && at[1] > 0) return c;
  if (at[3] < at[2] && at[2] < at[1] && at[3] > 0) return {c[0], c[3], c[2], c[1]};
  throw InputError("the four corners must be distinct and met in order along the boundary");
}

Spread spread(std::vector<std::pair<double, double>> value_weight) {
  Spread s;
  if (value_weight.empty()) return s;
  std::sort(value_weight.begin(), value_weight.end());
  double total = 0;
  for (const auto& [v, w] : value_weight) total += w;
  auto at = [&](double f) {
    double sum = 0;
    for (const auto& [v, w] : value_weight)
      if ((sum += w) >= f * total) return v;
    return value_weight.back().first;
  };
  s.min = value_weight.front().first, s.max = value_weight.back().first;
  s.p5 = at(0.05), s.p50 = at(0.5), s.p95 = at(0.95);
  return s;
}

// Flips, area scale and angle distortion per triangle against the length_u × length_v square.
void measure(SurfaceParameterization& p) {
  std::vector<std::pair<double, double>> area, angle;
  for (const Triangle& t : p.mesh.triangles) {
    const Vec3 e1 = p.mesh.points[t[1]] - p.mesh.points[t[0]],
               e2 = p.mesh.points[t[2]] - p.mesh.points[t[0]];
    const double a3 = 0.5 * norm(cross(e1, e2));
    p.area += a3;
    const double du1 = (p.uv[t[1]][0] - p.uv[t[0]][0]) * p.length_u,
                 dv1 = (p.uv[t[1]][1] - p.uv[t[0]][1]) * p.length_v,
                 du2 = (p.uv[t[2]][0] - p.uv[t[0]][0]) * p.length_u,
                 dv2 = (p.uv[t[2]][1] - p.uv[t[0]][1]) * p.length_v;
    const double det = du1 * dv2 - du2 * dv1;  // twice the signed image area
    if (!(det > 0) || a3 == 0) {
      ++p.flips;
      continue;
    }
    // Jacobian J = X U⁻¹ in a frame of the triangle's plane; σ₁/σ₂ from JᵀJ's eigenvalues.
    const Vec3 x = (1 / norm(e1)) * e1,
               y = (1 / norm(cross(cross(e1, e2), e1))) * cross(cross(e1, e2), e1);
    const double x11 = dot(e1, x), x12 = dot(e2, x), x21 = dot(e1, y), x22 = dot(e2, y);
    const double j11 = (x11 * dv2 - x12 * dv1) / det, j12 = (-x11 * du2 + x12 * du1) / det,
                 j21 = (x21 * dv2 - x22 * dv1) / det, j22 = (-x21 * du2 + x22 * du1) / det;
    const double a = j11 * j11 + j21 * j21, b = j11 * j12 + j21 * j22, c = j12 * j12 + j22 * j22;
    const double root = std::sqrt(std::max(0.0, (a - c) * (a - c) / 4 + b * b));
    const double l1 = (a + c) / 2 + root, l2 = std::max((a + c) / 2 - root, 1e-300);
    area.push_back({a3 / (0.5 * det), a3});
    angle.push_back({std::sqrt(l1 / l2), a3});
  }
  p.area_scale = spread(std::move(area));
  p.angle_distortion = spread(std::move(angle));
}

double path_length(const TriangleSoup& m, const std::vector<std::uint32_t>& loop,
                   std::uint32_t from, std::uint32_t to) {
  std::size_t i = std::find(loop.begin(), loop.end(), from) - loop.begin();
  double length = 0;
  for (; loop[i] != to; i = (i + 1) % loop.size())
    length += norm(m.points[loop[(i + 1) % loop.size()]] - m.points[loop[i]]);
  return length;
}

// Mean-value coordinates with the boundary on the unit square: the corners (in boundary
// order, surface on the left) at (0, 0), (1, 0), (1, 1) and (0, 1), the points between two
// corners by arc length along that side.
std::vector<std::array<double, 2>> solve_mvc(const TriangleSoup& m,
                                             const std::vector<std::uint32_t>& loop,
                                             const std::array<std::uint32_t, 4>& c) {
  constexpr std::array<std::array<double, 2>, 5> square{{{0, 0}, {1, 0}, {1, 1}, {0, 1}, {0, 0}}};
  std::vector<double> values(2 * m.points.size(), 0.0);
  std::vector<char> fixed(m.points.size(), 0);
  std::size_t i = std::find(loop.begin(), loop.end(), c[0]) - loop.begin();
  for (int side = 0; side < 4; ++side) {
    std::vector<std::pair<std::uint32_t, double>> run{{loop[i], 0.0}};  // point, length so far
    for (; loop[i] != c[(side + 1) % 4]; i = (i + 1) % loop.size())
      run.push_back(
          {loop[(i + 1) % loop.size()],
           run.back().second + norm(m.points[loop[(i + 1) % loop.size()]] - m.points[loop[i]])});
    const double total = run.back().second;
    if (!(total > 0))
      throw InputError("the surface cannot be laid out: two of its corners are at one point");
    run.pop_back();  // the next side's first corner
    for (const auto& [v, length] : run) {
      const double t = length / total;
      fixed[v] = 1;
      for (int k = 0; k < 2; ++k)
        values[2 * v + k] = square[side][k] + t * (square[side + 1][k] - square[side][k]);
    }
  }
  detail::solve_dirichlet(detail::mean_value_operator(m.points, m.triangles),
                          detail::Symmetry::General, fixed, 2, values,
                          "the surface cannot be laid out: its mean-value system is singular "
                          "(degenerate triangles?)");
  std::vector<std::array<double, 2>> uv(m.points.size());
  for (std::size_t v = 0; v < uv.size(); ++v) uv[v] = {values[2 * v], values[2 * v + 1]};
  return uv;
}

constexpr detail::Named<LayoutMethod> kLayoutMethods[] = {
    {LayoutMethod::Square, "square"}, {LayoutMethod::Free, "free"}, {LayoutMethod::Auto, "auto"}};

// The free layout from the square's (in mm), its tube period turned onto x, normalised to its
// bounding box and scaled so the area scale averages 1 (as the square's).
SurfaceParameterization free_layout(
    const SurfaceParameterization& square,
    const std::vector<std::pair<std::uint32_t, std::uint32_t>>& seam) {
  std::vector<std::array<double, 2>> start(square.uv.size());
  for (std::size_t i = 0; i < start.size(); ++i)
    start[i] = {square.uv[i][0] * square.length_u, square.uv[i][1] * square.length_v};
  const detail::ArapLayout a = detail::arap_layout(square.mesh, start, seam, 200);
  SurfaceParameterization q = square;
  q.method = LayoutMethod::Free;
  q.free_iterations = a.iterations;
  // A tube's period along +x, so u + 1 is the seam's other side.
  const double turn = seam.empty() ? 0 : -std::atan2(a.period[1], a.period[0]);
  const double c = std::cos(turn), s = std::sin(turn);
  std::array<double, 2> lo{std::numeric_limits<double>::infinity(),
                           std::numeric_limits<double>::infinity()};
  std::array<double, 2> hi{-lo[0], -lo[1]};
  std::vector<std::array<double, 2>> xy(a.xy.size());
  for (std::size_t i = 0; i < xy.size(); ++i) {
    xy[i] = {c * a.xy[i][0] - s * a.xy[i][1], s * a.xy[i][0] + c * a.xy[i][1]};
    for (int k = 0; k < 2; ++k)
      lo[k] = std::min(lo[k], xy[i][k]), hi[k] = std::max(hi[k], xy[i][k]);
  }
  double laid = 0;  // the layout's own area
  for (const Triangle& t : q.mesh.triangles)
    laid += 0.5 * ((xy[t[1]][0] - xy[t[0]][0]) * (xy[t[2]][1] - xy[t[0]][1]) -
                   (xy[t[2]][0] - xy[t[0]][0]) * (xy[t[1]][1] - xy[t[0]][1]));
  const double period = std::hypot(a.period[0], a.period[1]);
  const double lu = seam.empty() ? hi[0] - lo[0] : period, lv = hi[1] - lo[1];
  if (!(lu > 0) || !(lv > 0) || !(laid > 0))
    throw InputError("the surface cannot be laid out freely: its layout has no area");
  for (std::size_t i = 0; i < xy.size(); ++i)
    q.uv[i] = {(xy[i][0] - lo[0]) / lu, (xy[i][1] - lo[1]) / lv};
  // Scaled so the p5 and p95 cells lie as far (in ratio) below and above the size asked: a
  // free layout of a deep surface packs most triangles tighter than the mean (σ_A > 1) and a
  // few looser, so the mean would leave nearly all cells too large.
  const double k = std::sqrt(square.area / laid);
  q.length_u = lu * k, q.length_v = lv * k;
  q.area = 0, q.flips = 0;
  measure(q);
  const double centre = std::sqrt(std::sqrt(q.area_scale.p5 * q.area_scale.p95));
  if (std::isfinite(centre) && centre > 0) {
    q.length_u *= centre, q.length_v *= centre;
    q.area = 0, q.flips = 0;
    measure(q);
  }
  return q;
}

}  // namespace

SurfaceParameterization parameterize_surface(const TriangleSoup& surface,
                                             const ParameterizeOptions& options) {
  if (options.progress) options.progress->begin(std::string_view("parameterize"));
  Welded w = weld(surface);
  if (w.mesh.triangles.empty()) throw InputError("the surface has no triangles");
  const Edges e = directed_edges(w.mesh);
  const auto loops = check_and_loops(w.mesh, e);
  const std::size_t vertices = w.mesh.points.size(), faces = w.mesh.triangles.size();
  const std::size_t edges = (e.size() +
                             [&] {
                               std::size_t b = 0;
                               for (const auto& l : loops) b += l.size();
                               return b;
                             }()) /
                            2;
  const long euler = long(vertices) - long(edges) + long(faces);
  if (loops.empty()) throw InputError("the surface is closed: it needs a boundary to lay out");
  if (loops.size() > 2)
    throw InputError("the surface has " + std::to_string(loops.size()) +
                     " boundary loops; it can be laid out with one (a disk) or two (a tube)");
  if (euler != 2 - long(loops.size()))
    throw InputError("the surface has handles (genus " +
                     std::to_string((2 - long(loops.size()) - euler) / 2) +
                     "); only a disk or a tube can be laid out");
  if (loops.size() == 1 && loops[0].size() < 4)
    throw InputError("the surface's boundary has " + std::to_string(loops[0].size()) +
                     " points; laying it on a square needs at least 4");
  SurfaceParameterization p;
  p.boundary_loops = static_cast<int>(loops.size());
  std::array<std::uint32_t, 4> c{};
  std::vector<std::uint32_t> boundary = loops[0];  // of the disk laid out (a tube's: after the cut)
  std::vector<std::pair<std::uint32_t, std::uint32_t>> seam;  // a tube's (original, copy) points
  if (loops.size() == 2) {
    if (options.corners)
      throw InputError("a tube takes its corners from its seam; corners cannot be given");
    const std::vector<std::uint32_t> path = seam_path(w.mesh, e, loops[0], loops[1]);
    const std::vector<std::uint32_t> copy = cut_along(w.mesh, e, path);
    for (std::size_t i = 0; i < path.size(); ++i) seam.emplace_back(path[i], copy[i]);
    p.periodic_u = true;
    p.seam_edges = path.size() - 1;
    // With the surface on the left the cut disk's boundary runs along loop 0 into the seam's
    // start, up one side of the seam, along loop 1 and down the other side: corners at the
    // seam's ends, so the loops are v = 0 and v = 1 and the seam's sides u = 0 and u = 1.
    boundary = disk_boundary(w.mesh);
    const std::vector<std::uint32_t>& loop = boundary;
    const std::array<std::uint32_t, 4> ends{path.front(), copy.front(), path.back(), copy.back()};
    std::array<std::size_t, 4> at{};
    for (int q = 0; q < 4; ++q) at[q] = std::find(loop.begin(), loop.end(), ends[q]) - loop.begin();
    // Consecutive corners on the same loop bound that loop's side: start at loop 0's side.
    std::array<std::pair<std::size_t, std::uint32_t>, 4> sorted{};
    for (int q = 0; q < 4; ++q) sorted[q] = {at[q], ends[q]};
    std::sort(sorted.begin(), sorted.end());
    auto on_loop0 = [&](std::uint32_t v) { return v == path.front() || v == copy.front(); };
    int first = 0;
    while (!(on_loop0(sorted[first].second) && on_loop0(sorted[(first + 1) % 4].second))) ++first;
    for (int q = 0; q < 4; ++q) c[q] = sorted[(first + q) % 4].second;
  } else {
    c = options.corners ? given_corners(*options.corners, w.merged, loops[0])
                        : default_corners(w.mesh, loops[0]);
  }
  if (options.corners && options.method == LayoutMethod::Free)
    throw InputError("a free layout places no corners; corners need the square layout");
  p.corners = c;
  p.uv = solve_mvc(w.mesh, boundary, c);
  const std::vector<std::uint32_t>& loop = boundary;
  p.length_u =
      0.5 * (path_length(w.mesh, loop, c[0], c[1]) + path_length(w.mesh, loop, c[2], c[3]));
  p.length_v =
      0.5 * (path_length(w.mesh, loop, c[1], c[2]) + path_length(w.mesh, loop, c[3], c[0]));
  // The sides' ratio, scaled to the surface's area: cells keep their size on average (a dome's
  // boundary is far shorter than its area suggests).
  double area = 0;
  for (const Triangle& t : w.mesh.triangles)
    area += 0.5 * norm(cross(w.mesh.points[t[1]] - w.mesh.points[t[0]],
                             w.mesh.points[t[2]] - w.mesh.points[t[0]]));
  const double k = std::sqrt(area / (p.length_u * p.length_v));
  p.length_u *= k, p.length_v *= k;
  p.mesh = std::move(w.mesh);
  p.source_triangle = std::move(w.source_triangle);
  measure(p);
  if (options.method == LayoutMethod::Square || options.corners) return p;
  SurfaceParameterization q = free_layout(p, seam);
  if (options.method == LayoutMethod::Free) return q;
  const auto ratio = [](const Spread& s) { return s.p95 / std::max(s.p5, 1e-300); };
  if (q.flips == 0 && ratio(q.area_scale) < 0.95 * ratio(p.area_scale)) {
    q.other_area_scale = p.area_scale;
    return q;
  }
  p.other_area_scale = q.area_scale;
  p.free_iterations = q.free_iterations;
  return p;
}

std::string_view layout_method_name(LayoutMethod method) {
  return detail::name_of(kLayoutMethods, method);
}

LayoutMethod layout_method_from_name(std::string_view name) {
  return detail::from_name(kLayoutMethods, name, "layout");
}

}  // namespace tpmsfill
