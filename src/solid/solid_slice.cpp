// Direct slicing and iso-material surfaces of a fitted solid (solid_slice.hpp): an octree in
// the parameter cube, marching cubes on its leaves of any level, vertices by regula falsi,
// mapped through G.
#include "tpmsfill/solid/solid_slice.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <string>
#include <tuple>
#include <unordered_map>
#include <unordered_set>

#include "layers/covered_region.hpp"
#include "mesh/exact_orientation.hpp"
#include "sampling/mc_tables.hpp"
#include "solid/internal/octree_cells.hpp"
#include "solid/internal/plane_flips.hpp"
#include "solid/internal/spline_terms.hpp"
#include "tpmsfill/error.hpp"

namespace tpmsfill {
namespace {

constexpr int kMaxLevel = 16;
constexpr int kTurnedPasses = 16;  // LevelSetFinder::extract_section()
constexpr double kFlat = 1;  // above any ear's shape (area over the sum of squared sides: < 0.15)

// A triangle's signed area in the xy plane: > 0 counter-clockwise from +z.
double plane_area(const SolidLevelSet& mesh, const std::array<std::uint32_t, 3>& t) {
  const Vec3 a = mesh.points[t[0]], b = mesh.points[t[1]], c = mesh.points[t[2]];
  return ((b.x - a.x) * (c.y - a.y) - (c.x - a.x) * (b.y - a.y)) / 2;
}

using Cell = OctreeCell;
using Index = std::array<std::uint32_t, 3>;  // a grid point of the deepest level

using detail::cell_key;

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

  // Steps 1–3 of the file comment: the leaves marching cubes runs on, each at its own level.
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
        if (c.level < options_.max_level && volume(c) > tau) {
          split_.insert(cell_key(c.level, c.index));
          for (int o = 0; o < 8; ++o) next.push_back(child(c, o));
        } else {
          kept.push_back(c);
        }
      }
      current = std::move(next);
    }
    deepest_ = options_.initial_level;
    for (const Cell& c : kept) deepest_ = std::max(deepest_, c.level);
    contour_leaves(kept, deepest_);
    close_surface(kept, deepest_, kept);
    in_order(kept);
    return kept;
  }

  // A section's leaves whose disks turn a triangle over in its plane where G does not fold:
  // a leaf's chords cut its curved image short, or cross (bear's default model, proven
  // fold-free in all but one of its 14,330 elements by fold_certificate.hpp, turned 284
  // triangles over in its stack). Each such leaf is split, the level set closed again
  // (close_surface) and extracted again, a level deeper a pass, for kTurnedPasses passes, no
  // deeper than so many levels below max_level. Passes beget passes: a split leaf's neighbours
  // gain fine face points that can cross their own long chords (bear's 40 % layer needed 11).
  // Where det J_G ≤ 0 at a triangle's corner G folds, and splitting mends nothing there.
  SolidLevelSet extract_section(std::vector<Cell> cells) {
    SolidLevelSet out = extract(cells);
    for (int pass = 0; pass < kTurnedPasses; ++pass) {
      std::vector<char> turned(cells.size(), 0);
      bool any = false;
      for (std::size_t i = 0; i < cells.size(); ++i) {
        if (cells[i].level >= std::min(kMaxLevel, options_.max_level + kTurnedPasses)) continue;
        for (std::uint32_t t = cell_triangles_[i]; t < cell_triangles_[i + 1] && !turned[i]; ++t)
          turned[i] = turned_over(out, out.triangles[t]) && unfolded(out, out.triangles[t]);
        any = any || turned[i];
      }
      if (!any) break;
      std::vector<Cell> todo;
      const std::size_t n = cells.size();
      for (std::size_t i = 0; i < n; ++i) {
        if (!turned[i]) continue;
        split_.insert(cell_key(cells[i].level, cells[i].index));
        around(cells[i], todo);
        for (int o = 0; o < 8; ++o)
          if (keep(child(cells[i], o))) cells.push_back(child(cells[i], o));
      }
      todo.insert(todo.end(), cells.begin() + static_cast<std::ptrdiff_t>(n), cells.end());
      close_surface(cells, deepest_, std::move(todo));
      in_order(cells);
      extract(cells, out);
    }
    drop_unused_points(out);
    return out;
  }

  // A section's area and contours are those of its border, where the level set crosses the
  // cube's faces (whatever levels tile its inside), and there a coarse leaf's chords cut the
  // curved outline short: 0.3 % of bear's sections at the default τ, 9 % of its top layer. So
  // leaves whose faces on the cube's faces are crossed go down to the deepest level τ asked
  // for anywhere in the layer, the inside keeping its own levels: bear's sections then have
  // the single level's areas to 0.12 % (all of the cube's leaves there: to 0.004 %, with 1.6
  // times the triangles).
  void contour_leaves(std::vector<Cell>& kept, int deepest) {
    std::vector<Cell> todo;
    todo.swap(kept);
    while (!todo.empty()) {
      const Cell c = todo.back();
      todo.pop_back();
      if (c.level >= deepest || !on_contour(c)) {
        kept.push_back(c);
        continue;
      }
      split_.insert(cell_key(c.level, c.index));
      for (int o = 0; o < 8; ++o)
        if (keep(child(c, o))) todo.push_back(child(c, o));
    }
  }

  // Whether the level set crosses one of the cell's faces on the cube's faces (by its corners).
  bool on_contour(const Cell& c) {
    const detail::McTables& tables = detail::mc_tables();
    const std::uint32_t last = (1u << c.level) - 1;
    for (int f = 0; f < 6; ++f) {
      if (c.index[f / 2] != (f % 2 ? last : 0)) continue;
      bool below = false, above = false;
      for (int k : tables.face_corners[f]) (corner_at(c, k).f < 0 ? below : above) = true;
      if (below && above) return true;
    }
    return false;
  }

  // Below the basis's leaves only corners decide, and a leaf whose corners agree on a face
  // may still be crossed there where a finer neighbour samples that face. So the leaf across
  // every crossed face piece of a kept leaf is split down to the piece's level and the cell
  // across kept, with its crossed siblings on the way; and a kept leaf whose own corners miss
  // a crossing on one of its faces is split too (below the deepest level), since its loop
  // would lie flat on that face and cap the neighbour's bump turned over (fandisk's 60 %
  // section). A split changes the pieces and edges of the leaves around it, which are checked
  // again, until none changes. The level set is then closed inside the cube (no cracks).
  // `todo`: the leaves to check first (all of them, or those around a few splits).
  void close_surface(std::vector<Cell>& cells, int deepest, std::vector<Cell> todo) {
    const detail::McTables& tables = detail::mc_tables();
    std::unordered_set<std::uint64_t> have;
    for (const Cell& c : cells) have.insert(cell_key(c.level, c.index));
    std::vector<Index> walk;
    const auto split_cell = [&](const Cell& c) {
      split_.insert(cell_key(c.level, c.index));
      around(c, todo);
    };
    // Checks one leaf; true where it changed the tree.
    const auto check = [&](const Cell& c) {
      if (split_.count(cell_key(c.level, c.index)) || !have.count(cell_key(c.level, c.index)))
        return false;
      bool misses = false, changed = false;
      for_each_piece(c, [&](const Piece& p) {
        samples(p, walk);
        bool inside = sample(walk.back()).f < 0, crossed = false;
        for (const Index& i : walk) crossed |= (sample(i).f < 0) != inside;
        if (!crossed) return;
        if (c.level < deepest && !misses) {
          bool below = false, above = false;
          for (int k : tables.face_corners[2 * p.axis + p.side])
            (corner_at(c, k).f < 0 ? below : above) = true;
          misses = !(below && above);
        }
        if (p.border) return;
        Cell leaf = leaf_at(p.other);
        if (have.count(cell_key(leaf.level, leaf.index))) return;
        changed = true;
        for (; leaf.level < p.level; ++leaf.level) {
          split_cell(leaf);
          const int s = p.level - leaf.level - 1;
          const Index on = {p.other.index[0] >> s, p.other.index[1] >> s, p.other.index[2] >> s};
          for (int o = 0; o < 8; ++o) {
            const Cell ch = child(leaf, o);
            if (ch.index != on && keep(ch) && have.insert(cell_key(ch.level, ch.index)).second)
              cells.push_back(ch), todo.push_back(ch);
          }
          leaf.index = on;
        }
        if (have.insert(cell_key(leaf.level, leaf.index)).second)
          cells.push_back(leaf), todo.push_back(leaf);
      });
      if (!misses) return changed;
      split_cell(c);
      for (int o = 0; o < 8; ++o) {
        const Cell ch = child(c, o);
        if (keep(ch) && have.insert(cell_key(ch.level, ch.index)).second)
          cells.push_back(ch), todo.push_back(ch);
      }
      return true;
    };
    // The leaves around the splits first, then whole passes until one changes nothing (what
    // the worklist misses: bear's 40 % section had 3 cracks without them).
    for (bool changed = true; changed;) {
      while (!todo.empty()) {
        const Cell c = todo.back();
        todo.pop_back();
        check(c);
      }
      changed = false;
      for (std::size_t at = 0; at < cells.size(); ++at) changed = check(Cell(cells[at])) || changed;
    }
    std::erase_if(cells,
                  [&](const Cell& c) { return split_.count(cell_key(c.level, c.index)) > 0; });
  }

  // The leaves no finer than c that share a face, an edge or a corner with it: those whose
  // pieces and edges c's split changes (finer ones already see c's children's level).
  void around(const Cell& c, std::vector<Cell>& out) const {
    const std::int64_t n = std::int64_t{1} << c.level;
    for (int d = 0; d < 27; ++d) {
      if (d == 13) continue;  // c itself
      std::int64_t i[3] = {c.index[0] + d % 3 - 1, c.index[1] + d / 3 % 3 - 1,
                           c.index[2] + d / 9 - 1};
      if (std::min({i[0], i[1], i[2]}) < 0 || std::max({i[0], i[1], i[2]}) >= n) continue;
      out.push_back(leaf_at({c.level,
                             {static_cast<std::uint32_t>(i[0]), static_cast<std::uint32_t>(i[1]),
                              static_cast<std::uint32_t>(i[2])}}));
    }
  }

  // Step 4: marching cubes over the leaves, vertices shared by their segment's key. A leaf
  // whose faces and edges no finer neighbour subdivides takes its loops from the table; any
  // other links the segments of its face pieces into loops (cubical marching squares, Ho et
  // al. 2005): both leaves sharing a piece see the same samples and segments, whatever their
  // levels, so no 2:1 balance is needed and no crack opens. Each loop becomes a disk (disk).
  SolidLevelSet extract(const std::vector<Cell>& cells) {
    SolidLevelSet out;
    extract(cells, out);
    return out;
  }

  // The same into `out`, replacing its triangles and keeping its points (the segments' found
  // again by their keys, not computed again).
  void extract(const std::vector<Cell>& cells, SolidLevelSet& out) {
    const detail::McTables& tables = detail::mc_tables();
    out.triangles.clear();
    out.level = level_;
    out.cells = cells.size();
    std::vector<Index> walk;
    std::vector<std::pair<std::uint32_t, std::uint32_t>> links;
    std::vector<std::uint32_t> loop;
    cell_triangles_.clear();
    for (const Cell& c : cells) {
      cell_triangles_.push_back(static_cast<std::uint32_t>(out.triangles.size()));
      if (!plain(c)) {
        links.clear();
        for_each_piece(c, [&](const Piece& p) { link(p, walk, links, out); });
        triangulate(c, links, loop, out);
        continue;
      }
      std::array<const Corner*, 8> corner{};
      unsigned config = 0;
      for (int k = 0; k < 8; ++k) {
        corner[k] = &sample(corner_index(c, k));
        config |= static_cast<unsigned>(corner[k]->f < 0) << k;
      }
      if (config == 0 || config == 255) continue;
      const unsigned key = detail::mc_case_key(tables, config, [&](int k) { return corner[k]->f; });
      std::array<std::uint32_t, 12> slot{};
      for (int e = 0; e < 12; ++e) {
        if (!(tables.crossed_edges[config] >> e & 1)) continue;
        const auto [c0, c1] = tables.edge_corners[e];
        slot[e] = vertex(e / 4, corner_index(c, c0), corner_index(c, c1), out);
      }
      for (const auto& edges : tables.loops[key]) {
        loop.clear();
        for (std::uint8_t e : edges) loop.push_back(slot[e]);
        disk(c, loop, out);
      }
    }
    cell_triangles_.push_back(static_cast<std::uint32_t>(out.triangles.size()));
    out.evaluations = evaluations_;
  }

  const Box3& box() const { return box_; }  // of the control points, which hold the solid

 private:
  // The leaves in one order (their first corner's z, y, x, then level), whatever order the
  // splits left them in, so that the points' and triangles' order is the same every run.
  void in_order(std::vector<Cell>& cells) {
    level_ = options_.initial_level;
    for (const Cell& c : cells) level_ = std::max(level_, c.level);
    std::sort(cells.begin(), cells.end(), [](const Cell& a, const Cell& b) {
      const Index p = corner_index(a, 0), q = corner_index(b, 0);
      return std::tie(p[2], p[1], p[0], a.level) < std::tie(q[2], q[1], q[0], b.level);
    });
  }

  // The points no triangle uses (the split leaves' own: their fans' centres, their segments'
  // crossings that no leaf kept shares) taken out, in order; vertices_ forgets them all.
  void drop_unused_points(SolidLevelSet& mesh) {
    std::vector<std::uint32_t> at(mesh.points.size(), 0);
    for (const auto& t : mesh.triangles)
      for (std::uint32_t v : t) at[v] = 1;
    std::uint32_t kept = 0;
    for (std::size_t v = 0; v < at.size(); ++v) {
      if (!at[v]) continue;
      mesh.points[kept] = mesh.points[v], mesh.uvw[kept] = mesh.uvw[v];
      mesh.material[kept] = mesh.material[v];
      at[v] = kept++;
    }
    mesh.points.resize(kept), mesh.uvw.resize(kept), mesh.material.resize(kept);
    for (auto& t : mesh.triangles)
      for (std::uint32_t& v : t) v = at[v];
    vertices_.clear();
  }

  // det J_G > 0 at the triangle's three corners: where G folds, a split leaf turns over
  // again, as many times as it is split.
  bool unfolded(const SolidLevelSet& mesh, const std::array<std::uint32_t, 3>& t) {
    for (std::uint32_t v : t) {
      const SolidPoint p = evaluate(mesh.uvw[v]);
      if (!(dot(cross(p.jacobian[0], p.jacobian[1]), p.jacobian[2]) > 0)) return false;
    }
    return true;
  }

  // Turned over by more than rounding: a layer along a grid plane makes triangles flat to
  // rounding, either way up, which no split mends.
  static bool turned_over(const SolidLevelSet& mesh, const std::array<std::uint32_t, 3>& t) {
    const Vec3 u = mesh.points[t[1]] - mesh.points[t[0]], v = mesh.points[t[2]] - mesh.points[t[0]];
    return 2 * plane_area(mesh, t) < -1e-9 * (dot(u, u) + dot(v, v));
  }

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
    local_.resize(64 * b.elements.size());
    for (std::size_t e = 0; e < b.elements.size(); ++e) {
      std::array<double, 64> local{};
      detail::for_each_term(b, e, [&](int k, std::uint32_t f, double w) {
        local[k] +=
            w * (component_ < 3 ? (&spline_.geometry[f].x)[component_] : spline_.material[f]);
      });
      for (double x : local) ranges_[e].add({x - value_, x - value_});
      std::copy(local.begin(), local.end(), local_.begin() + static_cast<std::ptrdiff_t>(64 * e));
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

  static Cell child(const Cell& c, int o) { return detail::child_cell(c, o); }

  // Corner k of a cell in integer coordinates of the deepest level.
  static Index corner_index(const Cell& c, int k) {
    const int s = kMaxLevel - c.level;
    return {(c.index[0] + (k & 1)) << s, (c.index[1] + (k >> 1 & 1)) << s,
            (c.index[2] + (k >> 2 & 1)) << s};
  }

  static std::array<double, 3> uvw(const Index& i) {
    return {std::ldexp(double(i[0]), -kMaxLevel), std::ldexp(double(i[1]), -kMaxLevel),
            std::ldexp(double(i[2]), -kMaxLevel)};
  }

  std::array<double, 3> corner_uvw(const Cell& c, int k) const { return uvw(corner_index(c, k)); }

  const Corner& sample(const Index& i) {
    const std::uint64_t key = std::uint64_t(i[2]) << 42 | std::uint64_t(i[1]) << 21 | i[0];
    const auto found = corners_.find(key);
    if (found != corners_.end()) return found->second;
    const SolidPoint p = point_at(uvw(i));
    // A sample within regula falsi's tolerance of the level set is on it, and 0 counts as
    // outside: where a layer runs along a grid plane, rounding alone would otherwise pick each
    // sample's side there, and the loops it made doubled back and turned over.
    const double f = std::abs(scalar(p)) <= 1e-9 * size_ ? 0 : scalar(p);
    return corners_.emplace(key, Corner{f, p.position, p.material}).first->second;
  }

  const Corner& corner_at(const Cell& c, int k) { return sample(corner_index(c, k)); }

  SolidPoint evaluate(std::array<double, 3> uvw) {
    ++evaluations_;
    return evaluate_solid(spline_, uvw);
  }

  // G and M without their derivatives, which only project() needs.
  SolidPoint point_at(std::array<double, 3> uvw) {
    ++evaluations_;
    return detail::solid_point(spline_, uvw, false);
  }

  // f alone, from its element's local coefficients: regula falsi's steps need no more than
  // this, and G, M and their derivatives cost it several times over.
  double scalar_at(std::array<double, 3> uvw) {
    ++evaluations_;
    for (double& x : uvw) x = std::clamp(x, 0.0, 1.0);
    const std::size_t e = basis_element_at(spline_.basis, uvw);
    const LocalBasis b = local_basis(spline_.basis, e, uvw, 0);
    const double* local = &local_[64 * e];
    double f = 0;
    for (int k = 0; k < 64; ++k) f += b.value[k] * local[k];
    return f - value_;
  }

  bool split(int level, const std::int64_t (&i)[3]) const {
    const std::int64_t n = std::int64_t{1} << level;
    for (std::int64_t x : i)
      if (x < 0 || x >= n) return false;
    return split_.count(
               cell_key(level, {static_cast<std::uint32_t>(i[0]), static_cast<std::uint32_t>(i[1]),
                                static_cast<std::uint32_t>(i[2])})) > 0;
  }

  // The segment of `level` along `axis` from p: split when a cell of that level around it is.
  // Every leaf touching the segment asks the same tree, so all agree on its samples.
  bool split_segment(int axis, int level, const Index& p) const {
    const int s = kMaxLevel - level, u = (axis + 1) % 3, v = (axis + 2) % 3;
    for (int o = 0; o < 4; ++o) {
      std::int64_t i[3] = {p[0] >> s, p[1] >> s, p[2] >> s};
      i[u] -= o & 1;
      i[v] -= o >> 1 & 1;
      if (split(level, i)) return true;
    }
    return false;
  }

  // The points strictly inside the segment where finer leaves sample it, in increasing order.
  void segment_points(int axis, int level, Index p, std::vector<Index>& out) const {
    if (level >= kMaxLevel || !split_segment(axis, level, p)) return;
    segment_points(axis, level + 1, p, out);
    p[axis] += 1u << (kMaxLevel - level - 1);
    out.push_back(p);
    segment_points(axis, level + 1, p, out);
  }

  // A leaf's 12 edges and 6 faces are whole: marching cubes' table applies.
  bool plain(const Cell& c) const {
    for (int a = 0; a < 3; ++a)
      for (int s = 0; s < 2; ++s) {
        std::int64_t i[3] = {c.index[0], c.index[1], c.index[2]};
        i[a] += s ? 1 : -1;
        if (split(c.level, i)) return false;
      }
    for (int e = 0; e < 12; ++e)
      if (split_segment(e / 4, c.level, corner_index(c, detail::mc_tables().edge_corners[e][0])))
        return false;
    return true;
  }

  // One square of a leaf's face, as fine as the leaves on either side: the face (axis, side)
  // at `level`, from `lower` (integer coordinates of the deepest level), with the cell across.
  struct Piece {
    int axis = 0, side = 0, level = 0;
    Index lower{};
    bool border = false;  // on the cube's face: nothing across
    Cell other;
  };

  template <class Visit>
  void for_each_piece(const Cell& c, const Visit& visit) const {
    const std::int64_t n = std::int64_t{1} << c.level;
    for (int a = 0; a < 3; ++a)
      for (int s = 0; s < 2; ++s) {
        std::int64_t i[3] = {c.index[0], c.index[1], c.index[2]};
        i[a] += s ? 1 : -1;
        Piece p{a, s, c.level, corner_index(c, s << a), i[a] < 0 || i[a] >= n, c};
        if (!p.border) p.other.index[a] = static_cast<std::uint32_t>(i[a]);
        pieces(p, visit);
      }
  }

  template <class Visit>
  void pieces(const Piece& p, const Visit& visit) const {
    if (p.border || !split_.count(cell_key(p.level, p.other.index))) {
      visit(p);
      return;
    }
    const int u = (p.axis + 1) % 3, v = (p.axis + 2) % 3, half = kMaxLevel - p.level - 1;
    for (int o = 0; o < 4; ++o) {
      Piece q = p;
      q.level = p.level + 1;
      const int bits = (p.side ? 0 : 1) << p.axis | (o & 1) << u | (o >> 1 & 1) << v;
      q.other = child(p.other, bits);
      q.lower[u] += static_cast<std::uint32_t>(o & 1) << half;
      q.lower[v] += static_cast<std::uint32_t>(o >> 1 & 1) << half;
      pieces(q, visit);
    }
  }

  // A piece's samples, counter-clockwise seen from outside its leaf (as mc_tables walks a
  // face): its corners and the points where finer leaves split its sides.
  void samples(const Piece& p, std::vector<Index>& out) const {
    static constexpr int kWalk[2][4][2] = {{{0, 0}, {0, 1}, {1, 1}, {1, 0}},
                                           {{0, 0}, {1, 0}, {1, 1}, {0, 1}}};
    const int u = (p.axis + 1) % 3, v = (p.axis + 2) % 3;
    const std::uint32_t size = 1u << (kMaxLevel - p.level);
    out.clear();
    for (int k = 0; k < 4; ++k) {
      const int* from = kWalk[p.side][k];
      const int* to = kWalk[p.side][(k + 1) % 4];
      Index a = p.lower;
      a[u] += from[0] * size;
      a[v] += from[1] * size;
      out.push_back(a);
      const int along = from[0] != to[0] ? u : v;
      const bool up = from[0] + from[1] < to[0] + to[1];
      Index lo = a;
      if (!up) lo[along] -= size;
      const std::size_t first = out.size();
      segment_points(along, p.level, lo, out);
      if (!up) std::reverse(out.begin() + static_cast<std::ptrdiff_t>(first), out.end());
    }
  }

  // A piece's segments as links from each entering point to its exiting one (mc_tables.cpp,
  // step 1): on a plain square with four crossings the asymptotic decider of mc_case_key,
  // elsewhere the inside runs are cut off (a tie counts as separated there too).
  void link(const Piece& p, std::vector<Index>& walk,
            std::vector<std::pair<std::uint32_t, std::uint32_t>>& links, SolidLevelSet& out) {
    samples(p, walk);
    const std::size_t n = walk.size();
    point_.clear(), entering_.clear();
    for (std::size_t k = 0; k < n; ++k) {
      const Index& a = walk[k];
      const Index& b = walk[(k + 1) % n];
      const bool in_a = sample(a).f < 0, in_b = sample(b).f < 0;
      if (in_a == in_b) continue;
      int axis = 0;
      while (a[axis] == b[axis]) ++axis;
      point_.push_back(a[axis] < b[axis] ? vertex(axis, a, b, out) : vertex(axis, b, a, out));
      entering_.push_back(in_b);
    }
    const std::size_t count = point_.size();
    bool connected = false;
    if (n == 4 && count == 4) {
      double d[4];
      for (int k = 0; k < 4; ++k) d[k] = static_cast<float>(sample(walk[k]).f);
      const bool first_inside = sample(walk[0]).f < 0;
      connected =
          (first_inside ? d[0] * d[2] : d[1] * d[3]) > (first_inside ? d[1] * d[3] : d[0] * d[2]);
    }
    for (std::size_t k = 0; k < count; ++k)
      if (entering_[k])
        links.push_back({point_[k], point_[connected ? (k + count - 1) % count : (k + 1) % count]});
  }

  // The links of a leaf close into loops (each point enters one piece and leaves another),
  // each a disk (clip_ears).
  void triangulate(const Cell& c, std::vector<std::pair<std::uint32_t, std::uint32_t>>& links,
                   std::vector<std::uint32_t>& loop, SolidLevelSet& out) {
    std::sort(links.begin(), links.end());
    std::vector<bool> used(links.size());
    for (std::size_t start = 0; start < links.size(); ++start) {
      if (used[start]) continue;
      loop.clear();
      for (std::size_t at = start; !used[at];) {
        used[at] = true;
        loop.push_back(links[at].first);
        const auto found = std::lower_bound(links.begin(), links.end(),
                                            std::pair{links[at].second, std::uint32_t{0}});
        if (found == links.end() || found->first != links[at].second) break;
        at = static_cast<std::size_t>(found - links.begin());
      }
      disk(c, loop, out);
    }
  }

  // One loop of a leaf as a disk: three points one triangle, more their ears (clip_ears),
  // or where no ear is clear, a fan from their centroid moved onto the level set.
  void disk(const Cell& c, const std::vector<std::uint32_t>& loop, SolidLevelSet& out) {
    const std::size_t n = loop.size();
    if (n < 3) return;
    if (n == 3) {
      out.triangles.push_back({loop[0], loop[1], loop[2]});
      return;
    }
    if (clip_ears(loop, out)) return;
    std::array<double, 3> mean{};
    for (std::uint32_t v : loop)
      for (int a = 0; a < 3; ++a) mean[a] += out.uvw[v][a] / static_cast<double>(n);
    const auto centre = static_cast<std::uint32_t>(out.points.size());
    add_point(project(mean, c), out);
    for (std::size_t k = 0; k < n; ++k)
      out.triangles.push_back({loop[k], loop[(k + 1) % n], centre});
  }

  // A loop of four or more points as n − 2 triangles cut off as ears in the plane of its
  // mapped points (a slice's own plane), each the loop's way round, with no other point in or
  // on it, and each the best shaped ear left: no triangle turns over unless the loop does (G
  // folds). The table's fans from a centroid turned slivers over where a coarse leaf's loop
  // bends (one of 10,097 in a fitted blob's section; 4 of bear's 40 % section where det J_G
  // > 0 at every corner). False where no ear is clear of rounding; the caller fans then.
  bool clip_ears(const std::vector<std::uint32_t>& loop, SolidLevelSet& out) {
    const std::size_t n = loop.size();
    const Vec3 o = out.points[loop[0]];
    Vec3 normal{};
    for (std::size_t k = 0; k < n; ++k)
      normal = normal + cross(out.points[loop[k]] - o, out.points[loop[(k + 1) % n]] - o);
    if (component_ == 2) normal = {0, 0, normal.z};  // a slice's triangles turn in its plane
    const double twice_area = norm(normal);
    if (!(twice_area > 0)) return false;
    normal = (1 / twice_area) * normal;
    Vec3 e1 = cross(normal, std::abs(normal.x) < 0.5 ? Vec3{1, 0, 0} : Vec3{0, 1, 0});
    e1 = (1 / norm(e1)) * e1;
    const Vec3 e2 = cross(normal, e1);  // e1 × e2 = normal
    flat_.resize(n);
    ring_.resize(n);
    // A slice's loop is flat in its plane: its own x and y (y mirrored where the loop runs
    // clockwise), so that its ears' signs are decided exactly, the nearly straight runs of a
    // leaf's chords included (a fan's centre off such a run's kernel turned 2 of bear's
    // triangles over). Another level set's loop is bent: projected, its signs to rounding.
    const bool exact = component_ == 2;
    for (std::size_t k = 0; k < n; ++k) {
      const Vec3 p = out.points[loop[k]], d = p - o;
      flat_[k] = exact ? Vec2{p.x, normal.z > 0 ? p.y : -p.y} : Vec2{dot(d, e1), dot(d, e2)};
      ring_[k] = static_cast<std::uint32_t>(k);
    }
    auto turn = [&](std::uint32_t a, std::uint32_t b, std::uint32_t c) {
      const Vec2 p = flat_[a], q = flat_[b], r = flat_[c];
      return (q.x - p.x) * (r.y - p.y) - (r.x - p.x) * (q.y - p.y);
    };
    auto sign = [&](std::uint32_t a, std::uint32_t b, std::uint32_t c) {
      const Vec2 p = flat_[a], q = flat_[b], r = flat_[c];
      return detail::orientation_2({p.x, p.y}, {q.x, q.y}, {r.x, r.y});
    };
    auto length2 = [&](std::uint32_t a, std::uint32_t b) {
      const Vec2 d{flat_[b].x - flat_[a].x, flat_[b].y - flat_[a].y};
      return d.x * d.x + d.y * d.y;
    };
    const double least = 1e-12 * twice_area;
    const std::size_t first = out.triangles.size();
    auto same = [&](std::uint32_t a, std::uint32_t b) {
      return flat_[a].x == flat_[b].x && flat_[a].y == flat_[b].y;
    };
    while (ring_.size() > 2) {
      const std::size_t m = ring_.size();
      std::size_t best = m;
      double best_shape = -1;
      for (std::size_t i = 0; i < m && best_shape < kFlat; ++i) {
        const std::uint32_t a = ring_[(i + m - 1) % m], b = ring_[i], c = ring_[(i + 1) % m];
        // Where a layer runs along a grid plane, crossings land on its corners and two points
        // of a loop can coincide: that flat ear (area exactly 0) goes first.
        if (same(a, b) || same(b, c)) {
          best = i, best_shape = kFlat;
          continue;
        }
        const double area = turn(a, b, c);
        if (exact ? sign(a, b, c) <= 0 : !(area > least)) continue;
        bool clear = true;
        for (std::size_t j = 0; j < m && clear && m > 3; ++j) {
          const std::uint32_t r = ring_[j];
          if (r == a || r == b || r == c || same(r, a) || same(r, b) || same(r, c)) continue;
          clear = exact ? !(sign(a, b, r) >= 0 && sign(b, c, r) >= 0 && sign(c, a, r) >= 0)
                        : !(turn(a, b, r) >= 0 && turn(b, c, r) >= 0 && turn(c, a, r) >= 0);
        }
        const double shape = std::max(0.0, area / (length2(a, b) + length2(b, c) + length2(c, a)));
        if (clear && shape > best_shape) best = i, best_shape = shape;
      }
      if (best == m) {
        out.triangles.resize(first);
        return false;
      }
      out.triangles.push_back(
          {loop[ring_[(best + m - 1) % m]], loop[ring_[best]], loop[ring_[(best + 1) % m]]});
      ring_.erase(ring_.begin() + static_cast<std::ptrdiff_t>(best));
    }
    return true;
  }

  // The point where f = 0 on the segment a → b (a below b on `axis`), found once per segment:
  // both leaves along it, of any levels, share it by the segment's key.
  std::uint32_t vertex(int axis, const Index& a, const Index& b, SolidLevelSet& out) {
    const int level = kMaxLevel - __builtin_ctz(b[axis] - a[axis]);
    const std::uint64_t key = std::uint64_t(axis) << 56 | std::uint64_t(level) << 51 |
                              std::uint64_t(a[2]) << 34 | std::uint64_t(a[1]) << 17 | a[0];
    const auto [at, fresh] = vertices_.emplace(key, static_cast<std::uint32_t>(out.points.size()));
    if (fresh) add_crossing(uvw(a), uvw(b), sample(a), sample(b), out);
    return at->second;
  }

  // The leaf of the tree that holds `c` (no finer than c).
  Cell leaf_at(const Cell& c) const {
    Cell at{options_.initial_level, {}};
    for (;;) {
      const int s = c.level - at.level;
      at.index = {c.index[0] >> s, c.index[1] >> s, c.index[2] >> s};
      if (s == 0 || !split_.count(cell_key(at.level, at.index))) return at;
      ++at.level;
    }
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
    double ft = scalar_at(at(t));
    int side = 0;
    for (int it = 0; it < 40 && std::abs(ft) > tolerance; ++it) {
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
      ft = scalar_at(at(t));
    }
    add_point(at(t), out);
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
    const SolidPoint p = point_at(uvw);
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
  int level_ = 0;                              // the deepest leaf's
  int deepest_ = 0;                            // the deepest level τ asked for (cells())
  std::vector<std::uint32_t> cell_triangles_;  // per leaf extracted, its first triangle
  std::size_t evaluations_ = 0;
  std::vector<Range> ranges_;
  std::vector<double> local_;  // per element, f + value's 64 local B-spline coefficients
  std::unordered_map<std::uint64_t, Range> node_range_;
  std::unordered_map<std::uint64_t, Corner> corners_;
  std::unordered_set<std::uint64_t> split_;  // cells of the tree that have children
  std::unordered_map<std::uint64_t, std::uint32_t> vertices_;  // by segment
  std::vector<std::uint32_t> point_;                           // a piece's crossings, in walk order
  std::vector<bool> entering_;
  std::vector<Vec2> flat_;  // a loop's points in its plane
  std::vector<std::uint32_t> ring_;
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
  section.mesh = finder.extract_section(finder.cells(tau));
  for (Vec3& p : section.mesh.points) p.z = z;  // on the plane (edge points are, to 1e-9)
  // What splitting left turned over (none on bear's or fandisk's stacks) is mended in the
  // plane by edge flips, which keep the section's winding everywhere.
  detail::flip_turned_triangles(section.mesh.points, section.mesh.triangles);
  std::vector<std::vector<Vec2>> turned;  // the turned-over triangles, reversed
  for (const auto& t : section.mesh.triangles) {
    const double area = plane_area(section.mesh, t);
    section.area += area;
    const Vec3 a = section.mesh.points[t[0]], b = section.mesh.points[t[1]],
               c = section.mesh.points[t[2]];
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
