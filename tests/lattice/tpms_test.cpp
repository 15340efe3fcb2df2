// Stage "tpms": the normalised fields, their separable evaluation and the unclipped porosity.
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <tpmsfill/error.hpp>
#include <tpmsfill/fill.hpp>
#include <tpmsfill/lattice/tpms.hpp>

#include "test_util.hpp"

using namespace tpmsfill;

namespace {

// The formulas of docs/method.md, written out independently of the separable kernel.
double raw_f(TpmsType type, Vec3 p, Vec3 cell) {
  const double X = 2 * M_PI * p.x / cell.x, Y = 2 * M_PI * p.y / cell.y,
               Z = 2 * M_PI * p.z / cell.z;
  switch (type) {
    case TpmsType::Gyroid:
      return std::cos(X) * std::sin(Y) + std::cos(Y) * std::sin(Z) + std::cos(Z) * std::sin(X);
    case TpmsType::Primitive:
      return std::cos(X) + std::cos(Y) + std::cos(Z);
    case TpmsType::Diamond:
      return std::cos(X) * std::cos(Y) * std::cos(Z) - std::sin(X) * std::sin(Y) * std::sin(Z);
    case TpmsType::Iwp:
      return 2 * (std::cos(X) * std::cos(Y) + std::cos(Y) * std::cos(Z) +
                  std::cos(Z) * std::cos(X)) -
             (std::cos(2 * X) + std::cos(2 * Y) + std::cos(2 * Z));
    case TpmsType::Neovius:
      return 3 * (std::cos(X) + std::cos(Y) + std::cos(Z)) +
             4 * std::cos(X) * std::cos(Y) * std::cos(Z);
    case TpmsType::Frd:
      return 4 * std::cos(X) * std::cos(Y) * std::cos(Z) -
             (std::cos(2 * X) * std::cos(2 * Y) + std::cos(2 * Y) * std::cos(2 * Z) +
              std::cos(2 * Z) * std::cos(2 * X));
    case TpmsType::Lidinoid:
      return 0.5 * (std::sin(2 * X) * std::cos(Y) * std::sin(Z) +
                    std::sin(2 * Y) * std::cos(Z) * std::sin(X) +
                    std::sin(2 * Z) * std::cos(X) * std::sin(Y)) -
             0.5 * (std::cos(2 * X) * std::cos(2 * Y) + std::cos(2 * Y) * std::cos(2 * Z) +
                    std::cos(2 * Z) * std::cos(2 * X)) +
             0.15;
    case TpmsType::SplitP:
      return 1.1 * (std::sin(2 * X) * std::sin(Z) * std::cos(Y) +
                    std::sin(2 * Y) * std::sin(X) * std::cos(Z) +
                    std::sin(2 * Z) * std::sin(Y) * std::cos(X)) -
             0.2 * (std::cos(2 * X) * std::cos(2 * Y) + std::cos(2 * Y) * std::cos(2 * Z) +
                    std::cos(2 * Z) * std::cos(2 * X)) -
             0.4 * (std::cos(2 * X) + std::cos(2 * Y) + std::cos(2 * Z));
    case TpmsType::Fourier:  // fourier_f() below
      break;
  }
  return 0;
}

// Seed 000's eq. 2 written out: Σ A cos(2π(h x/Tx + k y/Ty + l z/Tz) + P).
double fourier_f(const std::vector<FourierTerm>& terms, Vec3 p, Vec3 cell) {
  double f = 0;
  for (const FourierTerm& t : terms)
    f += t.amplitude * std::cos(2 * M_PI *
                                    (t.wave[0] * p.x / cell.x + t.wave[1] * p.y / cell.y +
                                     t.wave[2] * p.z / cell.z) +
                                t.phase);
  return f;
}

Vec3 numeric_gradient(TpmsType type, Vec3 p, Vec3 cell) {
  const double h = 1e-6;
  return {
      (raw_f(type, {p.x + h, p.y, p.z}, cell) - raw_f(type, {p.x - h, p.y, p.z}, cell)) / (2 * h),
      (raw_f(type, {p.x, p.y + h, p.z}, cell) - raw_f(type, {p.x, p.y - h, p.z}, cell)) / (2 * h),
      (raw_f(type, {p.x, p.y, p.z + h}, cell) - raw_f(type, {p.x, p.y, p.z - h}, cell)) / (2 * h)};
}

const TpmsType (&kTypes)[8] = test::kAllTpmsTypes;
// The three whose level 0 splits space into congruent halves.
const TpmsType kBalanced[] = {TpmsType::Gyroid, TpmsType::Primitive, TpmsType::Diamond};

}  // namespace

TEST(Tpms, NetworkValueIsFOverItsGradientNorm) {
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(-5, 5);
  for (TpmsType type : kTypes) {
    const TpmsOptions o{.type = type, .cell = {2, 2.5, 3}};
    for (int n = 0; n < 500; ++n) {
      const Vec3 p{u(rng), u(rng), u(rng)};
      const double f = raw_f(type, p, o.cell), g = norm(numeric_gradient(type, p, o.cell));
      const double expected =
          std::fabs(f) >= 3 * g ? std::copysign(3.0, f) : f / g;  // clamp: max T
      EXPECT_NEAR(test::tpms_value(p, o), expected, 1e-4 * (1 + std::fabs(expected)))
          << tpms_type_name(type);
    }
  }
}

TEST(Tpms, NormalisedFieldIsADistanceNearTheSurface) {
  // Walk from a point on the surface along the normal: the value grows like the distance.
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(0, 2);
  for (TpmsType type : kTypes) {
    const TpmsOptions o{.type = type, .cell = {2, 2, 2}};
    int checked = 0;
    for (int n = 0; n < 200 && checked < 40; ++n) {
      Vec3 p{u(rng), u(rng), u(rng)};
      // Newton steps onto f = 0.
      for (int it = 0; it < 30; ++it) {
        const Vec3 g = numeric_gradient(type, p, o.cell);
        p = p - (raw_f(type, p, o.cell) / dot(g, g)) * g;
      }
      const Vec3 g = numeric_gradient(type, p, o.cell);
      if (std::fabs(raw_f(type, p, o.cell)) > 1e-9 || norm(g) < 1.0) continue;
      const Vec3 normal = (1.0 / norm(g)) * g;
      for (double h : {0.005, 0.01, 0.02}) {
        EXPECT_NEAR(test::tpms_value(p + h * normal, o), h, 0.15 * h) << tpms_type_name(type);
        EXPECT_NEAR(test::tpms_value(p - h * normal, o), -h, 0.15 * h) << tpms_type_name(type);
      }
      ++checked;
    }
    EXPECT_GE(checked, 20);
  }
}

TEST(Tpms, LevelAndSheetShiftTheField) {
  const Vec3 p{0.3, 0.7, 1.1};
  const float base = test::tpms_value(p, {});
  EXPECT_FLOAT_EQ(test::tpms_value(p, {.level = 0.25}), base + 0.25f);
  // Sheets refine the distance by one Newton step: close to, not equal to, |f̃| − t/2.
  EXPECT_NEAR(test::tpms_value(p, {.style = TpmsStyle::Sheet, .thickness = 0.4}),
              std::fabs(base) - 0.2f, 0.02 * std::fabs(base));
}

TEST(Tpms, SourceBoundHoldsEverywhere) {
  // f̃ is clamped to ± the largest cell size, so twice that bounds a network with a level
  // within a cell and a sheet of any thickness up to two cells.
  for (const TpmsOptions& o :
       {TpmsOptions{.cell = {1, 4, 2}, .level = 0.5},
        TpmsOptions{.style = TpmsStyle::Sheet, .cell = {1, 4, 2}, .thickness = 1.5}}) {
    const FieldSource source = tpms_source(o);
    EXPECT_DOUBLE_EQ(source.bound, 8.0);
    Grid g;
    g.origin = {-2.1, -3.3, 0.4};
    g.spacing = 0.23;
    g.dims = {40, 41, 42};
    const Field f = sample_field(source, g);
    float largest = 0;
    for (float v : f.values) largest = std::max(largest, std::fabs(v));
    EXPECT_LE(largest, source.bound);
    EXPECT_GT(largest, 0.25 * source.bound);  // the clamp is reached where |∇f| vanishes
  }
}

TEST(Tpms, BalancedNetworksAreHalfSolid) {
  // Gyroid and diamond are odd under a symmetry, Schwarz P under a half-cell shift: C = 0
  // splits space into two congruent labyrinths.
  for (TpmsType type : kBalanced)
    EXPECT_NEAR(tpms_solid_fraction({.type = type}), 0.5, 0.005) << tpms_type_name(type);
}

TEST(Tpms, SolidFractionFallsAsTheLevelRises) {
  double last = 1.0;
  for (double level : {-0.4, -0.2, 0.0, 0.2, 0.4}) {
    const double fraction = tpms_solid_fraction({.level = level});
    EXPECT_LT(fraction, last);
    last = fraction;
  }
}

TEST(Tpms, ThinSheetVolumeIsAreaTimesThickness) {
  // Gyroid area per unit cell is about 3.0915·T² (Schoen), so a thin sheet fills
  // 3.0915·t/T of space.
  for (double t : {0.05, 0.1}) {
    const double fraction =
        tpms_solid_fraction({.style = TpmsStyle::Sheet, .cell = {2, 2, 2}, .thickness = t}, 160);
    EXPECT_NEAR(fraction, 3.0915 * t / 2, 0.03 * 3.0915 * t / 2);
  }
}

TEST(Tpms, NamesAndValidation) {
  for (TpmsType type : kTypes) EXPECT_EQ(tpms_type_from_name(tpms_type_name(type)), type);
  EXPECT_EQ(tpms_type_from_name("schwarz-p"), TpmsType::Primitive);
  EXPECT_THROW(tpms_type_from_name("kelvin"), InputError);
  EXPECT_THROW(require_valid(TpmsOptions{.cell = {0, 1, 1}}), InputError);
  EXPECT_THROW(require_valid(TpmsOptions{.style = TpmsStyle::Sheet, .thickness = -1}), InputError);
  EXPECT_THROW(require_valid(TpmsOptions{.level = std::nan("")}), InputError);
}

TEST(Tpms, SheetBetweenTwoLevels) {
  // Seed 004's "nesting TPMS of different C": walls where C1 <= f̃ <= C2, here 0.2 to 0.8 mm
  // off a gyroid's minimal surface (4 mm cells). Level −(C1 + C2)/2 and thickness C2 − C1.
  TpmsOptions o;
  o.style = TpmsStyle::Sheet;
  o.cell = {4, 4, 4};
  o.level = -0.5, o.thickness = 0.6;
  // The gyroid is odd under a half-cell shift (f → −f): the mirrored levels hold as much solid.
  TpmsOptions mirrored = o;
  mirrored.level = 0.5;
  const double solid = tpms_solid_fraction(o);
  EXPECT_NEAR(tpms_solid_fraction(mirrored), solid, 0.01);
  // ... but not as much as the centred wall of the same thickness.
  TpmsOptions centred = o;
  centred.level = 0;
  EXPECT_GT(std::fabs(tpms_solid_fraction(centred) - solid), 0.02);
  EXPECT_NE(tpms_label(o).find("between levels 0.2 and 0.8 mm"), std::string::npos);
  // Filled: a cube of whole cells, valid, with the solid fraction the cell's samples predict.
  FillOptions f;
  f.grid.voxel_size = 0.1;
  static_cast<TpmsOptions&>(f.design) = o;
  const FillResult r = fill(test::make_box({0, 0, 0}, {8, 8, 8}), f);
  EXPECT_TRUE(r.report.validation.valid());
  EXPECT_NEAR(1 - r.report.porosity(), solid, 0.02);
  // A porosity target has no thickness left to solve.
  o.porosity = 0.7;
  EXPECT_THROW(require_valid(o), InputError);
}

TEST(Tpms, EveryNamedTypeIsAFourierSum) {
  // Issue 41: the eight named types as instances of the general form, the same field to
  // round-off: first f itself (the terms against the formulas written out above), then φ as
  // the fill samples it (the separable kernel's Fourier path against its named one), network
  // and sheet, rotated and not.
  std::mt19937 rng(41);
  std::uniform_real_distribution<double> u(-5, 5);
  for (TpmsType type : kTypes) {
    const Vec3 cell = {2, 2.5, 3};
    const std::vector<FourierTerm> terms = fourier_terms(TpmsOptions{.type = type});
    for (int n = 0; n < 200; ++n) {
      const Vec3 p{u(rng), u(rng), u(rng)};
      EXPECT_NEAR(fourier_f(terms, p, cell), raw_f(type, p, cell), 1e-12)
          << tpms_type_name(type) << " at " << p.x << " " << p.y << " " << p.z;
    }
    for (TpmsStyle style : {TpmsStyle::Network, TpmsStyle::Sheet})
      for (bool rotated : {false, true}) {
        TpmsOptions named{.type = type, .style = style, .cell = cell, .level = 0.1};
        if (rotated) named.rotation = rotation_from_euler({10, 20, 30});
        TpmsOptions general = named;
        general.type = TpmsType::Fourier;
        general.terms = terms;
        require_valid(general);
        const Grid grid{.origin = {-1, -2, 0.5}, .spacing = 0.13, .dims = {12, 11, 10}};
        const Field a = sample_field(tpms_source(named), grid),
                    b = sample_field(tpms_source(general), grid);
        for (std::size_t i = 0; i < a.values.size(); ++i)
          ASSERT_NEAR(a.values[i], b.values[i], 1e-5)
              << tpms_label(named) << (rotated ? " rotated" : "") << " at node " << i;
      }
  }
}

TEST(Tpms, AFourierLatticeTakesPorositySheetsAndLevels) {
  // A type of no name (a gyroid's terms plus a second harmonic): normalised like the named
  // ones, so a porosity is reached over the cell, a sheet's thickness is mm, and its field is
  // f/|∇f| near the surface.
  std::vector<FourierTerm> terms = fourier_terms(TpmsOptions{.type = TpmsType::Gyroid});
  terms.push_back({0.3, {2, 0, 1}, 0.4});
  terms.push_back({0.2, {0, 0, 0}, 0});  // a constant shifts the surface
  const TpmsOptions network{
      .type = TpmsType::Fourier, .terms = terms, .cell = {3, 3, 3}, .porosity = 0.7};
  EXPECT_NEAR(tpms_solid_fraction(network, 96), 0.3, 0.005);
  EXPECT_NE(tpms_label(network).find("fourier (8 terms)"), std::string::npos);
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-4, 4);
  const TpmsOptions plain{.type = TpmsType::Fourier, .terms = terms, .cell = {3, 3, 3}};
  for (int n = 0, near = 0; n < 2000 && near < 100; ++n) {
    const Vec3 p{u(rng), u(rng), u(rng)};
    const double f = fourier_f(terms, p, plain.cell);
    const double h = 1e-6;
    const Vec3 g{(fourier_f(terms, p + Vec3{h, 0, 0}, plain.cell) -
                  fourier_f(terms, p - Vec3{h, 0, 0}, plain.cell)) /
                     (2 * h),
                 (fourier_f(terms, p + Vec3{0, h, 0}, plain.cell) -
                  fourier_f(terms, p - Vec3{0, h, 0}, plain.cell)) /
                     (2 * h),
                 (fourier_f(terms, p + Vec3{0, 0, h}, plain.cell) -
                  fourier_f(terms, p - Vec3{0, 0, h}, plain.cell)) /
                     (2 * h)};
    if (std::fabs(f) > 0.3 * norm(g)) continue;  // near the surface, where f/|∇f| is unclamped
    ++near;
    EXPECT_NEAR(test::tpms_value(p, plain), f / norm(g), 1e-5);
  }
  // A thin sheet holds about its area times its thickness, as the named ones do: the same
  // fraction at twice the thickness doubles (within the curvature's share).
  const TpmsOptions thin{.type = TpmsType::Fourier,
                         .terms = terms,
                         .style = TpmsStyle::Sheet,
                         .cell = {3, 3, 3},
                         .thickness = 0.06};
  TpmsOptions twice = thin;
  twice.thickness = 0.12;
  EXPECT_NEAR(tpms_solid_fraction(twice, 128) / tpms_solid_fraction(thin, 128), 2, 0.06);
}

TEST(Tpms, FourierTermsAreChecked) {
  const std::vector<FourierTerm> p = fourier_terms(TpmsOptions{.type = TpmsType::Primitive});
  EXPECT_EQ(p.size(), 3u);
  EXPECT_THROW(require_valid(TpmsOptions{.type = TpmsType::Fourier}), InputError);  // no terms
  EXPECT_THROW(require_valid(TpmsOptions{.type = TpmsType::Gyroid, .terms = p}), InputError);
  EXPECT_THROW(require_valid(TpmsOptions{.type = TpmsType::Fourier, .terms = {{1, {0, 0, 0}, 0}}}),
               InputError);  // a constant has no surface
  EXPECT_THROW(require_valid(TpmsOptions{.type = TpmsType::Fourier, .terms = {{1, {17, 0, 0}, 0}}}),
               InputError);
  EXPECT_THROW(require_valid(
                   TpmsOptions{.type = TpmsType::Fourier, .terms = {{std::nan(""), {1, 0, 0}, 0}}}),
               InputError);
  EXPECT_THROW(require_valid(TpmsOptions{.type = TpmsType::Fourier,
                                         .terms = std::vector<FourierTerm>(kMaxFourierTerms + 1)}),
               InputError);
  EXPECT_EQ(tpms_type_from_name("fourier"), TpmsType::Fourier);
}

TEST(Tpms, RawLevelsAreTheSeedsC) {
  // The seeds write a network as f + C < 0 and a sheet as f² − C² < 0 (|f| < C). With raw
  // levels the solid is exactly that set, and φ is (f + C)/|∇f|, a distance in mm near it.
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(-5, 5);
  for (TpmsType type : kTypes) {
    const Vec3 cell = {2, 2.5, 3};
    const TpmsOptions network{.type = type, .cell = cell, .level = 0.3, .unit = LevelUnit::Raw};
    const TpmsOptions sheet{.type = type,
                            .style = TpmsStyle::Sheet,
                            .cell = cell,
                            .thickness = 0.6,
                            .unit = LevelUnit::Raw};
    for (int n = 0; n < 300; ++n) {
      const Vec3 p{u(rng), u(rng), u(rng)};
      const double f = raw_f(type, p, cell), g = norm(numeric_gradient(type, p, cell));
      const double network_phi = test::tpms_value(p, network),
                   sheet_phi = test::tpms_value(p, sheet);
      if (std::fabs(f + 0.3) > 1e-6) {
        EXPECT_EQ(network_phi < 0, f + 0.3 < 0);
      }
      if (std::fabs(std::fabs(f) - 0.3) > 1e-6) {
        EXPECT_EQ(sheet_phi < 0, std::fabs(f) < 0.3);
      }
      if (std::fabs(f + 0.3) < 0.5 * 3 * g) {
        EXPECT_NEAR(network_phi, (f + 0.3) / g, 1e-4 * (1 + std::fabs(network_phi)));
      }
    }
    // The cell's solid fraction counts the same set.
    double solid = 0;
    const int m = 40;
    for (int i = 0; i < m; ++i)
      for (int j = 0; j < m; ++j)
        for (int k = 0; k < m; ++k)
          solid +=
              raw_f(type, {cell.x * (i + 0.5) / m, cell.y * (j + 0.5) / m, cell.z * (k + 0.5) / m},
                    cell) +
                  0.3 <
              0;
    // (a sample within round-off of f = −C may fall either way: 2 of 64,000 allowed)
    EXPECT_NEAR(tpms_solid_fraction(network, m), solid / (m * m * m), 3.2e-5)
        << tpms_type_name(type);
  }
  // A porosity solves a level in mm: not with raw ones.
  EXPECT_THROW(require_valid(TpmsOptions{.unit = LevelUnit::Raw, .porosity = 0.7}), InputError);
  EXPECT_NE(tpms_label(TpmsOptions{.level = 0.3, .unit = LevelUnit::Raw}).find("C = 0.3"),
            std::string::npos);
}
