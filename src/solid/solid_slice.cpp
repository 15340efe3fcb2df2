// Direct slicing and iso-material surfaces of a fitted solid (solid_slice.hpp): an octree in
// the parameter cube, one level for marching cubes, vertices by regula falsi, mapped through G.
#include "tpmsfill/solid/solid_slice.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <string>
#include <tuple>
#include <unordered_map>

#include "layers/covered_region.hpp"
#include "sampling/mc_tables.hpp"
#include "solid/internal/spline_terms.hpp"
#include "tpmsfill/error.hpp"

namespace tpmsfill {
namespace {

constexpr int kMaxLevel = 16;

using Cell = OctreeCell;

// (level, i, j, k) in one integer (18 bits per index).
std::uint64_t cell_key(int level, std::array<std::uint32_t, 3> i) {
  return std::uint64_t(level) << 54 | std::uint64_t(i[2]) << 36 | std::uint64_t(i[1]) << 18 | i[0];
}

struct Range {
  double lo = std::numeric_limits<double>::infinity();
  double hi = -std::numeric_limits<double>::infinity();
  void add(const Range& r) { lo = std::min(lo, r.lo), hi = std::max(hi, r.hi); }
  bool may_cross() const { return lo < 0 && hi >= 0; }  // inside is f < 0
};

struct Corner {
  double f = 0;  // the scalar minus the level
  Vec3 position;
  double material = 0;
};

// The level set f = F − value = 0 of one component F of the solid (0..2: G's x, y, z; 3: M).
class LevelSetFinder {
 public:
  LevelSetFinder(const SolidSpline& spline, int component, double value,
                 const SolidSliceOptions& options)
      : spline_(spline), component_(component), value_(value), options_(options) {
    dyadic_ = spline.basis.spans.size() > 1 || spline.basis.spans[0] == 1;
    element_ranges();
  }

  // Steps 1–3 of the file comment: the cells of one level that marching cubes runs on.
  std::vector<Cell> cells(double tau) {
    std::vector<Cell> current, kept;
    const std::uint32_t n = 1u << options_.initial_level;
    for (std::uint32_t k = 0; k < n; ++k)
      for (std::uint32_t j = 0; j < n; ++j)
        for (std::uint32_t i = 0; i < n; ++i)
          current.push_back({options_.initial_level, {i, j, k}});
    while (!current.empty()) {
      std::vector<Cell> next;
      for (const Cell& c : current) {
        if (!keep(c)) continue;
        if (c.level < options_.max_level && volume(c) > tau)
          for (int o = 0; o < 8; ++o) next.push_back(child(c, o));
        else
          kept.push_back(c);
      }
      current = std::move(next);
    }
    level_ = options_.initial_level;
    for (const Cell& c : kept) level_ = std::max(level_, c.level);
    std::vector<Cell> out;
    for (const Cell& c : kept) descend(c, out);
    close_surface(out);
    std::sort(out.begin(), out.end(), [](const Cell& a, const Cell& b) {
      return std::tie(a.index[2], a.index[1], a.index[0]) <
             std::tie(b.index[2], b.index[1], b.index[0]);
    });
    return out;
  }

  // Below the basis's leaves only corners decide, and a cell whose corners agree may still be
  // crossed on a face its neighbour shares. So: every cell around every crossed edge is added,
  // until none is missing. The level set is then closed inside the cube (no cracks).
  void close_surface(std::vector<Cell>& cells) {
    const detail::McTables& tables = detail::mc_tables();
    std::unordered_map<std::uint64_t, char> have;
    for (const Cell& c : cells) have.emplace(cell_key(c.level, c.index), 1);
    const std::int64_t n = std::int64_t{1} << level_;
    for (std::size_t at = 0; at < cells.size(); ++at) {
      const Cell c = cells[at];
      unsigned config = 0;
      for (int k = 0; k < 8; ++k) config |= static_cast<unsigned>(corner_at(c, k).f < 0) << k;
      for (int e = 0; e < 12; ++e) {
        if (!(tables.crossed_edges[config] >> e & 1)) continue;
        const int c0 = tables.edge_corners[e][0], axis = e / 4;
        const std::int64_t lower[3] = {c.index[0] + (c0 & 1), c.index[1] + (c0 >> 1 & 1),
                                       c.index[2] + (c0 >> 2 & 1)};
        for (int o = 0; o < 4; ++o) {  // the four cells around the edge
          std::int64_t i[3] = {lower[0], lower[1], lower[2]};
          i[(axis + 1) % 3] -= o & 1;
          i[(axis + 2) % 3] -= o >> 1 & 1;
          if (std::min({i[0], i[1], i[2]}) < 0 || std::max({i[0], i[1], i[2]}) >= n) continue;
          const Cell around{level_,
                            {static_cast<std::uint32_t>(i[0]), static_cast<std::uint32_t>(i[1]),
                             static_cast<std::uint32_t>(i[2])}};
          if (have.emplace(cell_key(around.level, around.index), 1).second) cells.push_back(around);
        }
      }
    }
  }

  // Step 4: marching cubes over the cells, vertices shared by edge id.
  SolidLevelSet extract(const std::vector<Cell>& cells) {
    const detail::McTables& tables = detail::mc_tables();
    SolidLevelSet out;
    out.level = level_;
    out.cells = cells.size();
    std::unordered_map<std::uint64_t, std::uint32_t> edge_vertex;
    for (const Cell& c : cells) {
      std::array<const Corner*, 8> corner{};
      unsigned config = 0;
      for (int k = 0; k < 8; ++k) {
        corner[k] = &corner_at(c, k);
        config |= static_cast<unsigned>(corner[k]->f < 0) << k;
      }
      if (config == 0 || config == 255) continue;
      const detail::McCase& mc =
          tables.cases[detail::mc_case_key(tables, config, [&](int k) { return corner[k]->f; })];
      std::array<std::uint32_t, 16> slot{};
      for (int e = 0; e < 12; ++e) {
        if (!(tables.crossed_edges[config] >> e & 1)) continue;
        const auto [c0, c1] = tables.edge_corners[e];
        const std::uint64_t key = edge_key(c, c0, e / 4);
        const auto [at, fresh] =
            edge_vertex.emplace(key, static_cast<std::uint32_t>(out.points.size()));
        if (fresh)
          add_crossing(corner_uvw(c, c0), corner_uvw(c, c1), *corner[c0], *corner[c1], out);
        slot[e] = at->second;
      }
      for (int m = 0; m < mc.centroid_count; ++m) {
        std::array<double, 3> mean{};
        int count = 0;
        for (unsigned bits = mc.centroid_edges[m]; bits; bits &= bits - 1, ++count)
          for (int a = 0; a < 3; ++a) mean[a] += out.uvw[slot[__builtin_ctz(bits)]][a];
        for (double& x : mean) x /= count;
        slot[12 + m] = static_cast<std::uint32_t>(out.points.size());
        add_point(project(mean, c), out);
      }
      for (int t = 0; t < mc.triangle_count; ++t)
        out.triangles.push_back(
            {slot[mc.triangles[t][0]], slot[mc.triangles[t][1]], slot[mc.triangles[t][2]]});
    }
    out.evaluations = evaluations_;
    return out;
  }

  const Box3& box() const { return box_; }  // of the control points, which hold the solid

 private:
  double scalar(const SolidPoint& p) const {
    return (component_ < 3 ? (&p.position.x)[component_] : p.material) - value_;
  }

  // The range of f's local B-spline coefficients per leaf (a bound of f over it), and per
  // octree node the union over its leaves.
  void element_ranges() {
    const SplineBasis& b = spline_.basis;
    for (const Vec3& p : spline_.geometry) {
      box_.min = {std::min(box_.min.x, p.x), std::min(box_.min.y, p.y), std::min(box_.min.z, p.z)};
      box_.max = {std::max(box_.max.x, p.x), std::max(box_.max.y, p.y), std::max(box_.max.z, p.z)};
    }
    size_ = std::max(norm(box_.max - box_.min), 1e-300);
    ranges_.resize(b.elements.size());
    for (std::size_t e = 0; e < b.elements.size(); ++e) {
      std::array<double, 64> local{};
      detail::for_each_term(b, e, [&](int k, std::uint32_t f, double w) {
        local[k] +=
            w * (component_ < 3 ? (&spline_.geometry[f].x)[component_] : spline_.material[f]);
      });
      for (double x : local) ranges_[e].add({x - value_, x - value_});
      if (!dyadic_) continue;
      const Cell& c = b.elements[e];
      for (int l = c.level; l >= 0; --l) {
        const int s = c.level - l;
        node_range_[cell_key(l, {c.index[0] >> s, c.index[1] >> s, c.index[2] >> s})].add(
            ranges_[e]);
      }
    }
  }

  // A bound of f over the cell, while the cell is no deeper than the basis's leaves there.
  bool range(const Cell& c, Range& r) const {
    if (dyadic_) {
      const auto found = node_range_.find(cell_key(c.level, c.index));
      if (found == node_range_.end()) return false;
      r = found->second;
      return true;
    }
    const std::uint32_t spans = spline_.basis.spans[0];
    const double n = std::ldexp(1.0, c.level);
    if (n > spans) return false;
    std::array<std::uint32_t, 3> lo{}, hi{};
    for (int a = 0; a < 3; ++a) {
      lo[a] = static_cast<std::uint32_t>(std::floor(c.index[a] * spans / n));
      hi[a] = std::min(spans, static_cast<std::uint32_t>(std::ceil((c.index[a] + 1) * spans / n)));
    }
    for (std::uint32_t k = lo[2]; k < hi[2]; ++k)
      for (std::uint32_t j = lo[1]; j < hi[1]; ++j)
        for (std::uint32_t i = lo[0]; i < hi[0]; ++i) r.add(ranges_[i + spans * (j + spans * k)]);
    return true;
  }

  bool keep(const Cell& c) {
    bool below = false, above = false;
    for (int k = 0; k < 8; ++k) (corner_at(c, k).f < 0 ? below : above) = true;
    if (below && above) return true;
    Range r;
    return range(c, r) && r.may_cross();
  }

  void descend(const Cell& c, std::vector<Cell>& out) {
    if (c.level == level_) {
      out.push_back(c);
      return;
    }
    for (int o = 0; o < 8; ++o) {
      const Cell ch = child(c, o);
      if (keep(ch)) descend(ch, out);
    }
  }

  static Cell child(const Cell& c, int o) {
    return {
        c.level + 1,
        {2 * c.index[0] + (o & 1), 2 * c.index[1] + (o >> 1 & 1), 2 * c.index[2] + (o >> 2 & 1)}};
  }

  // Corner k of a cell in integer coordinates of the deepest level.
  std::array<std::uint32_t, 3> corner_index(const Cell& c, int k) const {
    const int s = kMaxLevel - c.level;
    return {(c.index[0] + (k & 1)) << s, (c.index[1] + (k >> 1 & 1)) << s,
            (c.index[2] + (k >> 2 & 1)) << s};
  }

  std::array<double, 3> corner_uvw(const Cell& c, int k) const {
    const std::array<std::uint32_t, 3> i = corner_index(c, k);
    return {std::ldexp(double(i[0]), -kMaxLevel), std::ldexp(double(i[1]), -kMaxLevel),
            std::ldexp(double(i[2]), -kMaxLevel)};
  }

  const Corner& corner_at(const Cell& c, int k) {
    const std::array<std::uint32_t, 3> i = corner_index(c, k);
    const std::uint64_t key = std::uint64_t(i[2]) << 42 | std::uint64_t(i[1]) << 21 | i[0];
    const auto found = corners_.find(key);
    if (found != corners_.end()) return found->second;
    const SolidPoint p = evaluate(corner_uvw(c, k));
    return corners_.emplace(key, Corner{scalar(p), p.position, p.material}).first->second;
  }

  SolidPoint evaluate(std::array<double, 3> uvw) {
    ++evaluations_;
    return evaluate_solid(spline_, uvw);
  }

  // The edge from corner c0 along `axis`: its lower corner at the cells' level, and the axis.
  std::uint64_t edge_key(const Cell& c, int c0, int axis) const {
    const std::array<std::uint32_t, 3> i = {c.index[0] + (c0 & 1), c.index[1] + (c0 >> 1 & 1),
                                            c.index[2] + (c0 >> 2 & 1)};
    return std::uint64_t(axis) << 60 | std::uint64_t(i[2]) << 40 | std::uint64_t(i[1]) << 20 | i[0];
  }

  // Volume of the cell's image: its 8 mapped corners as the 6 tets around the diagonal 0–7.
  double volume(const Cell& c) {
    static constexpr int kTets[6][2] = {{1, 3}, {3, 2}, {2, 6}, {6, 4}, {4, 5}, {5, 1}};
    Vec3 p[8];
    for (int k = 0; k < 8; ++k) p[k] = corner_at(c, k).position;
    double v = 0;
    for (const auto& t : kTets)
      v += std::abs(dot(p[t[0]] - p[0], cross(p[t[1]] - p[0], p[7] - p[0]))) / 6;
    return v;
  }

  // The point of the edge a → b where f = 0: regula falsi, Illinois variant.
  void add_crossing(std::array<double, 3> a, std::array<double, 3> b, const Corner& ca,
                    const Corner& cb, SolidLevelSet& out) {
    double fa = ca.f, fb = cb.f, ta = 0, tb = 1;
    const double tolerance = 1e-9 * size_;
    auto at = [&](double t) {
      return std::array<double, 3>{a[0] + t * (b[0] - a[0]), a[1] + t * (b[1] - a[1]),
                                   a[2] + t * (b[2] - a[2])};
    };
    double t = ta - fa * (tb - ta) / (fb - fa);
    SolidPoint p = evaluate(at(t));
    int side = 0;
    for (int it = 0; it < 40 && std::abs(scalar(p)) > tolerance; ++it) {
      const double ft = scalar(p);
      if ((ft < 0) == (fa < 0)) {
        ta = t, fa = ft;
        if (side == -1) fb /= 2;
        side = -1;
      } else {
        tb = t, fb = ft;
        if (side == 1) fa /= 2;
        side = 1;
      }
      t = ta - fa * (tb - ta) / (fb - fa);
      p = evaluate(at(t));
    }
    out.uvw.push_back(at(t));
    out.points.push_back(p.position);
    out.material.push_back(p.material);
  }

  // A centroid of a loop of edge points, moved onto f = 0 along ∇f (a few Newton steps),
  // kept within its cell so that its triangles do not turn over.
  std::array<double, 3> project(std::array<double, 3> x, const Cell& c) {
    const std::array<double, 3> lo = corner_uvw(c, 0), hi = corner_uvw(c, 7);
    for (int it = 0; it < 8; ++it) {
      const SolidPoint p = evaluate(x);
      const double f = scalar(p);
      if (std::abs(f) <= 1e-9 * size_) break;
      const Vec3 g = component_ < 3
                         ? Vec3{(&p.jacobian[0].x)[component_], (&p.jacobian[1].x)[component_],
                                (&p.jacobian[2].x)[component_]}
                         : p.material_gradient;
      const double g2 = dot(g, g);
      if (!(g2 > 0)) break;
      const double step[3] = {f * g.x / g2, f * g.y / g2, f * g.z / g2};
      for (int a = 0; a < 3; ++a) x[a] = std::clamp(x[a] - step[a], lo[a], hi[a]);
    }
    return x;
  }

  void add_point(std::array<double, 3> uvw, SolidLevelSet& out) {
    const SolidPoint p = evaluate(uvw);
    out.uvw.push_back(uvw);
    out.points.push_back(p.position);
    out.material.push_back(p.material);
  }

  const SolidSpline& spline_;
  int component_;
  double value_;
  SolidSliceOptions options_;
  bool dyadic_ = true;
  Box3 box_;
  double size_ = 1;
  int level_ = 0;
  std::size_t evaluations_ = 0;
  std::vector<Range> ranges_;
  std::unordered_map<std::uint64_t, Range> node_range_;
  std::unordered_map<std::uint64_t, Corner> corners_;
};

void check_options(const SolidSpline& spline, const SolidSliceOptions& o) {
  if (spline.geometry.size() != spline.basis.functions.size() || spline.basis.elements.empty())
    throw InputError("the spline has no control points for its basis");
  if (!(o.tau >= 0)) throw InputError("tau must not be negative");
  if (o.max_level < 0 || o.max_level > kMaxLevel || o.initial_level < 0 ||
      o.initial_level > o.max_level)
    throw InputError("slice levels must be 0 to 16, the initial one not above the deepest");
}

// The section's border edges chained into closed contours (the triangles counter-clockwise
// from +z, so outer boundaries come out counter-clockwise and holes clockwise).
std::vector<Contour> border_contours(const SolidLevelSet& mesh) {
  std::map<std::pair<std::uint32_t, std::uint32_t>, int> uses;
  for (const auto& t : mesh.triangles)
    for (int e = 0; e < 3; ++e) ++uses[{t[e], t[(e + 1) % 3]}];
  std::multimap<std::uint32_t, std::uint32_t> next;
  for (const auto& [edge, count] : uses)
    if (!uses.count({edge.second, edge.first})) next.emplace(edge.first, edge.second);
  std::vector<Contour> contours;
  while (!next.empty()) {
    Contour c;
    const std::uint32_t first = next.begin()->first;
    std::uint32_t at = first;
    do {
      const auto it = next.find(at);
      if (it == next.end()) break;  // an open chain: not closed (cannot happen in a 2-manifold)
      c.points.push_back({mesh.points[at].x, mesh.points[at].y});
      at = it->second;
      next.erase(it);
    } while (at != first);
    c.area = signed_area(c.points);
    contours.push_back(std::move(c));
  }
  return contours;
}

}  // namespace

double default_slice_tau(const Box3& box) {
  return std::pow(norm(box.max - box.min) / 64, 3);
}

SolidSection slice_solid(const SolidSpline& spline, double z, const SolidSliceOptions& options) {
  check_options(spline, options);
  LevelSetFinder finder(spline, 2, z, options);
  const double tau = options.tau > 0 ? options.tau : default_slice_tau(finder.box());
  SolidSection section;
  section.z = z;
  section.mesh = finder.extract(finder.cells(tau));
  for (Vec3& p : section.mesh.points) p.z = z;  // on the plane (edge points are, to 1e-9)
  std::vector<std::vector<Vec2>> turned;        // the turned-over triangles, reversed
  for (const auto& t : section.mesh.triangles) {
    const Vec3 a = section.mesh.points[t[0]], b = section.mesh.points[t[1]],
               c = section.mesh.points[t[2]];
    const double area = ((b.x - a.x) * (c.y - a.y) - (c.x - a.x) * (b.y - a.y)) / 2;
    section.area += area;
    if (area < 0) turned.push_back({{a.x, a.y}, {c.x, c.y}, {b.x, b.y}});
  }
  section.flipped = turned.size();
  section.contours = border_contours(section.mesh);
  if (section.flipped > 0) {
    // Where G folds, turned-over triangles lie over others and the border chains cross
    // themselves: their winding at a point is P − N (triangles covering it either way up),
    // so a printer filling them by any rule leaves notches where a fold doubles back (0 = 1 −
    // 1). Each turned-over triangle added twice, reversed, makes it P + N: the region the
    // solid covers at z, as simple contours.
    std::vector<std::vector<Vec2>> paths;
    for (const Contour& c : section.contours) paths.push_back(c.points);
    for (const auto& t : turned) paths.insert(paths.end(), 2, t);
    section.contours = detail::nonzero_region(paths);
    section.area = 0;
    for (const Contour& c : section.contours) section.area += c.area;
  }
  return section;
}

SolidLevelSet iso_material_surface(const SolidSpline& spline, double m,
                                   const SolidSliceOptions& options) {
  check_options(spline, options);
  if (spline.material.empty()) throw InputError("the spline has no material");
  LevelSetFinder finder(spline, 3, m, options);
  const double tau = options.tau > 0 ? options.tau : default_slice_tau(finder.box());
  return finder.extract(finder.cells(tau));
}

}  // namespace tpmsfill
