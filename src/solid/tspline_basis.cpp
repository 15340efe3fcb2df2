// Cubic T-splines on the cube octree's T-mesh (tspline_basis.hpp).
#include "tpmsfill/solid/tspline_basis.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <set>
#include <string>
#include <tuple>
#include <unordered_map>
#include <unordered_set>
#include <utility>

#include "core/bspline_basis.hpp"
#include "core/parallel.hpp"
#include "solid/internal/octree_cells.hpp"
#include "tpmsfill/error.hpp"

namespace tpmsfill {
namespace {

constexpr int kMaxLevel = 16;
using Point = std::array<std::int64_t, 3>;  // a T-mesh vertex, in cells of the deepest level
using Knots = std::array<std::int64_t, 5>;  // one axis's local knots, in the same units

using detail::cell_key;
using detail::cell_less;
using detail::child_cell;

// The T-mesh: its leaves, looked up by the deepest level's cell they hold, and the inner
// nodes above them, for descents.
class TMesh {
 public:
  explicit TMesh(const std::vector<OctreeCell>& leaves) : leaves_(leaves) {
    double volume = 0;
    for (const OctreeCell& c : leaves_) {
      if (c.level < 0 || c.level > kMaxLevel)
        throw InputError("a T-mesh cell has level " + std::to_string(c.level) + " (0 to 16)");
      for (std::uint32_t i : c.index)
        if (i >= (1u << c.level)) throw InputError("a T-mesh cell lies outside the cube");
      volume += std::ldexp(1.0, -3 * c.level);
      deepest_ = std::max(deepest_, c.level);
    }
    if (leaves_.empty() || std::abs(volume - 1) > 1e-12)
      throw InputError("the T-mesh's cells do not tile the cube");
    size_ = std::int64_t{1} << deepest_;
    for (std::uint32_t i = 0; i < leaves_.size(); ++i) {
      leaf_.emplace(cell_key(leaves_[i].level, leaves_[i].index), i);
      levels_.insert(leaves_[i].level);
      for (int l = leaves_[i].level - 1; l >= 0; --l) {
        const int shift = leaves_[i].level - l;
        if (!inner_
                 .insert(cell_key(l, {leaves_[i].index[0] >> shift, leaves_[i].index[1] >> shift,
                                      leaves_[i].index[2] >> shift}))
                 .second)
          break;
      }
    }
  }

  int deepest() const { return deepest_; }
  std::int64_t size() const { return size_; }
  const std::vector<OctreeCell>& leaves() const { return leaves_; }

  // The cell's extent along `axis`, in the deepest level's cells.
  std::array<std::int64_t, 2> range(const OctreeCell& c, int axis) const {
    const std::int64_t s = std::int64_t{1} << (deepest_ - c.level);
    return {c.index[axis] * s, (c.index[axis] + 1) * s};
  }

  // The leaf holding the deepest level's cell v.
  std::uint32_t leaf_at(const Point& v) const {
    for (int l : levels_) {
      const int shift = deepest_ - l;
      const auto found =
          leaf_.find(cell_key(l, {std::uint32_t(v[0] >> shift), std::uint32_t(v[1] >> shift),
                                  std::uint32_t(v[2] >> shift)}));
      if (found != leaf_.end()) return found->second;
    }
    throw InputError("the T-mesh's cells do not tile the cube");
  }

  // The first T-mesh face normal to `axis` that the ray from vertex p crosses going `dir`
  // (±1): the nearest far face of the (up to four) cells around the ray's line there. A ray
  // at the cube's face stays there (the boundary knot repeats).
  std::int64_t next_face(const Point& p, int axis, int dir) const {
    if (dir > 0 ? p[axis] >= size_ : p[axis] <= 0) return p[axis];
    const int b = (axis + 1) % 3, c = (axis + 2) % 3;
    std::int64_t best = dir > 0 ? size_ : 0;
    for (int q = 0; q < 4; ++q) {
      Point v = p;
      v[axis] = dir > 0 ? p[axis] : p[axis] - 1;
      v[b] -= q & 1;
      v[c] -= q >> 1 & 1;
      if (v[b] < 0 || v[b] >= size_ || v[c] < 0 || v[c] >= size_) continue;
      const auto [lo, hi] = range(leaves_[leaf_at(v)], axis);
      best = dir > 0 ? std::min(best, hi) : std::max(best, lo);
    }
    return best;
  }

  // visit(leaf) for every leaf that meets the open box [lo, hi] (deepest-level units).
  template <class Visit>
  void leaves_in(const Point& lo, const Point& hi, const Visit& visit) const {
    descend({0, {0, 0, 0}}, lo, hi, visit);
  }

 private:
  template <class Visit>
  void descend(const OctreeCell& c, const Point& lo, const Point& hi, const Visit& visit) const {
    for (int a = 0; a < 3; ++a) {
      const auto [from, to] = range(c, a);
      if (to <= lo[a] || from >= hi[a]) return;
    }
    if (const auto found = leaf_.find(cell_key(c.level, c.index)); found != leaf_.end()) {
      visit(found->second);
      return;
    }
    if (!inner_.count(cell_key(c.level, c.index))) return;
    for (int o = 0; o < 8; ++o) descend(child_cell(c, o), lo, hi, visit);
  }

  std::vector<OctreeCell> leaves_;
  int deepest_ = 0;
  std::int64_t size_ = 1;
  std::unordered_map<std::uint64_t, std::uint32_t> leaf_;
  std::unordered_set<std::uint64_t> inner_;
  std::set<int> levels_;
};

// The blossom at (x1, x2, x3) of the polynomial piece, on the non-empty span [ξ_k, ξ_k+1],
// of the cubic B-spline with knots ξ_0..ξ_4: de Boor's algorithm on its unit coefficient,
// the rth step at x_r. Only d_j with 0 ≤ j ≤ r are non-zero at step r, and their α use
// ξ_0..ξ_4 alone, each over a knot interval that holds the span (so never 0).
double blossom(const std::array<double, 5>& xi, int k, const std::array<double, 3>& x) {
  double d[4] = {1, 0, 0, 0};
  for (int r = 1; r <= 3; ++r)
    for (int j = std::min(k, r); j >= std::max(k - 3 + r, 0); --j) {
      const double alpha = (x[r - 1] - xi[j]) / (xi[j + 4 - r] - xi[j]);
      d[j] = (1 - alpha) * (j > 0 ? d[j - 1] : 0.0) + alpha * d[j];
    }
  return d[k];
}

// A function's piece on span `span` of a level with `spans` spans, as its weights on the
// span's four local B-splines (the dual functionals: blossoms at their inner knots). The
// weights of a B-spline on a refinement of its knots lie in [0, 1]; round-off next to 0 or
// 1 is set to it, so that a function equal to a local B-spline has the one weight 1.
std::array<double, 4> span_weights(const std::array<double, 5>& xi, std::uint32_t spans,
                                   std::uint32_t span) {
  const double lo = double(span) / spans, hi = double(span + 1) / spans;
  int k = 0;
  while (k < 3 && !(xi[k] <= lo && hi <= xi[k + 1])) ++k;
  std::array<double, 4> w{};
  if (!(xi[k] <= lo && hi <= xi[k + 1])) return w;  // outside the support
  for (int r = 0; r < 4; ++r) {
    const std::ptrdiff_t j = std::ptrdiff_t(span) + r;
    std::array<double, 3> x{};
    for (int q = 0; q < 3; ++q) x[q] = detail::clamped_uniform_knot(j + 1 + q, 3, spans);
    double v = blossom(xi, k, x);
    if (std::abs(v) < 1e-13) v = 0;
    if (std::abs(v - 1) < 1e-13) v = 1;
    w[r] = v;
  }
  return w;
}

// Two runs of one knot vector: one starts inside the other and they agree where both are.
bool knots_overlap(const std::array<double, 5>& a, const std::array<double, 5>& b) {
  for (int s = 0; s < 4; ++s) {
    bool ab = true, ba = true;
    for (int i = 0; s + i < 5; ++i) {
      ab = ab && a[s + i] == b[i];
      ba = ba && b[s + i] == a[i];
    }
    if (ab || ba) return true;
  }
  return false;
}

struct Element {
  OctreeCell cell;
  std::vector<std::uint32_t> functions;  // those non-zero on it
};

}  // namespace

SplineBasis tspline_basis(const CubeOctree& octree) {
  const TMesh tmesh(octree.leaves);
  const std::int64_t size = tmesh.size();
  SplineBasis basis;
  basis.kind = SplineKind::tspline;
  basis.tmesh = tmesh.leaves();
  std::sort(basis.tmesh.begin(), basis.tmesh.end(), cell_less);
  // The anchors: every cell's corners, by w, v, u.
  std::vector<Point> anchors;
  for (const OctreeCell& c : basis.tmesh)
    for (int corner = 0; corner < 8; ++corner) {
      Point p{};
      for (int a = 0; a < 3; ++a) p[a] = tmesh.range(c, a)[corner >> a & 1];
      anchors.push_back(p);
    }
  std::sort(anchors.begin(), anchors.end(), [](const Point& a, const Point& b) {
    return std::tie(a[2], a[1], a[0]) < std::tie(b[2], b[1], b[0]);
  });
  anchors.erase(std::unique(anchors.begin(), anchors.end()), anchors.end());
  // Per anchor and axis its knot vectors (two on the cube's faces), then their products.
  std::vector<std::array<Knots, 3>> knots;
  for (const Point& p : anchors) {
    std::array<std::vector<Knots>, 3> axis;
    for (int a = 0; a < 3; ++a) {
      Point q = p;
      const std::int64_t up1 = tmesh.next_face(q, a, 1);
      q[a] = up1;
      const std::int64_t up2 = tmesh.next_face(q, a, 1);
      q[a] = p[a];
      const std::int64_t down1 = tmesh.next_face(q, a, -1);
      q[a] = down1;
      const std::int64_t down2 = tmesh.next_face(q, a, -1);
      axis[a].push_back({down2, down1, p[a], up1, up2});
      if (p[a] == 0) axis[a].push_back({0, 0, 0, 0, up1});
      if (p[a] == size) axis[a].push_back({down1, size, size, size, size});
    }
    for (const Knots& w : axis[2])
      for (const Knots& v : axis[1])
        for (const Knots& u : axis[0]) {
          knots.push_back({u, v, w});
          basis.functions.push_back(
              {tmesh.deepest(), {std::uint32_t(p[0]), std::uint32_t(p[1]), std::uint32_t(p[2])}});
        }
  }
  const std::size_t n = knots.size();
  basis.knots.resize(n);
  for (std::size_t f = 0; f < n; ++f)
    for (int a = 0; a < 3; ++a)
      for (int q = 0; q < 5; ++q) basis.knots[f][a][q] = double(knots[f][a][q]) / double(size);
  // Per T-mesh cell the functions non-zero on it.
  std::vector<std::vector<std::uint32_t>> on_cell(tmesh.leaves().size());
  for (std::uint32_t f = 0; f < n; ++f) {
    Point lo{}, hi{};
    for (int a = 0; a < 3; ++a) lo[a] = knots[f][a][0], hi[a] = knots[f][a][4];
    tmesh.leaves_in(lo, hi, [&](std::uint32_t leaf) { on_cell[leaf].push_back(f); });
  }
  // The elements: each cell split while a knot of one of its functions lies inside.
  std::vector<Element> elements;
  const auto split = [&](auto&& self, const OctreeCell& cell,
                         const std::vector<std::uint32_t>& functions) -> void {
    std::array<std::array<std::int64_t, 2>, 3> r{};
    for (int a = 0; a < 3; ++a) r[a] = tmesh.range(cell, a);
    std::vector<std::uint32_t> here;
    bool cut = false;
    for (std::uint32_t f : functions) {
      bool meets = true;
      for (int a = 0; a < 3; ++a)
        meets = meets && knots[f][a][0] < r[a][1] && knots[f][a][4] > r[a][0];
      if (!meets) continue;
      here.push_back(f);
      for (int a = 0; a < 3 && !cut; ++a)
        for (std::int64_t x : knots[f][a]) cut = cut || (x > r[a][0] && x < r[a][1]);
    }
    if (!cut) {
      elements.push_back({cell, std::move(here)});
      return;
    }
    for (int o = 0; o < 8; ++o) self(self, child_cell(cell, o), here);
  };
  for (std::uint32_t leaf = 0; leaf < tmesh.leaves().size(); ++leaf)
    split(split, tmesh.leaves()[leaf], on_cell[leaf]);
  std::sort(elements.begin(), elements.end(),
            [](const Element& a, const Element& b) { return cell_less(a.cell, b.cell); });
  int deepest = 0;
  for (const Element& e : elements) deepest = std::max(deepest, e.cell.level);
  for (int l = 0; l <= deepest; ++l) basis.spans.push_back(1u << l);
  // The rows: per element its 64 local B-splines' weights, rows of equal content shared;
  // made in parallel a block of elements at a time (a block's rows are what memory holds).
  using Row = std::vector<std::pair<std::uint32_t, double>>;
  std::unordered_map<std::string, std::uint32_t> row_of;
  basis.row_start.push_back(0);
  constexpr std::size_t kBlock = 4096;
  std::vector<std::array<Row, 64>> rows;
  for (std::size_t first = 0; first < elements.size(); first += kBlock) {
    const std::size_t last = std::min(elements.size(), first + kBlock);
    rows.assign(last - first, {});
    detail::parallel_for(last - first, 16, [&](std::size_t begin, std::size_t end) {
      for (std::size_t e = first + begin; e < first + end; ++e) {
        const OctreeCell& c = elements[e].cell;
        for (std::uint32_t f : elements[e].functions) {
          std::array<std::array<double, 4>, 3> w{};
          for (int a = 0; a < 3; ++a)
            w[a] = span_weights(basis.knots[f][a], basis.spans[c.level], c.index[a]);
          for (int k = 0; k < 64; ++k) {
            const double x = w[0][k % 4] * w[1][k / 4 % 4] * w[2][k / 16];
            if (x != 0) rows[e - first][k].emplace_back(f, x);
          }
        }
      }
    });
    for (std::size_t e = first; e < last; ++e) {
      basis.elements.push_back(elements[e].cell);
      for (const Row& row : rows[e - first]) {
        std::string key(row.size() * 12, '\0');  // packed: a pair has padding bytes
        for (std::size_t t = 0; t < row.size(); ++t) {
          std::memcpy(key.data() + 12 * t, &row[t].first, 4);
          std::memcpy(key.data() + 12 * t + 4, &row[t].second, 8);
        }
        const auto [at, fresh] =
            row_of.emplace(std::move(key), std::uint32_t(basis.row_start.size() - 1));
        if (fresh) {
          for (const auto& [f, w] : row) {
            basis.row_function.push_back(f);
            basis.row_weight.push_back(w);
          }
          basis.row_start.push_back(std::uint32_t(basis.row_function.size()));
        }
        basis.element_rows.push_back(at->second);
      }
    }
  }
  return basis;
}

TSplineCheck check_tspline(const SplineBasis& basis) {
  TSplineCheck check;
  const std::size_t elements = basis.elements.size();
  std::vector<double> unity(elements, 0);
  std::vector<std::array<double, 2>> sums(elements);
  std::vector<std::vector<std::pair<std::uint32_t, std::uint32_t>>> bad(elements), same(elements);
  detail::parallel_for(elements, 16, [&](std::size_t begin, std::size_t end) {
    for (std::size_t e = begin; e < end; ++e) {
      std::vector<std::uint32_t> functions;
      std::array<double, 64> row_sum{};
      for (int k = 0; k < 64; ++k) {
        const std::uint32_t row = basis.element_rows[64 * e + k];
        for (std::uint32_t t = basis.row_start[row]; t < basis.row_start[row + 1]; ++t) {
          row_sum[k] += basis.row_weight[t];
          functions.push_back(basis.row_function[t]);
        }
        unity[e] = std::max(unity[e], std::abs(row_sum[k] - 1));
      }
      // Σ φ itself at the element's corners, edges' and faces' middles and centre.
      const OctreeCell& cell = basis.elements[e];
      const double h = 1.0 / basis.spans[cell.level];
      sums[e] = {1e300, -1e300};
      for (int q = 0; q < 27; ++q) {
        const std::array<double, 3> uvw = {(cell.index[0] + 0.5 * (q % 3)) * h,
                                           (cell.index[1] + 0.5 * (q / 3 % 3)) * h,
                                           (cell.index[2] + 0.5 * (q / 9)) * h};
        const LocalBasis local = local_basis(basis, e, uvw, 0);
        double sum = 0;
        for (int k = 0; k < 64; ++k) sum += row_sum[k] * local.value[k];
        sums[e] = {std::min(sums[e][0], sum), std::max(sums[e][1], sum)};
      }
      std::sort(functions.begin(), functions.end());
      functions.erase(std::unique(functions.begin(), functions.end()), functions.end());
      for (std::size_t i = 0; i < functions.size(); ++i)
        for (std::size_t j = i + 1; j < functions.size(); ++j) {
          const auto& a = basis.knots[functions[i]];
          const auto& b = basis.knots[functions[j]];
          if (a == b) {
            same[e].emplace_back(functions[i], functions[j]);
            continue;
          }
          if (!knots_overlap(a[0], b[0]) && !knots_overlap(a[1], b[1]) &&
              !knots_overlap(a[2], b[2]))
            bad[e].emplace_back(functions[i], functions[j]);
        }
    }
  });
  // A pair meets on several elements: counted once; the T-mesh cells under its common support
  // (and under a sum off one) are the ones to split.
  std::vector<std::pair<std::uint32_t, std::uint32_t>> pairs, twins;
  std::vector<char> flagged(basis.tmesh.size(), 0);
  CubeOctree tmesh;
  tmesh.leaves = basis.tmesh;
  for (const OctreeCell& c : tmesh.leaves) tmesh.deepest = std::max(tmesh.deepest, c.level);
  check.sum_range = {1e300, -1e300};
  for (std::size_t e = 0; e < elements; ++e) {
    check.unity_error = std::max(check.unity_error, unity[e]);
    check.sum_range = {std::min(check.sum_range[0], sums[e][0]),
                       std::max(check.sum_range[1], sums[e][1])};
    pairs.insert(pairs.end(), bad[e].begin(), bad[e].end());
    twins.insert(twins.end(), same[e].begin(), same[e].end());
    if (unity[e] > 1e-12 || !bad[e].empty() || !same[e].empty()) {
      const OctreeCell& c = basis.elements[e];
      const double h = 1.0 / basis.spans[c.level];
      flagged[octree_leaf_at(
          tmesh, {(c.index[0] + 0.5) * h, (c.index[1] + 0.5) * h, (c.index[2] + 0.5) * h})] = 1;
    }
  }
  for (auto* list : {&pairs, &twins}) {
    std::sort(list->begin(), list->end());
    list->erase(std::unique(list->begin(), list->end()), list->end());
  }
  check.incompatible_pairs = pairs.size();
  check.duplicates = twins.size();
  for (std::size_t c = 0; c < flagged.size(); ++c)
    if (flagged[c]) check.cells.push_back(c);
  return check;
}

}  // namespace tpmsfill
