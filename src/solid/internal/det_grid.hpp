/// @file det_grid.hpp
/// @brief det J_G on a grid of points of a spline element, by sum factorisation over the axes:
/// what the fit's fold watch (solid_spline.cpp) and the fold certificate
/// (fold_certificate.cpp) share.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "solid/internal/spline_terms.hpp"
#include "solid/internal/untangle.hpp"
#include "tpmsfill/solid/thb_basis.hpp"

namespace tpmsfill::detail {

/// n fractions of an element along each axis, from `first` in a list of them: the grid's
/// point p is (i, j, k) with p = i + n j + n² k.
struct ElementGrid {
  const double* fractions;
  int first, n;

  std::array<double, 3> point(const OctreeCell& cell, const std::vector<std::uint32_t>& spans,
                              int p) const {
    const int g[3] = {p % n, p / n % n, p / (n * n)};
    const double h = 1.0 / spans[cell.level];
    std::array<double, 3> uvw;
    for (int a = 0; a < 3; ++a) uvw[a] = (cell.index[a] + fractions[first + g[a]]) * h;
    return uvw;
  }
};

/// The four 1D cubic B-splines and their slopes at fixed fractions of every span of every
/// level: the same for a level's every element but the three at each end of an axis, so one
/// table of a few thousand values serves every grid of every element.
class SpanTable {
 public:
  SpanTable(const SplineBasis& basis, const double* fractions, int count)
      : count_(count), table_(basis.spans.size()) {
    for (std::size_t l = 0; l < basis.spans.size(); ++l) {
      const std::uint32_t spans = basis.spans[l];
      table_[l].resize(std::size_t(spans) * count * 8);
      for (std::uint32_t span = 0; span < spans; ++span)
        for (int f = 0; f < count; ++f) {
          double ders[3][4] = {};
          span_basis(spans, span, (span + fractions[f]) / spans, 1, ders);
          double* out = &table_[l][(std::size_t(span) * count + f) * 8];
          for (int k = 0; k < 4; ++k) out[k] = ders[0][k], out[4 + k] = ders[1][k];
        }
    }
  }
  /// The four values, then the four slopes.
  const double* at(int level, std::uint32_t span, int fraction) const {
    return &table_[level][(std::size_t(span) * count_ + fraction) * 8];
  }

 private:
  int count_;
  std::vector<std::vector<double>> table_;  // [level][(span · count + fraction) · 8 + k]
};

/// The largest grid grid_determinants() takes along an axis.
constexpr int kMaxGridPoints = 9;

/// visit(p, det J_G) at the points of a grid (n ≤ kMaxGridPoints) in element e, from its
/// local coefficients (64 × 3, local B-spline a + 4 b + 16 c) and a table holding the grid's
/// fractions: 4 × 4 products a fraction rather than 64 a point.
template <class Visit>
void grid_determinants(const SplineBasis& basis, const SpanTable& axes, std::size_t e,
                       const double* local, ElementGrid grid, const Visit& visit) {
  constexpr int kMax = kMaxGridPoints;
  const int n = grid.n;
  const OctreeCell& cell = basis.elements[e];
  const double* axis[3][kMax];
  for (int a = 0; a < 3; ++a)
    for (int i = 0; i < n; ++i) axis[a][i] = axes.at(cell.level, cell.index[a], grid.first + i);
  // Along u: p0 = Σ_a U(a) y, p1 = Σ_a U'(a) y, per (i, b + 4 c, r).
  double p0[kMax][16][3] = {}, p1[kMax][16][3] = {};
  for (int i = 0; i < n; ++i)
    for (int bc = 0; bc < 16; ++bc)
      for (int a = 0; a < 4; ++a)
        for (int r = 0; r < 3; ++r) {
          const double y = local[3 * (a + 4 * bc) + r];
          p0[i][bc][r] += axis[0][i][a] * y, p1[i][bc][r] += axis[0][i][4 + a] * y;
        }
  // Along v: G, ∂_u G and ∂_v G per (i, j, c, r).
  double q[kMax][kMax][4][3][3] = {};
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j)
      for (int c = 0; c < 4; ++c)
        for (int b = 0; b < 4; ++b) {
          const double v = axis[1][j][b], dv = axis[1][j][4 + b];
          for (int r = 0; r < 3; ++r) {
            q[i][j][c][0][r] += v * p0[i][b + 4 * c][r];
            q[i][j][c][1][r] += v * p1[i][b + 4 * c][r];
            q[i][j][c][2][r] += dv * p0[i][b + 4 * c][r];
          }
        }
  for (int k = 0; k < n; ++k)
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i) {
        Matrix3 jg{};
        for (int c = 0; c < 4; ++c) {
          const double w = axis[2][k][c], dw = axis[2][k][4 + c];
          for (int r = 0; r < 3; ++r) {
            jg[3 * r + 0] += w * q[i][j][c][1][r];
            jg[3 * r + 1] += w * q[i][j][c][2][r];
            jg[3 * r + 2] += dw * q[i][j][c][0][r];
          }
        }
        visit(i + n * j + n * n * k, determinant(jg));
      }
}

/// Per element, what det J_G's Bernstein bound shows (fold_certificate.hpp): proven positive,
/// folded (a point with det J_G ≤ 0 found), or undecided after `depth` halvings; uvw and det
/// are the least of the points seen (the 9³ grid, the boxes' corners), the fold's when folded.
struct ElementVerdict {
  enum class Kind : std::uint8_t { proven, folded, undecided } kind = Kind::proven;
  std::array<double, 3> uvw{};
  double det = 0;
  std::uint32_t boxes = 0;  ///< sub-boxes examined
};
/// The halvings certify_fold_free makes by default, and the fit's own bound.
constexpr int kCertificateDepth = 6;
std::vector<ElementVerdict> element_verdicts(const SplineBasis& basis,
                                             const std::vector<double>& rows, int depth);

}  // namespace tpmsfill::detail
