// Foldover-free maps (untangle.hpp): the regularised energy, its gradient, L-BFGS, and the
// schedule of ε.
#define EIGEN_NO_DEBUG 1  // Eigen's checks abort() rather than throw: leave them out
#include "solid/internal/untangle.hpp"

#include <algorithm>
#include <cmath>
#include <deque>
#include <limits>

#include "core/parallel.hpp"

#if defined(CGAL_EIGEN3_ENABLED)
#include <Eigen/Dense>
#include <Eigen/SparseCholesky>
#endif

namespace tpmsfill::detail {

// The volume term's share (the paper's θ). Small, so the untangled tets keep their shapes
// rather than even out their volumes: bear's fit from a map untangled with θ = 0.5 was 1.4
// times further from its points than from the harmonic map, with θ = 0.01 1.4 times closer
// (the harmonic map's inverted tets gone; docs/benchmarks.md §20).
constexpr double kTheta = 0.01;

double determinant(const Matrix3& a) {
  return a[0] * (a[4] * a[8] - a[5] * a[7]) - a[1] * (a[3] * a[8] - a[5] * a[6]) +
         a[2] * (a[3] * a[7] - a[4] * a[6]);
}

// Rows r1 × r2, r2 × r0, r0 × r1.
Matrix3 cofactor(const Matrix3& a) {
  Matrix3 c;
  for (int i = 0; i < 3; ++i) {
    const int j = (i + 1) % 3, k = (i + 2) % 3;
    c[3 * i + 0] = a[3 * j + 1] * a[3 * k + 2] - a[3 * j + 2] * a[3 * k + 1];
    c[3 * i + 1] = a[3 * j + 2] * a[3 * k + 0] - a[3 * j + 0] * a[3 * k + 2];
    c[3 * i + 2] = a[3 * j + 0] * a[3 * k + 1] - a[3 * j + 1] * a[3 * k + 0];
  }
  return c;
}

Matrix3 inverse(const Matrix3& a, double det) {
  const Matrix3 c = cofactor(a);
  Matrix3 out;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) out[3 * i + j] = c[3 * j + i] / det;
  return out;
}

double determinant(const Matrix2& a) {
  return a[0] * a[3] - a[1] * a[2];
}

Matrix2 cofactor(const Matrix2& a) {
  return {a[3], -a[2], -a[1], a[0]};
}

namespace {

// The density in D dimensions: (1 − θ) tr(JᵀJ) / χ^(2/D) + θ (det² + 1) / χ, and ∂f/∂J.
template <int D>
double simplex_density(const std::array<double, D * D>& j, double eps, double theta,
                       std::array<double, D * D>& derivative) {
  const std::array<double, D* D> c = cofactor(j);
  const double det = determinant(j);
  double trace = 0;
  for (double a : j) trace += a * a;
  const double root = std::sqrt(eps * eps + det * det);
  const double chi = 0.5 * (det + root);
  const double chi_d = root > 0 ? 0.5 * (1 + det / root) : 0.5;
  const double chi_scale = D == 3 ? std::cbrt(chi * chi) : chi;  // χ^(2/D)
  const double shape = trace / chi_scale, volume = (det * det + 1) / chi;
  for (int i = 0; i < D * D; ++i)
    derivative[i] = (1 - theta) * (2 * j[i] / chi_scale - (2.0 / D) * shape / chi * chi_d * c[i]) +
                    theta * (2 * det - volume * chi_d) / chi * c[i];
  return (1 - theta) * shape + theta * volume;
}

}  // namespace

Matrix2 inverse(const Matrix2& a, double det) {
  return {a[3] / det, -a[1] / det, -a[2] / det, a[0] / det};
}

double foldover_density(const Matrix3& j, double eps, Matrix3& derivative) {
  return simplex_density<3>(j, eps, kTheta, derivative);
}

namespace {

// The simplices (tets, or triangles flattened) with a movable corner: their corners, the
// inverse of their scaled shape R (its columns the edges from corner 0) and their share of
// the total measure. The same code serves the cube map's interior (D = 3) and its patches
// (D = 2): J = U R⁻¹ either way.
template <int D>
class SimplexEnergy final : public FoldoverEnergy {
 public:
  using Matrix = std::array<double, D * D>;
  using Point = std::array<double, D>;
  using Corners = std::array<std::uint32_t, D + 1>;

  // `shapes[i]` is simplex i's R (row-major); simplices whose R has no volume are left out.
  SimplexEnergy(const std::vector<Corners>& simplices, const std::vector<Matrix>& shapes,
                const std::vector<char>& movable, const std::vector<Point>& image, double theta)
      : image_(image), variable_(movable.size(), -1), theta_(theta) {
    for (std::size_t v = 0; v < movable.size(); ++v)
      if (movable[v]) variable_[v] = static_cast<std::int64_t>(points_++);
    double measure = 0;
    for (std::size_t i = 0; i < simplices.size(); ++i) {
      const Corners& t = simplices[i];
      if (std::none_of(t.begin(), t.end(), [&](std::uint32_t v) { return movable[v] != 0; }))
        continue;
      const double det = determinant(shapes[i]);
      if (!(det > 0)) continue;
      elements_.push_back({t, inverse(shapes[i], det), det});
      measure += det;
    }
    // The shapes scaled so that their total measure is their images' (a map that keeps
    // volume has det J = 1 on average): R⁻¹ scales by 1 / s, s^D = image measure / measure.
    double image_measure = 0;
    for (const Element& e : elements_) image_measure += determinant(image_edges(e, {}));
    const double ratio = std::max(image_measure, 1e-300) / std::max(measure, 1e-300);
    const double scale = D == 3 ? std::cbrt(ratio) : std::sqrt(ratio);
    for (Element& e : elements_) {
      for (double& x : e.inverse) x /= scale;
      e.weight /= measure;
    }
  }

  std::size_t variables() const { return D * points_; }
  bool empty() const { return elements_.empty() || points_ == 0; }

  std::vector<double> initial() const {
    std::vector<double> x(variables());
    for (std::size_t v = 0; v < variable_.size(); ++v)
      if (variable_[v] >= 0)
        for (int a = 0; a < D; ++a) x[D * variable_[v] + a] = image_[v][a];
    return x;
  }

  void write(const std::vector<double>& x, std::vector<Point>& image) const {
    for (std::size_t v = 0; v < variable_.size(); ++v)
      if (variable_[v] >= 0)
        for (int a = 0; a < D; ++a) image[v][a] = x[D * variable_[v] + a];
  }

  double min_det(const std::vector<double>& x) const override {
    double least = std::numeric_limits<double>::infinity();
    for (const Element& e : elements_) least = std::min(least, determinant(jacobian(e, x)));
    return least;
  }

  // E at x for this ε, and its gradient (the same order as x). Per element in parallel, summed
  // in element order, so the result does not depend on the thread count.
  double operator()(const std::vector<double>& x, double eps,
                    std::vector<double>& gradient) const override {
    std::vector<double> energy(elements_.size());
    std::vector<std::array<double, D*(D + 1)>> local(elements_.size());
    parallel_for(elements_.size(), 1024, [&](std::size_t begin, std::size_t end) {
      for (std::size_t i = begin; i < end; ++i) energy[i] = element(elements_[i], x, eps, local[i]);
    });
    gradient.assign(variables(), 0.0);
    double total = 0;
    for (std::size_t i = 0; i < elements_.size(); ++i) {
      total += energy[i];
      for (int k = 0; k <= D; ++k) {
        const std::int64_t v = variable_[elements_[i].corners[k]];
        if (v >= 0)
          for (int a = 0; a < D; ++a) gradient[D * v + a] += local[i][D * k + a];
      }
    }
    return total;
  }

  // Σ_T w_T Bᵀ [H_J]₊ B, B = ∂J/∂x and [H_J]₊ each density's Hessian in J made positive
  // semi-definite (projected Newton). f = (1 − θ) t χ^(−p) + θ (d² + 1) / χ, t = |J|²,
  // d = det J, χ = χ(d, ε), p = 2 / D = 1.
  // Only in the plane: in space the schedule of ε is what limits, not the steps (on the lower
  // femur's stand-in, 50 Newton steps an ε lowered ε 5 % a round, as L-BFGS's did, in 20 min).
  bool hessian(const std::vector<double>& x, double eps,
               std::vector<Entry>& entries) const override {
#if defined(CGAL_EIGEN3_ENABLED)
    if constexpr (D != 2) {
      (void)x, (void)eps, (void)entries;
      return false;
    } else {
      constexpr int N = D * D, M = D * (D + 1);
      constexpr double p = 2.0 / D;
      std::vector<Eigen::Matrix<double, M, M>> local(elements_.size());
      parallel_for(elements_.size(), 256, [&](std::size_t begin, std::size_t end) {
        for (std::size_t i = begin; i < end; ++i) {
          const Element& e = elements_[i];
          const Matrix j = jacobian(e, x), c = cofactor(j);
          const double d = determinant(j);
          double t = 0;
          for (double a : j) t += a * a;
          const double r = std::sqrt(eps * eps + d * d), chi = 0.5 * (d + r);
          const double chi_d = r > 0 ? 0.5 * (1 + d / r) : 0.5,
                       chi_dd = r > 0 ? eps * eps / (2 * r * r * r) : 0;
          const double cp = std::pow(chi, -p), g = (d * d + 1) / chi;
          const double f_t = (1 - theta_) * cp;
          const double f_d =
              -p * (1 - theta_) * t * cp / chi * chi_d + theta_ * (2 * d - g * chi_d) / chi;
          const double f_dd =
              (1 - theta_) * t * cp *
                  (p * (p + 1) * chi_d * chi_d / (chi * chi) - p * chi_dd / chi) +
              theta_ * (2 - 4 * d * chi_d / chi - g * chi_dd + 2 * g * chi_d * chi_d / chi) / chi;
          const double f_td = -p * (1 - theta_) * cp / chi * chi_d;
          Eigen::Matrix<double, N, 1> jv, cv;
          for (int k = 0; k < N; ++k) jv[k] = j[k], cv[k] = c[k];
          Eigen::Matrix<double, N, N> h = 2 * f_t * Eigen::Matrix<double, N, N>::Identity() +
                                          f_dd * cv * cv.transpose() +
                                          2 * f_td * (jv * cv.transpose() + cv * jv.transpose());
          // f_d ∂²d/∂J²: d = J00 J11 − J01 J10.
          h(0, 3) += f_d, h(3, 0) += f_d, h(1, 2) -= f_d, h(2, 1) -= f_d;
          const Eigen::SelfAdjointEigenSolver<Eigen::Matrix<double, N, N>> eigen(h);
          h = eigen.eigenvectors() * eigen.eigenvalues().cwiseMax(0).asDiagonal() *
              eigen.eigenvectors().transpose();
          // ∂J[r][c] / ∂(corner k's coordinate s) = δ_rs g_k[c]:
          // g_0 = −Σ_m R⁻¹[m], g_k = R⁻¹[k − 1].
          Eigen::Matrix<double, N, M> b = Eigen::Matrix<double, N, M>::Zero();
          for (int k = 0; k <= D; ++k)
            for (int col = 0; col < D; ++col) {
              double g_k = 0;
              if (k > 0) {
                g_k = e.inverse[D * (k - 1) + col];
              } else {
                for (int m = 0; m < D; ++m) g_k -= e.inverse[D * m + col];
              }
              for (int row = 0; row < D; ++row) b(D * row + col, D * k + row) = g_k;
            }
          local[i] = e.weight * b.transpose() * h * b;
        }
      });
      for (std::size_t i = 0; i < elements_.size(); ++i)
        for (int k = 0; k <= D; ++k)
          for (int l = 0; l <= D; ++l) {
            const std::int64_t vk = variable_[elements_[i].corners[k]];
            const std::int64_t vl = variable_[elements_[i].corners[l]];
            if (vk < 0 || vl < 0) continue;
            for (int r = 0; r < D; ++r)
              for (int s = 0; s < D; ++s)
                if (D * vl + s <= D * vk + r)
                  entries.push_back({D * vk + r, D * vl + s, local[i](D * k + r, D * l + s)});
          }
      return true;
    }
#else
    (void)x, (void)eps, (void)entries;
    return false;
#endif
  }

 private:
  struct Element {
    Corners corners;
    Matrix inverse;
    double weight;
  };

  Point at(std::uint32_t p, const std::vector<double>& x) const {
    const std::int64_t v = variable_[p];
    if (v < 0 || x.empty()) return image_[p];
    Point q;
    for (int a = 0; a < D; ++a) q[a] = x[D * v + a];
    return q;
  }

  // U: column k is corner k + 1's image less corner 0's.
  Matrix image_edges(const Element& e, const std::vector<double>& x) const {
    const Point p0 = at(e.corners[0], x);
    Matrix u;
    for (int k = 0; k < D; ++k) {
      const Point p = at(e.corners[k + 1], x);
      for (int r = 0; r < D; ++r) u[D * r + k] = p[r] - p0[r];
    }
    return u;
  }

  Matrix jacobian(const Element& e, const std::vector<double>& x) const {
    const Matrix u = image_edges(e, x);
    Matrix j{};
    for (int r = 0; r < D; ++r)
      for (int c = 0; c < D; ++c)
        for (int m = 0; m < D; ++m) j[D * r + c] += u[D * r + m] * e.inverse[D * m + c];
    return j;
  }

  // One element's energy, and its gradient by corner (∂E/∂U = ∂E/∂J R⁻ᵀ).
  double element(const Element& e, const std::vector<double>& x, double eps,
                 std::array<double, D*(D + 1)>& gradient) const {
    Matrix d;  // ∂f/∂J
    const double f = simplex_density<D>(jacobian(e, x), eps, theta_, d);
    gradient.fill(0.0);
    for (int r = 0; r < D; ++r)
      for (int k = 0; k < D; ++k) {
        double du = 0;  // ∂E/∂U[r][k]
        for (int m = 0; m < D; ++m) du += d[D * r + m] * e.inverse[D * k + m];
        gradient[D * (k + 1) + r] += e.weight * du;
        gradient[r] -= e.weight * du;
      }
    return e.weight * f;
  }

  const std::vector<Point>& image_;
  std::vector<std::int64_t> variable_;
  std::size_t points_ = 0;
  std::vector<Element> elements_;
  double theta_;
};

double dot(const std::vector<double>& a, const std::vector<double>& b) {
  double s = 0;
  for (std::size_t i = 0; i < a.size(); ++i) s += a[i] * b[i];
  return s;
}

// A backtracking Armijo search along `direction` from x (energy e, slope gᵀ direction): the
// step halves from 1, at most `tries` times, until the energy is finite (ε = 0 makes
// det J ≤ 0 a wall) and falls enough. On success `trial` holds the point, with its energy and
// gradient.
bool backtrack(const FoldoverEnergy& energy, double eps, const std::vector<double>& x,
               const std::vector<double>& direction, double e, double slope, int tries,
               std::vector<double>& trial, std::vector<double>& trial_g, double& trial_e) {
  double step = 1;
  for (int i = 0; i < tries; ++i, step *= 0.5) {
    for (std::size_t k = 0; k < x.size(); ++k) trial[k] = x[k] + step * direction[k];
    trial_e = energy(trial, eps, trial_g);
    if (std::isfinite(trial_e) && trial_e <= e + 1e-4 * step * slope) return true;
  }
  return false;
}

// L-BFGS (8 pairs) with a backtracking Armijo search; a step to a non-finite energy (ε = 0
// makes det J ≤ 0 a wall) is backtracked like any other. Returns the steps taken.
int minimise(const FoldoverEnergy& energy, double eps, int max_steps,
             const std::function<void()>& each_step, std::vector<double>& x) {
  constexpr int kPairs = 8;
  std::vector<double> g, trial_g, trial(x.size()), direction(x.size());
  double e = energy(x, eps, g);
  std::deque<std::vector<double>> s_list, y_list;
  int steps = 0;
  for (; steps < max_steps; ++steps) {
    if (each_step) each_step();
    // The two-loop recursion: direction = −H g.
    direction = g;
    std::vector<double> alpha(s_list.size());
    for (std::size_t i = s_list.size(); i-- > 0;) {
      alpha[i] = dot(s_list[i], direction) / dot(y_list[i], s_list[i]);
      for (std::size_t k = 0; k < x.size(); ++k) direction[k] -= alpha[i] * y_list[i][k];
    }
    double gamma = 1;
    if (!s_list.empty()) {
      gamma = dot(s_list.back(), y_list.back()) / dot(y_list.back(), y_list.back());
    } else {
      double largest = 0;
      for (double a : g) largest = std::max(largest, std::abs(a));
      gamma = largest > 0 ? 1e-2 / largest : 1;  // a first step of 0.01 in the cube
    }
    for (double& a : direction) a *= gamma;
    for (std::size_t i = 0; i < s_list.size(); ++i) {
      const double beta = dot(y_list[i], direction) / dot(y_list[i], s_list[i]);
      for (std::size_t k = 0; k < x.size(); ++k) direction[k] += (alpha[i] - beta) * s_list[i][k];
    }
    for (double& a : direction) a = -a;
    double slope = dot(g, direction);
    if (!(slope < 0)) {  // not a descent direction: start again from the gradient
      s_list.clear(), y_list.clear();
      double largest = 0;
      for (double a : g) largest = std::max(largest, std::abs(a));
      if (!(largest > 0)) break;
      for (std::size_t k = 0; k < x.size(); ++k) direction[k] = -g[k] * 1e-2 / largest;
      slope = dot(g, direction);
    }
    double trial_e = 0;
    if (!backtrack(energy, eps, x, direction, e, slope, 40, trial, trial_g, trial_e)) break;
    std::vector<double> s(x.size()), y(x.size());
    for (std::size_t k = 0; k < x.size(); ++k) s[k] = trial[k] - x[k], y[k] = trial_g[k] - g[k];
    const double decrease = e - trial_e;
    x.swap(trial);
    g.swap(trial_g);
    e = trial_e;
    if (dot(s, y) > 1e-16) {
      s_list.push_back(std::move(s));
      y_list.push_back(std::move(y));
      if (s_list.size() > kPairs) s_list.pop_front(), y_list.pop_front();
    }
    if (decrease <= 1e-9 * std::abs(e)) break;
  }
  return steps;
}

// Projected Newton steps on the energy at this ε (its Hessian's elements made positive
// semi-definite, a shift for the directions that leaves flat), each with a backtracking Armijo
// search. Returns the steps taken; -1 where the energy has no Hessian.
int newton_minimise(const FoldoverEnergy& energy, double eps, int max_steps,
                    const std::function<void()>& each_step, std::vector<double>& x) {
#if defined(CGAL_EIGEN3_ENABLED)
  const auto n = static_cast<Eigen::Index>(x.size());
  std::vector<double> g, trial_g, trial(x.size()), direction(x.size());
  std::vector<FoldoverEnergy::Entry> entries;
  double e = energy(x, eps, g);
  int steps = 0;
  for (; steps < max_steps; ++steps) {
    if (each_step) each_step();
    entries.clear();
    if (!energy.hessian(x, eps, entries)) return steps == 0 ? -1 : steps;
    std::vector<Eigen::Triplet<double>> triplets;
    triplets.reserve(entries.size());
    for (const auto& entry : entries) triplets.emplace_back(entry.row, entry.column, entry.value);
    Eigen::SparseMatrix<double> h(n, n);
    h.setFromTriplets(triplets.begin(), triplets.end());
    // Each diagonal entry grown by a share of itself, not of the largest: a crowded region's
    // entries are 10⁴⁰ times the rest's, and a shift of that size would freeze the rest.
    Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>, Eigen::Lower> solver;
    for (double shift = 1e-10; shift < 1; shift *= 100) {
      Eigen::SparseMatrix<double> shifted = h;
      for (Eigen::Index i = 0; i < n; ++i)
        shifted.coeffRef(i, i) = std::max(h.coeff(i, i) * (1 + shift), 1e-300);
      solver.compute(shifted);
      if (solver.info() == Eigen::Success) break;
    }
    if (solver.info() != Eigen::Success) break;
    const Eigen::VectorXd d = solver.solve(-Eigen::Map<const Eigen::VectorXd>(g.data(), n));
    for (Eigen::Index i = 0; i < n; ++i) direction[i] = d[i];
    const double slope = dot(g, direction);
    if (!(slope < 0) || -slope < 1e-9 * std::abs(e)) break;  // Newton's decrement: converged
    double trial_e = 0;
    if (!backtrack(energy, eps, x, direction, e, slope, 60, trial, trial_g, trial_e)) break;
    const double decrease = e - trial_e;
    x.swap(trial), g.swap(trial_g);
    e = trial_e;
    if (decrease <= 1e-9 * std::abs(e)) break;
  }
  return steps;
#else
  (void)energy, (void)eps, (void)max_steps, (void)each_step, (void)x;
  return -1;
#endif
}

}  // namespace

UntangleResult minimise_foldover(const FoldoverEnergy& energy, std::vector<double>& x,
                                 const FoldoverSchedule& schedule,
                                 const std::function<void(double)>& report) {
  UntangleResult result;
  std::vector<double> g;
  result.min_det_before = result.min_det_after = energy.min_det(x);
  // The schedule of ε (the paper's Algorithm 1 and eq. 6): after each minimisation,
  // μ = (1 − σ) χ(min det, ε), σ = max(1 − E / E_prev, 0.1), and ε = 2 √(μ (μ − min det)) while
  // min det < μ, else 0 (a barrier); done once min det > 0 and E stops falling.
  double eps = schedule.first_eps;
  for (; result.rounds < schedule.max_rounds; ++result.rounds) {
    const double before = energy(x, eps, g);
    const double done = double(result.rounds) / schedule.max_rounds;
    const auto each_step = [&] {
      if (report) report(done);
    };
    const int newton_steps =
        schedule.newton ? newton_minimise(energy, eps, schedule.max_newton_steps, each_step, x)
                        : -1;
    result.steps +=
        newton_steps >= 0 ? newton_steps : minimise(energy, eps, schedule.max_steps, each_step, x);
    const double after = energy(x, eps, g);
    const double least = energy.min_det(x);
    const double mu = std::min(after / before, schedule.decrease_cap) * 0.5 *
                      (least + std::sqrt(eps * eps + least * least));
    eps = least < mu ? 2 * std::sqrt(mu * (mu - least)) : 0;
    result.min_det_after = least;
    if (least > 0 && after > 0.999 * before) {
      ++result.rounds;
      break;
    }
  }
  return result;
}

UntangleResult untangle(const TetMesh& mesh, const std::vector<char>& movable,
                        std::vector<std::array<double, 3>>& uvw,
                        const std::function<void(double)>& report,
                        const FoldoverSchedule& schedule) {
  std::vector<Matrix3> shapes(mesh.tets.size());
  for (std::size_t t = 0; t < mesh.tets.size(); ++t)
    for (int k = 0; k < 3; ++k) {
      const Vec3 e = mesh.points[mesh.tets[t][k + 1]] - mesh.points[mesh.tets[t][0]];
      shapes[t][k] = e.x, shapes[t][3 + k] = e.y, shapes[t][6 + k] = e.z;
    }
  const SimplexEnergy<3> energy(mesh.tets, shapes, movable, uvw, kTheta);
  if (energy.empty()) return {};
  std::vector<double> x = energy.initial();
  const UntangleResult result = minimise_foldover(energy, x, schedule, report);
  energy.write(x, uvw);
  return result;
}

UntangleResult untangle_triangles(const std::vector<Vec3>& points,
                                  const std::vector<Triangle>& triangles,
                                  const std::vector<char>& movable, double theta,
                                  std::vector<std::array<double, 2>>& uv,
                                  const std::function<void(double)>& report) {
  // Each triangle's own shape in a frame of its plane: edge 1 along x.
  std::vector<Matrix2> shapes(triangles.size());
  for (std::size_t t = 0; t < triangles.size(); ++t) {
    const Vec3 a = points[triangles[t][1]] - points[triangles[t][0]];
    const Vec3 b = points[triangles[t][2]] - points[triangles[t][0]];
    const double length = norm(a);
    shapes[t] =
        length > 0 ? Matrix2{length, dot(a, b) / length, 0, norm(cross(a, b)) / length} : Matrix2{};
  }
  const SimplexEnergy<2> energy(triangles, shapes, movable, uv, theta);
  if (energy.empty()) return {};
  std::vector<double> x = energy.initial();
  FoldoverSchedule schedule;
  schedule.newton = true;
  UntangleResult result;
  result.min_det_before = energy.min_det(x);
  if (!(result.min_det_before > 0)) result = minimise_foldover(energy, x, schedule, report);
  // Then (or from a map with nothing turned, at once) ε = 0, a barrier, so none turns: the
  // schedule stops once none is turned, which can leave a region crowded to 10⁻²⁰.
  if (energy.min_det(x) > 0) {
    schedule.first_eps = 0;
    const UntangleResult barrier = minimise_foldover(energy, x, schedule, report);
    result.rounds += barrier.rounds, result.steps += barrier.steps;
    result.min_det_after = barrier.min_det_after;
  }
  energy.write(x, uv);
  return result;
}

}  // namespace tpmsfill::detail
