// Cubic THB splines on the cube octree, and the uniform tensor basis (thb_basis.hpp).
#include "tpmsfill/solid/thb_basis.hpp"

#include <algorithm>
#include <cmath>
#include <string>
#include <unordered_map>
#include <unordered_set>
#include <utility>

#include "core/bspline_basis.hpp"
#include "solid/internal/octree_cells.hpp"
#include "solid/internal/spline_terms.hpp"
#include "tpmsfill/error.hpp"

namespace tpmsfill {
namespace {

constexpr int kDegree = 3;

// Knot q of the clamped uniform cubic knots with `spans` spans: four 0s, s / spans, four 1s.
double knot(std::int64_t q, std::uint32_t spans) {
  return detail::clamped_uniform_knot(q, kDegree, spans);
}

std::vector<double> level_knots(std::uint32_t spans) {
  std::vector<double> knots(spans + 7);
  for (std::size_t q = 0; q < knots.size(); ++q) knots[q] = knot(std::int64_t(q), spans);
  return knots;
}

// The four B-splines of span `span` (knot span + 3 ≤ t < knot span + 4) at t, and their
// first `n` derivatives: ders[k][r] = kth derivative of B_{span + r}.
void basis_derivatives(std::uint32_t spans, std::uint32_t span, double t, int n,
                       double (&ders)[3][4]) {
  detail::basis_derivatives([spans](std::ptrdiff_t q) { return knot(q, spans); },
                            std::ptrdiff_t(span) + 3, kDegree, t, n, ders);
}

std::uint32_t span_of(double t, std::uint32_t spans) {
  const double x = std::floor(std::clamp(t, 0.0, 1.0) * spans);
  return static_cast<std::uint32_t>(std::clamp(x, 0.0, double(spans) - 1));
}

using detail::cell_key;
using detail::cell_less;

using Row = std::vector<std::pair<std::uint32_t, double>>;  // (function, weight), by function

// Per fine B-spline of level l + 1 (one axis), the level-l B-splines whose refinement holds
// it, with the weight: knot insertion (Boehm) of every midpoint, applied to the identity.
std::vector<Row> refinement(std::uint32_t coarse_spans) {
  std::vector<double> knots = level_knots(coarse_spans);
  const std::size_t coarse = coarse_spans + 3;
  std::vector<std::vector<double>> t(coarse, std::vector<double>(coarse, 0.0));
  for (std::size_t i = 0; i < coarse; ++i) t[i][i] = 1;
  for (std::uint32_t s = 0; s < coarse_spans; ++s) {
    const double x = (2.0 * s + 1) / (2.0 * coarse_spans);
    const std::size_t k = static_cast<std::size_t>(std::upper_bound(knots.begin(), knots.end(), x) -
                                                   knots.begin() - 1);
    std::vector<std::vector<double>> next(t.size() + 1);
    for (std::size_t i = 0; i < next.size(); ++i) {
      if (i + kDegree <= k) {
        next[i] = t[i];
      } else if (i > k) {
        next[i] = t[i - 1];
      } else {
        const double alpha = (x - knots[i]) / (knots[i + kDegree] - knots[i]);
        next[i].resize(coarse);
        for (std::size_t m = 0; m < coarse; ++m)
          next[i][m] = alpha * t[i][m] + (1 - alpha) * t[i - 1][m];
      }
    }
    t = std::move(next);
    knots.insert(knots.begin() + static_cast<std::ptrdiff_t>(k) + 1, x);
  }
  std::vector<Row> parents(t.size());
  for (std::size_t j = 0; j < t.size(); ++j)
    for (std::size_t m = 0; m < coarse; ++m)
      if (t[j][m] != 0) parents[j].emplace_back(static_cast<std::uint32_t>(m), t[j][m]);
  return parents;
}

// The dyadic hierarchy of a set of leaves: which cells of each level lie in Ω_level, which
// functions are in the basis, and every level-l B-spline as a combination of those.
class Hierarchy {
 public:
  explicit Hierarchy(const std::vector<OctreeCell>& leaves) {
    for (const OctreeCell& leaf : leaves) {
      top_ = std::max(top_, leaf.level);
      for (int l = leaf.level; l >= 0; --l) {
        const int shift = leaf.level - l;
        if (!nodes_
                 .insert(cell_key(
                     l, {leaf.index[0] >> shift, leaf.index[1] >> shift, leaf.index[2] >> shift}))
                 .second)
          break;  // its ancestors are in already
      }
    }
  }

  int top() const { return top_; }
  static std::uint32_t spans(int level) { return 1u << level; }

  // The level-l cells of B-spline (l, index)'s support all lie in Ω_l (`next`: in Ω_{l+1}).
  bool support_inside(int level, std::array<std::uint32_t, 3> index, bool next) const {
    if (level > top_ || (next && level + 1 > top_)) return false;
    const std::uint32_t last = spans(level) - 1;
    std::array<std::uint32_t, 3> lo{}, hi{};
    for (int a = 0; a < 3; ++a) {
      lo[a] = index[a] >= 3 ? index[a] - 3 : 0;
      hi[a] = std::min(index[a], last);
    }
    for (std::uint32_t k = lo[2]; k <= hi[2]; ++k)
      for (std::uint32_t j = lo[1]; j <= hi[1]; ++j)
        for (std::uint32_t i = lo[0]; i <= hi[0]; ++i) {
          const std::uint64_t key =
              next ? cell_key(level + 1, {2 * i, 2 * j, 2 * k}) : cell_key(level, {i, j, k});
          if (!nodes_.count(key)) return false;
        }
    return true;
  }

  bool active(int level, std::array<std::uint32_t, 3> index) const {
    return support_inside(level, index, false) && !support_inside(level, index, true);
  }

  void set_functions(const std::vector<SplineFunction>& functions) {
    for (std::uint32_t f = 0; f < functions.size(); ++f)
      function_id_.emplace(cell_key(functions[f].level, functions[f].index), f);
  }

  // A spline's coefficient on B-spline (level, index), as a combination of its coefficients on
  // the basis: the function's own when it is in the basis; refined from the coarser level when
  // its support leaves Ω_level. That is the truncation: inside Ω_level the coarser levels'
  // share is dropped. Memoised.
  const Row& expand(int level, std::array<std::uint32_t, 3> index) {
    const std::uint64_t key = cell_key(level, index);
    if (const auto found = memo_.find(key); found != memo_.end()) return found->second;
    Row row;
    if (support_inside(level, index, false)) {
      const auto id = function_id_.find(key);
      // Inside Ω_{l+1} too: a passive function, never reached from a leaf (see thb_basis).
      if (id == function_id_.end())
        throw InputError("the fine spline basis does not refine the coarse one");
      row.emplace_back(id->second, 1.0);
    } else {
      if (level == 0) throw InputError("the fine spline basis does not refine the coarse one");
      const std::array<const Row*, 3> parents = {&refinement_row(level, index[0]),
                                                 &refinement_row(level, index[1]),
                                                 &refinement_row(level, index[2])};
      for (const auto& [k, wk] : *parents[2])
        for (const auto& [j, wj] : *parents[1])
          for (const auto& [i, wi] : *parents[0]) {
            const Row& coarse = expand(level - 1, {i, j, k});
            for (const auto& [f, w] : coarse) row.emplace_back(f, wi * wj * wk * w);
          }
      std::sort(row.begin(), row.end(),
                [](const auto& a, const auto& b) { return a.first < b.first; });
      Row merged;
      for (const auto& entry : row)
        if (!merged.empty() && merged.back().first == entry.first)
          merged.back().second += entry.second;
        else
          merged.push_back(entry);
      row = std::move(merged);
    }
    return memo_.emplace(key, std::move(row)).first->second;
  }

 private:
  const Row& refinement_row(int fine_level, std::uint32_t fine_index) {
    while (static_cast<int>(refinements_.size()) < fine_level)
      refinements_.push_back(refinement(spans(static_cast<int>(refinements_.size()))));
    return refinements_[fine_level - 1][fine_index];
  }

  int top_ = 0;
  std::unordered_set<std::uint64_t> nodes_;
  std::unordered_map<std::uint64_t, std::uint32_t> function_id_;
  std::unordered_map<std::uint64_t, Row> memo_;
  std::vector<std::vector<Row>> refinements_;  // [l]: level l + 1 from level l
};

void check_tiling(const std::vector<OctreeCell>& leaves) {
  double volume = 0;
  for (const OctreeCell& c : leaves) {
    if (c.level < 0 || c.level > 16)
      throw InputError("an octree leaf has level " + std::to_string(c.level) + " (0 to 16)");
    for (std::uint32_t i : c.index)
      if (i >= (1u << c.level)) throw InputError("an octree leaf lies outside the cube");
    volume += std::ldexp(1.0, -3 * c.level);
  }
  if (leaves.empty() || std::abs(volume - 1) > 1e-12)
    throw InputError("the octree's leaves do not tile the cube");
}

}  // namespace

SplineBasis thb_basis(const CubeOctree& octree) {
  check_tiling(octree.leaves);
  SplineBasis basis;
  basis.elements = octree.leaves;
  std::sort(basis.elements.begin(), basis.elements.end(), cell_less);
  Hierarchy hierarchy(basis.elements);
  for (int l = 0; l <= hierarchy.top(); ++l) basis.spans.push_back(Hierarchy::spans(l));
  // An active function of level l is non-zero on a leaf of level l (its support meets
  // Ω_l \ Ω_{l+1}), so the candidates are the leaves' own B-splines.
  std::vector<std::uint64_t> candidates;
  candidates.reserve(basis.elements.size() * 8);
  for (const OctreeCell& e : basis.elements)
    for (std::uint32_t c = 0; c < 64; ++c)
      candidates.push_back(
          cell_key(e.level, {e.index[0] + c % 4, e.index[1] + c / 4 % 4, e.index[2] + c / 16}));
  std::sort(candidates.begin(), candidates.end());  // level, then k, j, i
  candidates.erase(std::unique(candidates.begin(), candidates.end()), candidates.end());
  for (std::uint64_t key : candidates) {
    const SplineFunction f{
        static_cast<int>(key >> 54),
        {static_cast<std::uint32_t>(key & 0x3ffff), static_cast<std::uint32_t>(key >> 18 & 0x3ffff),
         static_cast<std::uint32_t>(key >> 36 & 0x3ffff)}};
    if (hierarchy.active(f.level, f.index)) basis.functions.push_back(f);
  }
  hierarchy.set_functions(basis.functions);
  // One row per distinct B-spline of a leaf's level that is non-zero on a leaf.
  std::unordered_map<std::uint64_t, std::uint32_t> row_of;
  basis.row_start.push_back(0);
  for (const OctreeCell& e : basis.elements)
    for (std::uint32_t c = 0; c < 64; ++c) {
      const std::array<std::uint32_t, 3> index = {e.index[0] + c % 4, e.index[1] + c / 4 % 4,
                                                  e.index[2] + c / 16};
      const auto [at, fresh] = row_of.emplace(
          cell_key(e.level, index), static_cast<std::uint32_t>(basis.row_start.size() - 1));
      if (fresh) {
        for (const auto& [f, w] : hierarchy.expand(e.level, index)) {
          basis.row_function.push_back(f);
          basis.row_weight.push_back(w);
        }
        basis.row_start.push_back(static_cast<std::uint32_t>(basis.row_function.size()));
      }
      basis.element_rows.push_back(at->second);
    }
  return basis;
}

SplineBasis tensor_basis(int per_axis) {
  if (per_axis < 4 || per_axis > 1024)
    throw InputError("a uniform cubic spline needs 4 to 1024 control points per axis, not " +
                     std::to_string(per_axis));
  const std::uint32_t n = static_cast<std::uint32_t>(per_axis), spans = n - 3;
  SplineBasis basis;
  basis.kind = SplineKind::uniform;
  basis.spans = {spans};
  for (std::uint32_t k = 0; k < n; ++k)
    for (std::uint32_t j = 0; j < n; ++j)
      for (std::uint32_t i = 0; i < n; ++i) basis.functions.push_back({0, {i, j, k}});
  for (std::uint32_t k = 0; k < spans; ++k)
    for (std::uint32_t j = 0; j < spans; ++j)
      for (std::uint32_t i = 0; i < spans; ++i) {
        basis.elements.push_back({0, {i, j, k}});
        for (std::uint32_t c = 0; c < 64; ++c)
          basis.element_rows.push_back((i + c % 4) + n * ((j + c / 4 % 4) + n * (k + c / 16)));
      }
  for (std::uint32_t f = 0; f <= basis.functions.size(); ++f) basis.row_start.push_back(f);
  for (std::uint32_t f = 0; f < basis.functions.size(); ++f) {
    basis.row_function.push_back(f);
    basis.row_weight.push_back(1.0);
  }
  return basis;
}

std::vector<std::array<double, 3>> greville_points(const SplineBasis& basis) {
  std::vector<std::vector<double>> knots;
  for (std::uint32_t s : basis.spans) knots.push_back(level_knots(s));
  std::vector<std::array<double, 3>> points(basis.functions.size());
  if (basis.kind == SplineKind::tspline) {
    for (std::size_t f = 0; f < points.size(); ++f)
      for (int a = 0; a < 3; ++a)
        points[f][a] = (basis.knots[f][a][1] + basis.knots[f][a][2] + basis.knots[f][a][3]) / 3;
    return points;
  }
  for (std::size_t f = 0; f < points.size(); ++f) {
    const SplineFunction& fn = basis.functions[f];
    const std::vector<double>& u = knots[fn.level];
    for (int a = 0; a < 3; ++a)
      points[f][a] = (u[fn.index[a] + 1] + u[fn.index[a] + 2] + u[fn.index[a] + 3]) / 3;
  }
  return points;
}

std::size_t basis_element_at(const SplineBasis& basis, std::array<double, 3> uvw) {
  for (int level = 0; level < static_cast<int>(basis.spans.size()); ++level) {
    const std::uint32_t s = basis.spans[level];
    const OctreeCell cell{level, {span_of(uvw[0], s), span_of(uvw[1], s), span_of(uvw[2], s)}};
    const auto found =
        std::lower_bound(basis.elements.begin(), basis.elements.end(), cell, cell_less);
    if (found != basis.elements.end() && *found == cell)
      return static_cast<std::size_t>(found - basis.elements.begin());
  }
  throw InputError("the spline basis's elements do not tile the cube");
}

void detail::span_basis(std::uint32_t spans, std::uint32_t span, double t, int derivatives,
                        double (&ders)[3][4]) {
  tpmsfill::basis_derivatives(spans, span, t, std::clamp(derivatives, 0, 2), ders);
}

void detail::axis_basis(const SplineBasis& basis, std::size_t element, std::array<double, 3> uvw,
                        int derivatives, double (&axis)[3][3][4]) {
  const OctreeCell& e = basis.elements[element];
  for (int a = 0; a < 3; ++a)
    tpmsfill::basis_derivatives(basis.spans[e.level], e.index[a], uvw[a],
                                std::clamp(derivatives, 0, 2), axis[a]);
}

LocalBasis local_basis(const SplineBasis& basis, std::size_t element, std::array<double, 3> uvw,
                       int derivatives) {
  const int n = std::clamp(derivatives, 0, 2);
  double axis[3][3][4] = {};  // [axis][derivative][function]
  detail::axis_basis(basis, element, uvw, n, axis);
  LocalBasis local;
  for (int c = 0; c < 4; ++c)
    for (int b = 0; b < 4; ++b)
      for (int a = 0; a < 4; ++a) {
        const int at = a + 4 * b + 16 * c;
        const double u = axis[0][0][a], v = axis[1][0][b], w = axis[2][0][c];
        local.value[at] = u * v * w;
        if (n < 1) continue;
        const double du = axis[0][1][a], dv = axis[1][1][b], dw = axis[2][1][c];
        local.first[0][at] = du * v * w;
        local.first[1][at] = u * dv * w;
        local.first[2][at] = u * v * dw;
        if (n < 2) continue;
        local.second[0][at] = axis[0][2][a] * v * w;
        local.second[1][at] = u * axis[1][2][b] * w;
        local.second[2][at] = u * v * axis[2][2][c];
        local.second[3][at] = du * dv * w;
        local.second[4][at] = u * dv * dw;
        local.second[5][at] = du * v * dw;
      }
  return local;
}

void evaluate_spline(const SplineBasis& basis, const std::vector<double>& coefficients,
                     int dimension, std::array<double, 3> uvw, double* value, double* gradient) {
  const std::size_t e = basis_element_at(basis, uvw);
  const LocalBasis local = local_basis(basis, e, uvw, gradient ? 1 : 0);
  std::fill(value, value + dimension, 0.0);
  if (gradient) std::fill(gradient, gradient + 3 * dimension, 0.0);
  detail::for_each_term(basis, e, [&](int c, std::uint32_t f, double w) {
    const double* coefficient = coefficients.data() + std::size_t(f) * dimension;
    for (int d = 0; d < dimension; ++d) {
      value[d] += local.value[c] * w * coefficient[d];
      if (gradient)
        for (int a = 0; a < 3; ++a)
          gradient[a * dimension + d] += local.first[a][c] * w * coefficient[d];
    }
  });
}

std::vector<double> refine_coefficients(const SplineBasis& coarse, const SplineBasis& fine,
                                        const std::vector<double>& coefficients, int dimension) {
  if (coarse.kind == SplineKind::tspline || fine.kind == SplineKind::tspline)
    throw InputError("a T-spline basis need not hold a coarser spline: it cannot be refined");
  const bool dyadic =
      !coarse.spans.empty() && !fine.spans.empty() && coarse.spans[0] == 1 && fine.spans[0] == 1;
  if (!dyadic) {
    if (coarse.spans != fine.spans || coarse.functions.size() != fine.functions.size())
      throw InputError("the fine spline basis does not refine the coarse one");
    return coefficients;  // the same tensor basis
  }
  Hierarchy hierarchy(coarse.elements);
  hierarchy.set_functions(coarse.functions);
  std::vector<double> out(fine.functions.size() * std::size_t(dimension), 0.0);
  for (std::size_t f = 0; f < fine.functions.size(); ++f)
    for (const auto& [c, w] : hierarchy.expand(fine.functions[f].level, fine.functions[f].index))
      for (int d = 0; d < dimension; ++d)
        out[f * dimension + d] += w * coefficients[std::size_t(c) * dimension + d];
  return out;
}

}  // namespace tpmsfill
