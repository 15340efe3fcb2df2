// Foldover-free maps (untangle.hpp): the regularised energy, its gradient, L-BFGS, and the
// schedule of ε.
#include "solid/internal/untangle.hpp"

#include <algorithm>
#include <cmath>
#include <deque>
#include <limits>

#include "core/parallel.hpp"

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

double foldover_density(const Matrix3& j, double eps, Matrix3& derivative) {
  const Matrix3 c = cofactor(j);
  const double det = determinant(j);
  double trace = 0;
  for (double a : j) trace += a * a;
  const double root = std::sqrt(eps * eps + det * det);
  const double chi = 0.5 * (det + root);
  const double chi_d = root > 0 ? 0.5 * (1 + det / root) : 0.5;
  const double chi23 = std::cbrt(chi * chi);
  const double shape = trace / chi23, volume = (det * det + 1) / chi;
  for (int i = 0; i < 9; ++i)
    derivative[i] = (1 - kTheta) * (2 * j[i] / chi23 - (2.0 / 3) * shape / chi * chi_d * c[i]) +
                    kTheta * (2 * det - volume * chi_d) / chi * c[i];
  return (1 - kTheta) * shape + kTheta * volume;
}

namespace {

using M3 = Matrix3;

// The tets with a movable corner: their corners, the inverse of their scaled shape (its
// columns' edges from corner 0) and their share of the total volume.
struct Element {
  Tet corners;
  M3 inverse;
  double weight;
};

class TetEnergy final : public FoldoverEnergy {
 public:
  TetEnergy(const TetMesh& mesh, const std::vector<char>& movable,
            const std::vector<std::array<double, 3>>& uvw)
      : uvw_(uvw), variable_(mesh.points.size(), -1) {
    for (std::size_t v = 0; v < mesh.points.size(); ++v)
      if (movable[v]) variable_[v] = static_cast<std::int64_t>(points_++);
    double volume = 0;
    for (const Tet& t : mesh.tets) {
      if (!(movable[t[0]] || movable[t[1]] || movable[t[2]] || movable[t[3]])) continue;
      M3 shape;
      for (int k = 0; k < 3; ++k) {
        const Vec3 e = mesh.points[t[k + 1]] - mesh.points[t[0]];
        shape[k] = e.x, shape[3 + k] = e.y, shape[6 + k] = e.z;
      }
      const double det = determinant(shape);
      if (!(det > 0)) continue;
      elements_.push_back({t, detail::inverse(shape, det), det / 6});
      volume += det / 6;
    }
    // The shapes scaled so that their total volume is their images' (a map that keeps
    // volume has det J = 1 on average): R⁻¹ scales by 1 / s, s³ = image volume / volume.
    double image_volume = 0;
    for (const Element& e : elements_) image_volume += determinant(image_edges(e, {}));
    image_volume /= 6;
    const double scale = std::cbrt(std::max(image_volume, 1e-300) / std::max(volume, 1e-300));
    for (Element& e : elements_) {
      for (double& x : e.inverse) x /= scale;
      e.weight /= volume;
    }
  }

  std::size_t variables() const { return 3 * points_; }
  bool empty() const { return elements_.empty() || points_ == 0; }

  std::vector<double> initial() const {
    std::vector<double> x(variables());
    for (std::size_t v = 0; v < variable_.size(); ++v)
      if (variable_[v] >= 0)
        for (int a = 0; a < 3; ++a) x[3 * variable_[v] + a] = uvw_[v][a];
    return x;
  }

  void write(const std::vector<double>& x, std::vector<std::array<double, 3>>& uvw) const {
    for (std::size_t v = 0; v < variable_.size(); ++v)
      if (variable_[v] >= 0)
        for (int a = 0; a < 3; ++a) uvw[v][a] = x[3 * variable_[v] + a];
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
    std::vector<std::array<double, 12>> local(elements_.size());
    parallel_for(elements_.size(), 1024, [&](std::size_t begin, std::size_t end) {
      for (std::size_t i = begin; i < end; ++i) energy[i] = element(elements_[i], x, eps, local[i]);
    });
    gradient.assign(variables(), 0.0);
    double total = 0;
    for (std::size_t i = 0; i < elements_.size(); ++i) {
      total += energy[i];
      for (int k = 0; k < 4; ++k) {
        const std::int64_t v = variable_[elements_[i].corners[k]];
        if (v >= 0)
          for (int a = 0; a < 3; ++a) gradient[3 * v + a] += local[i][3 * k + a];
      }
    }
    return total;
  }

 private:
  std::array<double, 3> at(std::uint32_t p, const std::vector<double>& x) const {
    const std::int64_t v = variable_[p];
    if (v < 0 || x.empty()) return uvw_[p];
    return {x[3 * v], x[3 * v + 1], x[3 * v + 2]};
  }

  // U: column k is corner k + 1's image less corner 0's.
  M3 image_edges(const Element& e, const std::vector<double>& x) const {
    const auto p0 = at(e.corners[0], x);
    M3 u;
    for (int k = 0; k < 3; ++k) {
      const auto p = at(e.corners[k + 1], x);
      for (int r = 0; r < 3; ++r) u[3 * r + k] = p[r] - p0[r];
    }
    return u;
  }

  M3 jacobian(const Element& e, const std::vector<double>& x) const {
    const M3 u = image_edges(e, x);
    M3 j{};
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 3; ++c)
        for (int m = 0; m < 3; ++m) j[3 * r + c] += u[3 * r + m] * e.inverse[3 * m + c];
    return j;
  }

  // One element's energy, and its gradient by corner (∂E/∂U = ∂E/∂J R⁻ᵀ).
  double element(const Element& e, const std::vector<double>& x, double eps,
                 std::array<double, 12>& gradient) const {
    M3 d;  // ∂f/∂J
    const double f = foldover_density(jacobian(e, x), eps, d);
    gradient.fill(0.0);
    for (int r = 0; r < 3; ++r)
      for (int k = 0; k < 3; ++k) {
        double du = 0;  // ∂E/∂U[r][k]
        for (int m = 0; m < 3; ++m) du += d[3 * r + m] * e.inverse[3 * k + m];
        gradient[3 * (k + 1) + r] += e.weight * du;
        gradient[r] -= e.weight * du;
      }
    return e.weight * f;
  }

  const std::vector<std::array<double, 3>>& uvw_;
  std::vector<std::int64_t> variable_;
  std::size_t points_ = 0;
  std::vector<Element> elements_;
};

double dot(const std::vector<double>& a, const std::vector<double>& b) {
  double s = 0;
  for (std::size_t i = 0; i < a.size(); ++i) s += a[i] * b[i];
  return s;
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
    double step = 1, trial_e = 0;
    bool accepted = false;
    for (int tries = 0; tries < 40; ++tries, step *= 0.5) {
      for (std::size_t k = 0; k < x.size(); ++k) trial[k] = x[k] + step * direction[k];
      trial_e = energy(trial, eps, trial_g);
      if (std::isfinite(trial_e) && trial_e <= e + 1e-4 * step * slope) {
        accepted = true;
        break;
      }
    }
    if (!accepted) break;
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
    result.steps += minimise(
        energy, eps, schedule.max_steps,
        [&] {
          if (report) report(done);
        },
        x);
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
                        const std::function<void(double)>& report) {
  const TetEnergy energy(mesh, movable, uvw);
  if (energy.empty()) return {};
  std::vector<double> x = energy.initial();
  const UntangleResult result = minimise_foldover(energy, x, {}, report);
  energy.write(x, uvw);
  return result;
}

}  // namespace tpmsfill::detail
