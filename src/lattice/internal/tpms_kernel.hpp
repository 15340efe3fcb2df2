/// @file tpms_kernel.hpp
/// @brief The TPMS type table: f and its gradient from per-axis trigonometry (AxisTrig), so that
/// grid lines share their sines and cosines; f̃ = f/|∇f| in mm; and TpmsLayer, one TPMS's
/// constants, which the tpms stage and the design (design.cpp) evaluate with.
#pragma once

#include <algorithm>
#include <cmath>
#include <memory>
#include <vector>

#include "tpmsfill/lattice/tpms.hpp"

namespace tpmsfill::detail {

/// sample_cell's sorted samples, shared from a small cache instead of copied.
std::shared_ptr<const CellSamples> shared_cell_samples(const TpmsOptions& options,
                                                       int samples = 96);

/// cos/sin of X at one coordinate along one axis.
struct AxisTrig {
  double c = 1, s = 0;
};

inline AxisTrig axis_trig(double phase) {
  return {std::cos(phase), std::sin(phase)};
}

/// f and ∂f/∂X, ∂f/∂Y, ∂f/∂Z (dimensionless).
struct FGrad {
  double f, gx, gy, gz;
};

namespace table {

// Each type's f is invariant under the cyclic permutation (X, Y, Z) → (Y, Z, X), so one
// function of (x, y, z) gives ∂f/∂X and the others follow by permuting its arguments. The
// double angles come from the single ones: cos 2X = 2c² − 1, sin 2X = 2sc.
struct Axis {
  double c, s, c2, s2;
};

inline Axis with_double(AxisTrig t) {
  return {t.c, t.s, 2 * t.c * t.c - 1, 2 * t.s * t.c};
}

// Σ over the cyclic terms of g(x, y, z) (the terms' sum that builds f).
template <class G>
double cyclic(const Axis& x, const Axis& y, const Axis& z, const G& g) {
  return g(x, y, z) + g(y, z, x) + g(z, x, y);
}

inline double f(TpmsType type, const Axis& x, const Axis& y, const Axis& z) {
  switch (type) {
    case TpmsType::Gyroid:  // cos X sin Y + cos Y sin Z + cos Z sin X
      return cyclic(x, y, z, [](const Axis& a, const Axis& b, const Axis&) { return a.c * b.s; });
    case TpmsType::Primitive:  // cos X + cos Y + cos Z
      return x.c + y.c + z.c;
    case TpmsType::Diamond:  // cos X cos Y cos Z − sin X sin Y sin Z
      return x.c * y.c * z.c - x.s * y.s * z.s;
    case TpmsType::Iwp:  // 2(cXcY + cYcZ + cZcX) − (c2X + c2Y + c2Z)
      return cyclic(x, y, z,
                    [](const Axis& a, const Axis& b, const Axis&) { return 2 * a.c * b.c - a.c2; });
    case TpmsType::Neovius:  // 3(cX + cY + cZ) + 4 cX cY cZ
      return 3 * (x.c + y.c + z.c) + 4 * x.c * y.c * z.c;
    case TpmsType::Frd:  // 4 cX cY cZ − (c2X c2Y + c2Y c2Z + c2Z c2X)
      return 4 * x.c * y.c * z.c -
             cyclic(x, y, z, [](const Axis& a, const Axis& b, const Axis&) { return a.c2 * b.c2; });
    case TpmsType::Lidinoid:  // ½Σ s2X cY sZ − ½Σ c2X c2Y + 0.15
      return cyclic(x, y, z,
                    [](const Axis& a, const Axis& b, const Axis& c) {
                      return 0.5 * (a.s2 * b.c * c.s - a.c2 * b.c2);
                    }) +
             0.15;
    case TpmsType::SplitP:  // 1.1Σ s2X sZ cY − 0.2Σ c2X c2Y − 0.4Σ c2X
      return cyclic(x, y, z, [](const Axis& a, const Axis& b, const Axis& c) {
        return 1.1 * a.s2 * c.s * b.c - 0.2 * a.c2 * b.c2 - 0.4 * a.c2;
      });
    case TpmsType::Fourier:  // TpmsFormula sums its terms
      break;
  }
  return 0;
}

// ∂f/∂X as a function of (x, y, z); ∂f/∂Y = dx(y, z, x), ∂f/∂Z = dx(z, x, y).
inline double dx(TpmsType type, const Axis& x, const Axis& y, const Axis& z) {
  switch (type) {
    case TpmsType::Gyroid:
      return -x.s * y.s + z.c * x.c;
    case TpmsType::Primitive:
      return -x.s;
    case TpmsType::Diamond:
      return -x.s * y.c * z.c - x.c * y.s * z.s;
    case TpmsType::Iwp:
      return -2 * x.s * (y.c + z.c) + 2 * x.s2;
    case TpmsType::Neovius:
      return -3 * x.s - 4 * x.s * y.c * z.c;
    case TpmsType::Frd:
      return -4 * x.s * y.c * z.c + 2 * x.s2 * (y.c2 + z.c2);
    case TpmsType::Lidinoid:
      return 0.5 * (2 * x.c2 * y.c * z.s + y.s2 * z.c * x.c - z.s2 * x.s * y.s) +
             x.s2 * (y.c2 + z.c2);
    case TpmsType::SplitP:
      return 1.1 * (2 * x.c2 * z.s * y.c + y.s2 * x.c * z.c - z.s2 * y.s * x.s) +
             0.4 * x.s2 * (y.c2 + z.c2) + 0.8 * x.s2;
    case TpmsType::Fourier:
      break;
  }
  return 0;
}

}  // namespace table

inline FGrad tpms_f(TpmsType type, AxisTrig tx, AxisTrig ty, AxisTrig tz) {
  const table::Axis x = table::with_double(tx), y = table::with_double(ty),
                    z = table::with_double(tz);
  return {table::f(type, x, y, z), table::dx(type, x, y, z), table::dx(type, y, z, x),
          table::dx(type, z, x, y)};
}

/// f of one lattice: a named type's formula, or a `fourier` sum whose terms are prepared once
/// (cos and sin of each phase) and evaluated from the same per-axis trigonometry: e^{i(hX+kY+lZ)}
/// is a product of powers of e^{iX}, e^{iY}, e^{iZ}, so a node needs no further cos or sin.
class TpmsFormula {
 public:
  explicit TpmsFormula(const TpmsOptions& o) : type_(o.type) {
    for (const FourierTerm& t : o.terms) {
      terms_.push_back({t.amplitude, t.wave, std::cos(t.phase), std::sin(t.phase)});
      for (int a = 0; a < 3; ++a) max_wave_[a] = std::max(max_wave_[a], std::abs(t.wave[a]));
    }
  }

  FGrad operator()(AxisTrig tx, AxisTrig ty, AxisTrig tz) const {
    if (type_ != TpmsType::Fourier) return tpms_f(type_, tx, ty, tz);
    // powers[a][n] = e^{inθ_a}, n = 0 .. the largest |wave| along axis a.
    struct Complex {
      double re, im;
      Complex operator*(Complex b) const { return {re * b.re - im * b.im, re * b.im + im * b.re}; }
    };
    Complex powers[3][kMaxFourierWave + 1];
    const AxisTrig trig[3] = {tx, ty, tz};
    for (int a = 0; a < 3; ++a) {
      powers[a][0] = {1, 0};
      for (int n = 1; n <= max_wave_[a]; ++n)
        powers[a][n] = powers[a][n - 1] * Complex{trig[a].c, trig[a].s};
    }
    auto power = [&](int a, int n) {
      const Complex p = powers[a][std::abs(n)];
      return n < 0 ? Complex{p.re, -p.im} : p;
    };
    FGrad r{0, 0, 0, 0};
    for (const Term& t : terms_) {
      // e^{i(θ + P)}: A cos(θ + P) is f's term, −A sin(θ + P)·(h, k, l) its gradient's.
      const Complex e = power(0, t.wave[0]) * power(1, t.wave[1]) * power(2, t.wave[2]) *
                        Complex{t.cos_phase, t.sin_phase};
      r.f += t.amplitude * e.re;
      r.gx -= t.amplitude * t.wave[0] * e.im;
      r.gy -= t.amplitude * t.wave[1] * e.im;
      r.gz -= t.amplitude * t.wave[2] * e.im;
    }
    return r;
  }

 private:
  struct Term {
    double amplitude;
    std::array<int, 3> wave;
    double cos_phase, sin_phase;
  };
  TpmsType type_;
  std::vector<Term> terms_;
  int max_wave_[3] = {0, 0, 0};
};

/// f/|∇f| in mm from f and its gradient in mm⁻¹ (per-axis factors 2π/T, rotation and any warp
/// already applied). Where |∇f| vanishes (away from the surface) the ratio blows up and only
/// its sign matters there, so it is clamped to ±clamp (the largest cell size).
inline double tpms_distance(double f, double gx, double gy, double gz, double clamp) {
  const double grad = std::sqrt(gx * gx + gy * gy + gz * gz);
  return std::fabs(f) >= clamp * grad ? std::copysign(clamp, f) : f / grad;
}

/// Sheets refine their distance (refined_distance), so that a thickness in mm is met; networks
/// keep the first-order one (their level is usually solved from a porosity), and raw levels
/// are the seeds' level sets of f, whose thickness is no length to meet.
inline bool refines(const TpmsOptions& o) {
  return o.style == TpmsStyle::Sheet && o.unit == LevelUnit::Millimetre;
}

/// A second-order distance in lattice coordinates q (mm): the first-order estimate d₀ = f/|∇f|
/// plus the first-order distance left at q − (f/|∇f|²)∇f, one Newton step towards the surface.
/// Near curved level sets f/|∇f| alone is off by O(d²κ): thin sheets came out up to 15 %
/// thinner than asked. `k` holds 2π/T per axis; f and gq (∇f in mm⁻¹) are at q.
inline double refined_distance(const TpmsFormula& formula, const double k[3], const double q[3],
                               double f, const double gq[3]) {
  const double g2 = gq[0] * gq[0] + gq[1] * gq[1] + gq[2] * gq[2];
  if (!(g2 > 0)) return 0;
  const double step = f / g2;
  const FGrad h =
      formula(axis_trig(k[0] * (q[0] - step * gq[0])), axis_trig(k[1] * (q[1] - step * gq[1])),
              axis_trig(k[2] * (q[2] - step * gq[2])));
  const double h2 =
      k[0] * k[0] * h.gx * h.gx + k[1] * k[1] * h.gy * h.gy + k[2] * k[2] * h.gz * h.gz;
  const double d0 = f / std::sqrt(g2), correction = h2 > 0 ? h.f / std::sqrt(h2) : 0.0;
  // Far from the surface the step can land near another sheet: keep d₀ where it did not
  // make the progress a Newton step makes close to the surface.
  return std::fabs(correction) <= 0.5 * std::fabs(d0) ? d0 + correction : d0;
}

/// One TPMS ready to evaluate: its options and the constants every node needs.
struct TpmsLayer {
  TpmsOptions o;
  TpmsFormula formula;
  double k[3];      ///< 2π/T per axis, mm⁻¹
  double clamp;     ///< |f̃| bound: the largest cell size, mm
  bool refine;      ///< refines()
  Mat3 to_lattice;  ///< Rᵀ
  bool rotated;     ///< R is not the identity (no per-axis tables then)

  explicit TpmsLayer(const TpmsOptions& options)
      : o(options),
        formula(options),
        k{2 * M_PI / options.cell.x, 2 * M_PI / options.cell.y, 2 * M_PI / options.cell.z},
        clamp(std::fmax(options.cell.x, std::fmax(options.cell.y, options.cell.z))),
        refine(refines(options)),
        to_lattice(options.rotation.transposed()),
        rotated(!options.rotation.is_identity()) {}

  /// Not rotated: the per-axis table of trigonometry along `axis` of `grid`, at the nodes'
  /// coordinates, or at `coordinates[n]` when given (an axis the design warps).
  std::vector<AxisTrig> trig_table(const Grid& grid, int axis,
                                   const std::vector<double>* coordinates = nullptr) const {
    std::vector<AxisTrig> table;
    for (int n = 0; n < grid.dims[axis]; ++n) {
      const double x = coordinates ? (*coordinates)[n] : grid.coordinate(axis, n);
      table.push_back(axis_trig(k[axis] * (x - o.origin[axis])));
    }
    return table;
  }

  /// f and its derivatives at w (mm; a node, or where a warp moves it), and w's lattice
  /// coordinates q = Rᵀ(w − origin): the path of a rotated TPMS, with no tables.
  FGrad at(Vec3 w, Vec3& q) const {
    q = to_lattice * (w - o.origin);
    return formula(axis_trig(k[0] * q.x), axis_trig(k[1] * q.y), axis_trig(k[2] * q.z));
  }

  /// ∇f in the lattice's own coordinates, mm⁻¹ (before rotation or warp).
  Vec3 lattice_gradient(const FGrad& fg) const {
    return {k[0] * fg.gx, k[1] * fg.gy, k[2] * fg.gz};
  }

  /// f̃ (mm) from f at a node, its gradient g in mm⁻¹ as the world sees it (rotation and any
  /// warp applied) and, for sheets, the node's lattice coordinates q (mm): the first-order
  /// distance, refined for sheets near the surface and scaled as g scales the lattice's own
  /// gradient.
  double distance(const FGrad& fg, Vec3 g, Vec3 q) const {
    double d = tpms_distance(fg.f, g.x, g.y, g.z, clamp);
    if (refine && std::fabs(d) < clamp) {
      // In lattice coordinates (rotation is an isometry), then scaled as the warp scales f̃.
      const Vec3 lg = lattice_gradient(fg);
      const double gq[3] = {lg.x, lg.y, lg.z}, qq[3] = {q.x, q.y, q.z};
      d = refined_distance(formula, k, qq, fg.f, gq) * (norm(lg) / norm(g));
    }
    return d;
  }

  /// φ (mm) at a node from f, its gradient g (as distance() takes them), q, and the level
  /// (network) or thickness (sheet) v in the layer's unit: on f̃ in mm, or raw on f, where the
  /// seeds' level sets f + C = 0 and |f + level| = thickness/2 are measured by their own
  /// first-order distance (f + C)/|∇f|.
  double value(const FGrad& fg, Vec3 g, Vec3 q, double v) const {
    const bool network = o.style == TpmsStyle::Network;
    if (o.unit == LevelUnit::Raw)
      return tpms_distance(network ? fg.f + v : std::fabs(fg.f + o.level) - 0.5 * v, g.x, g.y, g.z,
                           clamp);
    const double d = distance(fg, g, q);
    return network ? d + v : std::fabs(d + o.level) - 0.5 * v;
  }
};

}  // namespace tpmsfill::detail
