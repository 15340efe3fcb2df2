/// @file fold_certificate.cpp
/// @brief certify_fold_free: det J_G's Bernstein coefficients per element, halved where they
/// do not decide (fold_certificate.hpp).
#include "tpmsfill/solid/fold_certificate.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include "core/parallel.hpp"
#include "solid/internal/det_grid.hpp"
#include "solid/internal/fit_system.hpp"
#include "tpmsfill/error.hpp"

namespace tpmsfill {
namespace {

constexpr int kDegree = 8;          // of det J_G along each axis
constexpr int kN = kDegree + 1;     // coefficients along an axis
constexpr int kBox = kN * kN * kN;  // coefficients of a box, i + 9 j + 81 k
constexpr double kPositive = 1e-9;  // of the element's largest coefficient
constexpr double kEighths[kN] = {0,       1.0 / 8, 2.0 / 8, 3.0 / 8, 4.0 / 8,
                                 5.0 / 8, 6.0 / 8, 7.0 / 8, 1};
constexpr detail::ElementGrid kEighthGrid{kEighths, 0, kN};

using Box = std::array<double, kBox>;
static_assert(FoldCertificateOptions{}.depth == detail::kCertificateDepth);

// The inverse of the collocation matrix B[i][j] = B⁸_j(i / 8): Bernstein coefficients from
// values at the eighths, along one axis.
struct Collocation {
  double inverse[kN][kN];

  Collocation() {
    double a[kN][2 * kN] = {};
    for (int i = 0; i < kN; ++i) {
      const double t = double(i) / kDegree;
      for (int j = 0; j < kN; ++j) {
        double binomial = 1;
        for (int m = 0; m < j; ++m) binomial = binomial * (kDegree - m) / (m + 1);
        a[i][j] = binomial * std::pow(t, j) * std::pow(1 - t, kDegree - j);
      }
      a[i][kN + i] = 1;
    }
    for (int col = 0; col < kN; ++col) {  // Gauss–Jordan with partial pivoting
      int pivot = col;
      for (int r = col + 1; r < kN; ++r)
        if (std::abs(a[r][col]) > std::abs(a[pivot][col])) pivot = r;
      for (int c = 0; c < 2 * kN; ++c) std::swap(a[col][c], a[pivot][c]);
      const double d = a[col][col];
      for (int c = 0; c < 2 * kN; ++c) a[col][c] /= d;
      for (int r = 0; r < kN; ++r)
        if (r != col && a[r][col] != 0) {
          const double f = a[r][col];
          for (int c = 0; c < 2 * kN; ++c) a[r][c] -= f * a[col][c];
        }
    }
    for (int i = 0; i < kN; ++i)
      for (int j = 0; j < kN; ++j) inverse[i][j] = a[i][kN + j];
  }
};

// Along `axis`, every line of 9 values of `in` multiplied by the collocation's inverse.
void to_bernstein(const Collocation& m, int axis, const Box& in, Box& out) {
  const int stride = axis == 0 ? 1 : axis == 1 ? kN : kN * kN;
  for (int p = 0; p < kBox; ++p) {
    const int g = p / stride % kN;  // p's place along the axis
    double sum = 0;
    for (int j = 0; j < kN; ++j) sum += m.inverse[g][j] * in[p + (j - g) * stride];
    out[p] = sum;
  }
}

// The box halved along `axis` by de Casteljau's rule at 1/2: the lower half into lo, the
// upper into hi.
void halve(const Box& b, int axis, Box& lo, Box& hi) {
  const int stride = axis == 0 ? 1 : axis == 1 ? kN : kN * kN;
  for (int p = 0; p < kBox; ++p) {
    if (p / stride % kN != 0) continue;  // each line once, from its first point
    double t[kN];
    for (int i = 0; i < kN; ++i) t[i] = b[p + i * stride];
    lo[p] = t[0];
    hi[p + kDegree * stride] = t[kDegree];
    for (int r = 1; r < kN; ++r) {
      for (int i = 0; i + r < kN; ++i) t[i] = (t[i] + t[i + 1]) / 2;
      lo[p + r * stride] = t[0];
      hi[p + (kDegree - r) * stride] = t[kDegree - r];
    }
  }
}

using Verdict = detail::ElementVerdict::Kind;

// What one element's box of coefficients shows, halving it up to `depth` times; `origin` and
// `size` place the box in the element (fractions), `fold` and `fold_det` the least corner
// seen (≤ 0 where the element folds).
struct BoxCheck {
  double floor;  // a coefficient above this is positive
  int depth;
  std::size_t boxes = 0;
  std::array<double, 3> fold{};
  double fold_det = std::numeric_limits<double>::infinity();
  std::vector<std::array<Box, 14>> scratch = std::vector<std::array<Box, 14>>(depth + 1);

  Verdict check(const Box& b, std::array<double, 3> origin, double size, int level) {
    ++boxes;
    // The corners' coefficients are det J_G at the corners.
    bool corner_folds = false;
    for (int c = 0; c < 8; ++c) {
      const int i = (c & 1) * kDegree, j = (c >> 1 & 1) * kDegree, k = (c >> 2) * kDegree;
      const double det = b[i + kN * j + kN * kN * k];
      corner_folds = corner_folds || det <= 0;
      if (det < fold_det)
        fold_det = det, fold = {origin[0] + (c & 1) * size, origin[1] + (c >> 1 & 1) * size,
                                origin[2] + (c >> 2) * size};
    }
    if (corner_folds) return Verdict::folded;
    if (*std::min_element(b.begin(), b.end()) > floor) return Verdict::proven;
    if (level == depth) return Verdict::undecided;
    Box* half = &scratch[level][0];  // 2, then quarters 4, then eighths 8
    Box* quarter = half + 2;
    Box* eighth = quarter + 4;
    halve(b, 0, half[0], half[1]);
    for (int h = 0; h < 2; ++h) halve(half[h], 1, quarter[2 * h], quarter[2 * h + 1]);
    for (int q = 0; q < 4; ++q) halve(quarter[q], 2, eighth[2 * q], eighth[2 * q + 1]);
    Verdict verdict = Verdict::proven;
    for (int q = 0; q < 4; ++q)
      for (int w = 0; w < 2; ++w) {
        // quarter q = 2 (u half) + (v half); eighth 2 q + w
        const int u = q >> 1, v = q & 1;
        const double s = size / 2;
        const Verdict child =
            check(eighth[2 * q + w], {origin[0] + u * s, origin[1] + v * s, origin[2] + w * s}, s,
                  level + 1);
        if (child == Verdict::folded) return Verdict::folded;
        if (child == Verdict::undecided) verdict = Verdict::undecided;
      }
    return verdict;
  }
};

}  // namespace

std::vector<detail::ElementVerdict> detail::element_verdicts(const SplineBasis& basis,
                                                             const std::vector<double>& rows,
                                                             int depth) {
  const SpanTable axes(basis, kEighths, kN);
  static const Collocation collocation;
  std::vector<ElementVerdict> verdicts(basis.elements.size());
  parallel_for(verdicts.size(), 16, [&](std::size_t begin, std::size_t end) {
    Box values, along_u, along_v, coefficients;
    std::array<double, 64 * 3> local;
    BoxCheck check{0, std::max(depth, 0)};
    for (std::size_t e = begin; e < end; ++e) {
      for (int k = 0; k < 64; ++k)
        for (int d = 0; d < 3; ++d)
          local[3 * k + d] = rows[std::size_t(basis.element_rows[64 * e + k]) * 3 + d];
      grid_determinants(basis, axes, e, local.data(), kEighthGrid,
                        [&](int p, double det) { values[p] = det; });
      const OctreeCell& cell = basis.elements[e];
      ElementVerdict& v = verdicts[e];
      const int least = int(std::min_element(values.begin(), values.end()) - values.begin());
      if (values[least] <= 0) {  // a fold at a grid point: found, no bound needed
        v = {Verdict::folded, kEighthGrid.point(cell, basis.spans, least), values[least], 1};
        continue;
      }
      to_bernstein(collocation, 0, values, along_u);
      to_bernstein(collocation, 1, along_u, along_v);
      to_bernstein(collocation, 2, along_v, coefficients);
      double largest = 0;
      for (double b : coefficients) largest = std::max(largest, std::abs(b));
      check.floor = kPositive * largest;
      check.boxes = 0;
      check.fold_det = std::numeric_limits<double>::infinity();
      v.kind = check.check(coefficients, {0, 0, 0}, 1, 0);
      v.boxes = static_cast<std::uint32_t>(check.boxes);
      v.det = check.fold_det;
      const double h = 1.0 / basis.spans[cell.level];
      for (int a = 0; a < 3; ++a) v.uvw[a] = (cell.index[a] + check.fold[a]) * h;
    }
  });
  return verdicts;
}

FoldCertificate certify_fold_free(const SolidSpline& spline,
                                  const FoldCertificateOptions& options) {
  const SplineBasis& basis = spline.basis;
  if (spline.geometry.size() != basis.functions.size() || basis.elements.empty())
    throw InputError("the spline has no control points for its basis");
  std::vector<double> c;
  c.reserve(3 * spline.geometry.size());
  for (const Vec3& p : spline.geometry) c.insert(c.end(), {p.x, p.y, p.z});
  const std::vector<detail::ElementVerdict> verdicts =
      detail::element_verdicts(basis, detail::row_coefficients(basis, c, 3), options.depth);
  FoldCertificate certificate;
  certificate.elements = verdicts.size();
  double least = std::numeric_limits<double>::infinity();
  for (const detail::ElementVerdict& v : verdicts) {
    certificate.boxes += v.boxes;
    switch (v.kind) {
      case Verdict::proven:
        ++certificate.proven;
        break;
      case Verdict::undecided:
        ++certificate.undecided;
        break;
      case Verdict::folded:
        ++certificate.folded;
        if (v.det < least) least = v.det, certificate.fold = v.uvw, certificate.fold_det = v.det;
        break;
    }
  }
  return certificate;
}

}  // namespace tpmsfill
