// The spline fit's linear algebra on the extraction rows (fit_system.hpp).
#include "solid/internal/fit_system.hpp"

#include <algorithm>
#include <cmath>
#include <utility>

#include "core/bspline_basis.hpp"
#include "core/parallel.hpp"

namespace tpmsfill::detail {

Gather make_gather(const SplineBasis& basis) {
  Gather g;
  const std::size_t rows = basis.row_start.size() - 1;
  g.row_start.assign(rows + 1, 0);
  for (std::uint32_t r : basis.element_rows) ++g.row_start[r + 1];
  for (std::size_t r = 0; r < rows; ++r) g.row_start[r + 1] += g.row_start[r];
  g.row_slot.resize(basis.element_rows.size());
  std::vector<std::uint32_t> fill(g.row_start.begin(), g.row_start.end() - 1);
  for (std::uint32_t s = 0; s < basis.element_rows.size(); ++s)
    g.row_slot[fill[basis.element_rows[s]]++] = s;
  g.function_start.assign(basis.functions.size() + 1, 0);
  for (std::uint32_t f : basis.row_function) ++g.function_start[f + 1];
  for (std::size_t f = 0; f < basis.functions.size(); ++f)
    g.function_start[f + 1] += g.function_start[f];
  g.function_row.resize(basis.row_function.size());
  g.function_weight.resize(basis.row_function.size());
  fill.assign(g.function_start.begin(), g.function_start.end() - 1);
  for (std::uint32_t r = 0; r < rows; ++r)
    for (std::uint32_t t = basis.row_start[r]; t < basis.row_start[r + 1]; ++t) {
      const std::uint32_t at = fill[basis.row_function[t]]++;
      g.function_row[at] = r;
      g.function_weight[at] = basis.row_weight[t];
    }
  return g;
}

std::vector<double> row_coefficients(const SplineBasis& basis, const std::vector<double>& c,
                                     int dim) {
  const std::size_t rows = basis.row_start.size() - 1;
  std::vector<double> out(rows * dim, 0.0);
  parallel_for(rows, 1024, [&](std::size_t begin, std::size_t end) {
    for (std::size_t r = begin; r < end; ++r)
      for (std::uint32_t t = basis.row_start[r]; t < basis.row_start[r + 1]; ++t)
        for (int d = 0; d < dim; ++d)
          out[r * dim + d] += basis.row_weight[t] * c[std::size_t(basis.row_function[t]) * dim + d];
  });
  return out;
}

std::vector<double> functions_from_rows(const SplineBasis& basis, const Gather& g,
                                        const std::vector<double>& rows, int dim) {
  std::vector<double> out(basis.functions.size() * dim, 0.0);
  parallel_for(basis.functions.size(), 1024, [&](std::size_t begin, std::size_t end) {
    for (std::size_t f = begin; f < end; ++f)
      for (std::uint32_t t = g.function_start[f]; t < g.function_start[f + 1]; ++t)
        for (int d = 0; d < dim; ++d)
          out[f * dim + d] += g.function_weight[t] * rows[std::size_t(g.function_row[t]) * dim + d];
  });
  return out;
}

std::vector<double> gather(const SplineBasis& basis, const Gather& g,
                           const std::vector<double>& slot_values, int dim) {
  const std::size_t rows = g.row_start.size() - 1;
  std::vector<double> row_sum(rows * dim, 0.0);
  parallel_for(rows, 1024, [&](std::size_t begin, std::size_t end) {
    for (std::size_t r = begin; r < end; ++r)
      for (std::uint32_t t = g.row_start[r]; t < g.row_start[r + 1]; ++t)
        for (int d = 0; d < dim; ++d)
          row_sum[r * dim + d] += slot_values[std::size_t(g.row_slot[t]) * dim + d];
  });
  return functions_from_rows(basis, g, row_sum, dim);
}

RowMatrix row_matrix(const SplineBasis& basis, const Gather& g) {
  const std::size_t rows = g.row_start.size() - 1;
  RowMatrix m;
  m.neighbour.assign(rows * kStencil, kNoRow);
  m.value.assign(rows * kStencil, 0.0);
  parallel_for(rows, 256, [&](std::size_t begin, std::size_t end) {
    for (std::size_t r = begin; r < end; ++r)
      for (std::uint32_t t = g.row_start[r]; t < g.row_start[r + 1]; ++t) {
        const std::uint32_t slot = g.row_slot[t], e = slot / 64;
        const int k = static_cast<int>(slot % 64);
        for (int l = 0; l < 64; ++l)
          m.neighbour[r * kStencil + stencil_slot(k, l)] = basis.element_rows[64 * e + l];
      }
  });
  return m;
}

namespace {

constexpr double kNode[3] = {0.11270166537925831, 0.5, 0.88729833462074169};
constexpr double kWeight[3] = {5.0 / 18, 8.0 / 18, 5.0 / 18};

// Per element and axis, ∫ N_a N_b, ∫ N'_a N'_b and ∫ N''_a N''_b over its span for its four
// B-splines along the axis, by the 3-point rule the fit's gradients use, so that the matrix is
// the Hessian of the energy those gradients differentiate.
struct AxisIntegrals {
  double m[3][3][4][4];  // [axis][derivative][a][b]
};

AxisIntegrals axis_integrals(const SplineBasis& basis, const OctreeCell& cell) {
  AxisIntegrals out{};
  const std::uint32_t spans = basis.spans[cell.level];
  const auto knot = [spans](std::ptrdiff_t q) { return clamped_uniform_knot(q, 3, spans); };
  for (int axis = 0; axis < 3; ++axis)
    for (int q = 0; q < 3; ++q) {
      double ders[3][4];
      const double t = (cell.index[axis] + kNode[q]) / spans;
      basis_derivatives(knot, std::ptrdiff_t(cell.index[axis]) + 3, 3, t, 2, ders);
      const double w = kWeight[q] / spans;
      for (int d = 0; d < 3; ++d)
        for (int a = 0; a < 4; ++a)
          for (int b = 0; b < 4; ++b) out.m[axis][d][a][b] += w * ders[d][a] * ders[d][b];
    }
  return out;
}

}  // namespace

void assemble_row_matrix(const SplineBasis& basis, const Gather& g, const ElementTerms& terms,
                         RowMatrix& matrix) {
  const std::size_t elements = basis.elements.size();
  std::vector<AxisIntegrals> axis(elements);
  parallel_for(elements, 64, [&](std::size_t begin, std::size_t end) {
    for (std::size_t e = begin; e < end; ++e) axis[e] = axis_integrals(basis, basis.elements[e]);
  });
  const std::size_t rows = g.row_start.size() - 1;
  parallel_for(rows, 64, [&](std::size_t begin, std::size_t end) {
    for (std::size_t r = begin; r < end; ++r) {
      double* value = matrix.value.data() + r * kStencil;
      std::fill(value, value + kStencil, 0.0);
      for (std::uint32_t t = g.row_start[r]; t < g.row_start[r + 1]; ++t) {
        const std::uint32_t slot = g.row_slot[t], e = slot / 64;
        const int k = static_cast<int>(slot % 64);
        for (std::uint32_t s = (*terms.sample_start)[e]; s < (*terms.sample_start)[e + 1]; ++s) {
          const double* phi = terms.sample_value->data() + std::size_t(s) * 64;
          const double a = (*terms.sample_weight)[s] * phi[k];
          if (a == 0) continue;
          for (int l = 0; l < 64; ++l) value[stencil_slot(k, l)] += a * phi[l];
        }
        const auto& m = axis[e].m;
        const std::array<double, 3> first = (*terms.first)[e];
        const double plate = terms.plate ? (*terms.plate)[e] : 0;
        const double mass = terms.mass ? (*terms.mass)[e] : 0;
        const int k0 = k & 3, k1 = k >> 2 & 3, k2 = k >> 4;
        for (int l = 0; l < 64; ++l) {
          const int l0 = l & 3, l1 = l >> 2 & 3, l2 = l >> 4;
          double v[3][3];  // [axis][derivative]
          for (int d = 0; d < 3; ++d) {
            v[0][d] = m[0][d][k0][l0];
            v[1][d] = m[1][d][k1][l1];
            v[2][d] = m[2][d][k2][l2];
          }
          double sum = first[0] * v[0][1] * v[1][0] * v[2][0] +
                       first[1] * v[0][0] * v[1][1] * v[2][0] +
                       first[2] * v[0][0] * v[1][0] * v[2][1];
          if (plate != 0)
            sum += plate * (v[0][2] * v[1][0] * v[2][0] + v[0][0] * v[1][2] * v[2][0] +
                            v[0][0] * v[1][0] * v[2][2] +
                            2 * (v[0][1] * v[1][1] * v[2][0] + v[0][0] * v[1][1] * v[2][1] +
                                 v[0][1] * v[1][0] * v[2][1]));
          if (mass != 0) sum += mass * v[0][0] * v[1][0] * v[2][0];
          value[stencil_slot(k, l)] += sum;
        }
      }
    }
  });
}

namespace {

// K y on the rows, `dim` values each.
std::vector<double> multiply_rows(const RowMatrix& matrix, const std::vector<double>& y, int dim) {
  const std::size_t rows = matrix.value.size() / kStencil;
  std::vector<double> out(rows * dim, 0.0);
  parallel_for(rows, 256, [&](std::size_t begin, std::size_t end) {
    for (std::size_t r = begin; r < end; ++r)
      for (int s = 0; s < kStencil; ++s) {
        const std::uint32_t n = matrix.neighbour[r * kStencil + s];
        if (n == kNoRow) continue;
        const double v = matrix.value[r * kStencil + s];
        for (int d = 0; d < dim; ++d) out[r * dim + d] += v * y[std::size_t(n) * dim + d];
      }
  });
  return out;
}

// Per component d, Σ_f a[f, d] b[f, d], summed in fixed chunks.
std::vector<double> dots(const std::vector<double>& a, const std::vector<double>& b, int dim) {
  std::vector<double> out(dim);
  const std::size_t n = a.size() / dim;
  for (int d = 0; d < dim; ++d)
    out[d] =
        deterministic_sum(n, 4096, [&](std::size_t f) { return a[f * dim + d] * b[f * dim + d]; });
  return out;
}

}  // namespace

SolveReport solve_conjugate_gradients(const SplineBasis& basis, const Gather& g,
                                      const RowMatrix& matrix, const std::vector<double>& b,
                                      int dim, double tolerance, int max_iterations,
                                      std::vector<double>& x,
                                      const std::function<void()>& each_iteration) {
  const std::size_t n = basis.functions.size();
  const auto apply = [&](const std::vector<double>& v) {
    return functions_from_rows(basis, g,
                               multiply_rows(matrix, row_coefficients(basis, v, dim), dim), dim);
  };
  // The diagonal of Tᵀ K T: per function, Σ over pairs of its rows of w w' K(row, row').
  // A coarse function truncated near finer leaves has hundreds of rows: its rows' weights by
  // row, sorted, are searched rather than compared pair by pair.
  std::vector<double> inverse_diagonal(n, 0.0);
  parallel_for(n, 64, [&](std::size_t begin, std::size_t end) {
    std::vector<std::pair<std::uint32_t, double>> own;
    for (std::size_t f = begin; f < end; ++f) {
      own.clear();
      for (std::uint32_t t = g.function_start[f]; t < g.function_start[f + 1]; ++t)
        own.emplace_back(g.function_row[t], g.function_weight[t]);
      std::sort(own.begin(), own.end());
      double sum = 0;
      for (const auto& [r, w] : own)
        for (int s = 0; s < kStencil; ++s) {
          const std::uint32_t other = matrix.neighbour[std::size_t(r) * kStencil + s];
          const auto at = std::lower_bound(own.begin(), own.end(), std::make_pair(other, -1e300));
          if (at != own.end() && at->first == other)
            sum += w * at->second * matrix.value[std::size_t(r) * kStencil + s];
        }
      inverse_diagonal[f] = sum > 0 ? 1 / sum : 0;
    }
  });
  x.assign(n * dim, 0.0);
  std::vector<double> r = b, z(n * dim), p(n * dim);
  for (std::size_t f = 0; f < n; ++f)
    for (int d = 0; d < dim; ++d) z[f * dim + d] = inverse_diagonal[f] * r[f * dim + d];
  p = z;
  std::vector<double> rz = dots(r, z, dim), bb = dots(b, b, dim);
  SolveReport report;
  std::vector<char> done(dim, 0);
  for (int it = 0; it < max_iterations; ++it) {
    if (each_iteration) each_iteration();
    const std::vector<double> rr = dots(r, r, dim);
    bool all = true;
    report.relative_residual = 0;
    for (int d = 0; d < dim; ++d) {
      const double relative = bb[d] > 0 ? std::sqrt(rr[d] / bb[d]) : 0;
      report.relative_residual = std::max(report.relative_residual, relative);
      done[d] = relative <= tolerance;
      all = all && done[d];
    }
    if (all) break;
    report.iterations = it + 1;
    const std::vector<double> q = apply(p);
    const std::vector<double> pq = dots(p, q, dim);
    std::vector<double> alpha(dim, 0.0);
    for (int d = 0; d < dim; ++d) alpha[d] = !done[d] && pq[d] > 0 ? rz[d] / pq[d] : 0;
    for (std::size_t f = 0; f < n; ++f)
      for (int d = 0; d < dim; ++d) {
        x[f * dim + d] += alpha[d] * p[f * dim + d];
        r[f * dim + d] -= alpha[d] * q[f * dim + d];
        z[f * dim + d] = inverse_diagonal[f] * r[f * dim + d];
      }
    const std::vector<double> next = dots(r, z, dim);
    for (int d = 0; d < dim; ++d) {
      const double beta = rz[d] > 0 ? next[d] / rz[d] : 0;
      for (std::size_t f = 0; f < n; ++f) p[f * dim + d] = z[f * dim + d] + beta * p[f * dim + d];
    }
    rz = next;
  }
  return report;
}

}  // namespace tpmsfill::detail
