// Trivariate B-spline: per-axis bases (core/bspline_basis.hpp), separable contractions, and the
// two fits.
#include "tpmsfill/scan/bspline.hpp"

#include <algorithm>
#include <cmath>
#include <string>

#include "core/bspline_basis.hpp"
#include "core/parallel.hpp"
#include "tpmsfill/error.hpp"

namespace tpmsfill {
namespace {

constexpr int kMaxDegree = 7;

// The non-zero basis functions of one parameter: B_first .. B_first+degree.
struct BasisRow {
  int first = 0;
  std::array<double, kMaxDegree + 1> value{}, derivative{};
};

int find_span(const std::vector<double>& knots, int degree, int count, double t) {
  if (t >= knots[count]) return count - 1;
  if (t <= knots[degree]) return degree;
  // The last span whose knot is <= t.
  const auto it = std::upper_bound(knots.begin() + degree, knots.begin() + count + 1, t);
  return static_cast<int>(it - knots.begin()) - 1;
}

BasisRow basis_row(const std::vector<double>& knots, int degree, int count, double t) {
  t = std::clamp(t, 0.0, 1.0);
  const int span = find_span(knots, degree, count, t);
  double ders[2][kMaxDegree + 1];
  detail::basis_derivatives([&knots](std::ptrdiff_t q) { return knots[q]; }, span, degree, t, 1,
                            ders);
  BasisRow row;
  row.first = span - degree;
  std::copy(ders[0], ders[0] + degree + 1, row.value.begin());
  std::copy(ders[1], ders[1] + degree + 1, row.derivative.begin());
  return row;
}

// The basis rows of one axis at the centres of `cells` cells.
std::vector<BasisRow> axis_rows(const BSplineVolume& v, int axis, int cells) {
  std::vector<BasisRow> rows(static_cast<std::size_t>(cells));
  for (int a = 0; a < cells; ++a)
    rows[a] = basis_row(v.knots[axis], v.degree, v.counts[axis], (a + 0.5) / cells);
  return rows;
}

std::size_t product(std::array<int, 3> d) {
  return static_cast<std::size_t>(d[0]) * static_cast<std::size_t>(d[1]) *
         static_cast<std::size_t>(d[2]);
}

// out = M ×_axis t: along `axis`, t's `dims[axis]` entries become rows.size() entries, entry
// a = Σ_r value[r] · t[first + r] (transpose: t's entries are scattered back instead).
std::vector<double> mode_banded(const std::vector<double>& t, std::array<int, 3> dims, int axis,
                                const std::vector<BasisRow>& rows, int degree, int out_size,
                                bool transpose) {
  std::array<int, 3> out_dims = dims;
  out_dims[axis] = out_size;
  std::vector<double> out(product(out_dims), 0.0);
  const std::size_t stride_in = axis == 0   ? 1
                                : axis == 1 ? dims[0]
                                            : std::size_t(dims[0]) * dims[1];
  const std::size_t stride_out = axis == 0   ? 1
                                 : axis == 1 ? out_dims[0]
                                             : std::size_t(out_dims[0]) * out_dims[1];
  // One line per combination of the other two indices.
  const int o1 = (axis + 1) % 3, o2 = (axis + 2) % 3;
  auto offset = [&](const std::array<int, 3>& d, int i1, int i2) {
    std::array<std::size_t, 3> idx{};
    idx[o1] = i1, idx[o2] = i2;
    return idx[0] + d[0] * (idx[1] + std::size_t(d[1]) * idx[2]);
  };
  detail::parallel_for(std::size_t(dims[o2]), 1, [&](std::size_t begin, std::size_t end) {
    for (std::size_t i2 = begin; i2 < end; ++i2)
      for (int i1 = 0; i1 < dims[o1]; ++i1) {
        const double* in = t.data() + offset(dims, i1, static_cast<int>(i2));
        double* o = out.data() + offset(out_dims, i1, static_cast<int>(i2));
        for (std::size_t a = 0; a < rows.size(); ++a) {
          const BasisRow& row = rows[a];
          if (!transpose) {
            double s = 0;
            for (int r = 0; r <= degree; ++r) s += row.value[r] * in[(row.first + r) * stride_in];
            o[a * stride_out] = s;
          } else {
            for (int r = 0; r <= degree; ++r)
              o[(row.first + r) * stride_out] += row.value[r] * in[a * stride_in];
          }
        }
      }
  });
  return out;
}

// A c: the volume at the sample points (three banded mode products).
std::vector<double> apply(const std::vector<double>& c, const BSplineVolume& v,
                          const std::array<std::vector<BasisRow>, 3>& rows) {
  std::vector<double> t = c;
  std::array<int, 3> d = v.counts;
  for (int axis = 0; axis < 3; ++axis) {
    t = mode_banded(t, d, axis, rows[axis], v.degree, static_cast<int>(rows[axis].size()), false);
    d[axis] = static_cast<int>(rows[axis].size());
  }
  return t;
}

// Aᵀ r: samples back onto coefficients.
std::vector<double> apply_transpose(const std::vector<double>& r, const BSplineVolume& v,
                                    const std::array<std::vector<BasisRow>, 3>& rows) {
  std::vector<double> t = r;
  std::array<int, 3> d{static_cast<int>(rows[0].size()), static_cast<int>(rows[1].size()),
                       static_cast<int>(rows[2].size())};
  for (int axis = 0; axis < 3; ++axis) {
    t = mode_banded(t, d, axis, rows[axis], v.degree, v.counts[axis], true);
    d[axis] = v.counts[axis];
  }
  return t;
}

// The banded Cholesky factor L of G = BᵀB + λ D₂ᵀD₂ for one axis (n × n, half-bandwidth
// b = max(degree, 2)): row i holds L[i][i − b .. i] in l[i·(b + 1) ..], diagonal last.
struct BandedFactor {
  int n = 0, b = 0;
  std::vector<double> l;
  double& at(int i, int j) { return l[std::size_t(i) * (b + 1) + (j - i + b)]; }
  double at(int i, int j) const { return l[std::size_t(i) * (b + 1) + (j - i + b)]; }

  // Solves G x = y in place on a strided line (forward, then backward substitution).
  void solve(double* y, std::size_t stride) const {
    for (int i = 0; i < n; ++i) {
      double s = y[i * stride];
      for (int k = std::max(0, i - b); k < i; ++k) s -= at(i, k) * y[k * stride];
      y[i * stride] = s / at(i, i);
    }
    for (int i = n - 1; i >= 0; --i) {
      double s = y[i * stride];
      for (int k = i + 1; k <= std::min(n - 1, i + b); ++k) s -= at(k, i) * y[k * stride];
      y[i * stride] = s / at(i, i);
    }
  }
};

BandedFactor axis_factor(const std::vector<BasisRow>& rows, int degree, int n, double smoothing) {
  BandedFactor f;
  f.n = n, f.b = std::max(degree, 2);
  f.l.assign(std::size_t(n) * (f.b + 1), 0.0);
  for (const BasisRow& row : rows)  // lower triangle of BᵀB
    for (int r = 0; r <= degree; ++r)
      for (int s = 0; s <= r; ++s)
        f.at(row.first + r, row.first + s) += row.value[r] * row.value[s];
  double trace = 0;
  for (int i = 0; i < n; ++i) trace += f.at(i, i);
  const double lambda = smoothing * trace / n;
  for (int i = 0; i + 2 < n; ++i) {  // D₂ row i: c_i − 2 c_{i+1} + c_{i+2}
    const double w[3] = {1, -2, 1};
    for (int r = 0; r < 3; ++r)
      for (int s = 0; s <= r; ++s) f.at(i + r, i + s) += lambda * w[r] * w[s];
  }
  for (int j = 0; j < n; ++j) {  // in place: G's lower band becomes L's
    double d = f.at(j, j);
    for (int k = std::max(0, j - f.b); k < j; ++k) d -= f.at(j, k) * f.at(j, k);
    if (!(d > 0))
      throw InputError(
          "the fit's normal equations are singular: fewer samples than "
          "coefficients along an axis, or a smoothing of 0 with too many");
    f.at(j, j) = std::sqrt(d);
    for (int i = j + 1; i <= std::min(n - 1, j + f.b); ++i) {
      double s = f.at(i, j);
      for (int k = std::max(0, i - f.b); k < j; ++k) s -= f.at(i, k) * f.at(j, k);
      f.at(i, j) = s / f.at(j, j);
    }
  }
  return f;
}

// Solves G c = t along every line of `axis` in place.
void solve_lines(std::vector<double>& t, std::array<int, 3> dims, int axis, const BandedFactor& f) {
  const std::size_t stride = axis == 0 ? 1 : axis == 1 ? dims[0] : std::size_t(dims[0]) * dims[1];
  const int o1 = (axis + 1) % 3, o2 = (axis + 2) % 3;
  detail::parallel_for(std::size_t(dims[o2]), 1, [&](std::size_t begin, std::size_t end) {
    for (std::size_t i2 = begin; i2 < end; ++i2)
      for (int i1 = 0; i1 < dims[o1]; ++i1) {
        std::array<std::size_t, 3> idx{};
        idx[o1] = i1, idx[o2] = i2;
        f.solve(t.data() + idx[0] + dims[0] * (idx[1] + std::size_t(dims[1]) * idx[2]), stride);
      }
  });
}

}  // namespace

std::vector<double> clamped_uniform_knots(int count, int degree) {
  if (degree < 1 || degree > kMaxDegree)
    throw InputError("the B-spline degree must be 1 to " + std::to_string(kMaxDegree));
  if (count <= degree)
    throw InputError("a B-spline of degree " + std::to_string(degree) + " needs more than " +
                     std::to_string(degree) + " coefficients per axis");
  std::vector<double> k(static_cast<std::size_t>(count + degree + 1));
  for (std::size_t q = 0; q < k.size(); ++q)
    k[q] = detail::clamped_uniform_knot(std::ptrdiff_t(q), degree, count - degree);
  return k;
}

BSplineVolume make_bspline_volume(std::array<int, 3> counts, int degree) {
  BSplineVolume v;
  v.degree = degree;
  v.counts = counts;
  for (int a = 0; a < 3; ++a) v.knots[a] = clamped_uniform_knots(counts[a], degree);
  v.coefficients.assign(product(counts), 0.0);
  return v;
}

double bspline_value(const BSplineVolume& v, double u, double w_, double z) {
  const BasisRow bu = basis_row(v.knots[0], v.degree, v.counts[0], u);
  const BasisRow bv = basis_row(v.knots[1], v.degree, v.counts[1], w_);
  const BasisRow bw = basis_row(v.knots[2], v.degree, v.counts[2], z);
  double s = 0;
  for (int k = 0; k <= v.degree; ++k)
    for (int j = 0; j <= v.degree; ++j)
      for (int i = 0; i <= v.degree; ++i)
        s += bu.value[i] * bv.value[j] * bw.value[k] *
             v.coefficients[(bu.first + i) +
                            std::size_t(v.counts[0]) *
                                ((bv.first + j) + std::size_t(v.counts[1]) * (bw.first + k))];
  return s;
}

std::array<double, 3> bspline_gradient(const BSplineVolume& v, double u, double w_, double z) {
  const BasisRow bu = basis_row(v.knots[0], v.degree, v.counts[0], u);
  const BasisRow bv = basis_row(v.knots[1], v.degree, v.counts[1], w_);
  const BasisRow bw = basis_row(v.knots[2], v.degree, v.counts[2], z);
  std::array<double, 3> g{};
  for (int k = 0; k <= v.degree; ++k)
    for (int j = 0; j <= v.degree; ++j)
      for (int i = 0; i <= v.degree; ++i) {
        const double c =
            v.coefficients[(bu.first + i) +
                           std::size_t(v.counts[0]) *
                               ((bv.first + j) + std::size_t(v.counts[1]) * (bw.first + k))];
        g[0] += bu.derivative[i] * bv.value[j] * bw.value[k] * c;
        g[1] += bu.value[i] * bv.derivative[j] * bw.value[k] * c;
        g[2] += bu.value[i] * bv.value[j] * bw.derivative[k] * c;
      }
  return g;
}

void bspline_line(const BSplineVolume& vol, const std::vector<double>& u, double v, double w,
                  double* value, std::array<double, 3>* gradient) {
  const int p = vol.degree, nu = vol.counts[0];
  const BasisRow bv = basis_row(vol.knots[1], p, vol.counts[1], v);
  const BasisRow bw = basis_row(vol.knots[2], p, vol.counts[2], w);
  // The coefficients contracted over j and k: C(·, v, w), ∂C/∂v(·, v, w), ∂C/∂w(·, v, w).
  std::vector<double> line(std::size_t(nu) * 3, 0.0);
  for (int k = 0; k <= p; ++k)
    for (int j = 0; j <= p; ++j) {
      const double* c =
          vol.coefficients.data() +
          std::size_t(nu) * ((bv.first + j) + std::size_t(vol.counts[1]) * (bw.first + k));
      const double a = bv.value[j] * bw.value[k], b = bv.derivative[j] * bw.value[k],
                   d = bv.value[j] * bw.derivative[k];
      for (int i = 0; i < nu; ++i) {
        line[3 * i] += a * c[i];
        line[3 * i + 1] += b * c[i];
        line[3 * i + 2] += d * c[i];
      }
    }
  for (std::size_t n = 0; n < u.size(); ++n) {
    const BasisRow bu = basis_row(vol.knots[0], p, nu, u[n]);
    double s = 0;
    std::array<double, 3> g{};
    for (int r = 0; r <= p; ++r) {
      const double* l = line.data() + 3 * std::size_t(bu.first + r);
      s += bu.value[r] * l[0];
      g[0] += bu.derivative[r] * l[0];
      g[1] += bu.value[r] * l[1];
      g[2] += bu.value[r] * l[2];
    }
    value[n] = s;
    if (gradient) gradient[n] = g;
  }
}

std::vector<double> evaluate_bspline_grid(const BSplineVolume& v, std::array<int, 3> dims) {
  const std::array<std::vector<BasisRow>, 3> rows{
      axis_rows(v, 0, dims[0]), axis_rows(v, 1, dims[1]), axis_rows(v, 2, dims[2])};
  return apply(v.coefficients, v, rows);
}

FitResult fit_bspline(const std::vector<double>& values, std::array<int, 3> dims,
                      std::array<int, 3> counts, const FitOptions& o) {
  if (values.size() != product(dims) || product(dims) == 0)
    throw InputError("the field's value count does not match its dimensions");
  for (int a = 0; a < 3; ++a)
    if (counts[a] > dims[a])
      throw InputError("more coefficients than samples along an axis: " +
                       std::to_string(counts[a]) + " > " + std::to_string(dims[a]));
  for (double x : values)
    if (!std::isfinite(x)) throw InputError("the field holds a value that is not finite");
  FitResult result;
  BSplineVolume& v = result.volume = make_bspline_volume(counts, o.degree);
  const std::array<std::vector<BasisRow>, 3> rows{
      axis_rows(v, 0, dims[0]), axis_rows(v, 1, dims[1]), axis_rows(v, 2, dims[2])};
  if (o.method == FitMethod::Direct) {
    std::vector<double> t = values;
    std::array<int, 3> d = dims;
    for (int axis = 0; axis < 3; ++axis) {
      // c = (BᵀB + λD₂ᵀD₂)⁻¹ Bᵀ x along this axis: a banded product, then banded solves.
      const BandedFactor f = axis_factor(rows[axis], v.degree, counts[axis], o.smoothing);
      t = mode_banded(t, d, axis, rows[axis], v.degree, counts[axis], true);
      d[axis] = counts[axis];
      solve_lines(t, d, axis, f);
    }
    v.coefficients = std::move(t);
  } else {
    // Start from the samples nearest the Greville points; step 0.99 · 2 / (c_u c_v c_w), c the
    // largest column sum of each axis's basis (Gershgorin bounds λ_max(AᵀA) by its product).
    double bound = 1;
    std::array<std::vector<int>, 3> nearest;
    for (int a = 0; a < 3; ++a) {
      std::vector<double> column(counts[a], 0.0);
      for (const BasisRow& r : rows[a])
        for (int k = 0; k <= v.degree; ++k) column[r.first + k] += r.value[k];
      bound *= *std::max_element(column.begin(), column.end());
      for (int i = 0; i < counts[a]; ++i) {
        double g = 0;
        for (int k = 1; k <= v.degree; ++k) g += v.knots[a][i + k];
        g /= v.degree;
        nearest[a].push_back(std::clamp(static_cast<int>(g * dims[a]), 0, dims[a] - 1));
      }
    }
    for (int k = 0; k < counts[2]; ++k)
      for (int j = 0; j < counts[1]; ++j)
        for (int i = 0; i < counts[0]; ++i)
          v.coefficients[i + std::size_t(counts[0]) * (j + std::size_t(counts[1]) * k)] =
              values[nearest[0][i] +
                     std::size_t(dims[0]) * (nearest[1][j] + std::size_t(dims[1]) * nearest[2][k])];
    const double mu = 0.99 * 2 / bound;
    double previous = INFINITY;
    for (int it = 0; it < o.max_iterations; ++it) {
      std::vector<double> r = apply(v.coefficients, v, rows);
      double loss = 0;
      for (std::size_t n = 0; n < r.size(); ++n) r[n] = values[n] - r[n], loss += r[n] * r[n];
      result.report.iterations = it + 1;
      if (std::isfinite(previous) && std::fabs(previous - loss) <= o.relative_change * previous)
        break;
      previous = loss;
      const std::vector<double> g = apply_transpose(r, v, rows);
      for (std::size_t n = 0; n < g.size(); ++n) v.coefficients[n] += mu * g[n];
    }
  }
  const std::vector<double> fitted = apply(v.coefficients, v, rows);
  double sum = 0;
  for (std::size_t n = 0; n < fitted.size(); ++n) {
    const double e = std::fabs(fitted[n] - values[n]);
    sum += e * e;
    result.report.max_error = std::max(result.report.max_error, e);
  }
  result.report.rms = std::sqrt(sum / static_cast<double>(fitted.size()));
  return result;
}

}  // namespace tpmsfill
