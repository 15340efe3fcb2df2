/// @file tpms.hpp
/// @brief Stage "tpms": one triply periodic minimal surface as a signed field φ_TPMS in
/// millimetres (paper eq. 1–4), and the level or thickness that gives a porosity.
///
/// In lattice coordinates q = Rᵀ(p − origin) (R the lattice's rotation), with X = 2π q_x/Tx,
/// Y = 2π q_y/Ty, Z = 2π q_z/Tz (T = cell size per axis), each type has a periodic function f
/// (the table in docs/method.md). f is not a distance, so tpmsfill uses
/// f̃ = f/|∇f|, a first-order distance in mm, clamped to ±max(T) where |∇f| vanishes away from
/// the surface. Then:
///   network:  φ_TPMS = f̃ + level          (solid where φ < 0; level in mm, 0 = the surface)
///   sheet:    φ_TPMS = |f̃ + level| − thickness/2  (solid within thickness/2 of f̃ = −level)
/// Without rotation the evaluation is separable: the per-axis sines and cosines are computed
/// once per grid line, so a sample costs a few multiply-adds, a square root and a division.
///
/// Besides the named types, `fourier` is the seeds' general form (seed 000 eq. 2, seed 004's
/// Fourier form): f = Σ A cos(2π(h x/Tx + k y/Ty + l z/Tz) + P) over its terms, each with whole
/// periods (h, k, l) per cell, so the cell is a period and porosity solves over it as for the
/// named types (each of which is such a sum: tests/lattice/tpms_test.cpp writes all eight so).
///
/// Levels and thicknesses are mm on f̃ by default. LevelUnit::Raw takes them as the seeds write
/// C, on f itself: a network is f + C < 0 and a sheet |f + level| < thickness/2 (the seed's
/// f² − C² < 0 is level 0, thickness 2C), each measured as (f + C)/|∇f| so φ stays in mm.
///
/// tpms_source() is the field a TPMS plugs into the field seam (field.hpp) with; graded and
/// blended designs build on this stage (design.hpp).
#pragma once

#include <array>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "tpmsfill/field.hpp"
#include "tpmsfill/types.hpp"

namespace tpmsfill {

/// The surface types of the table in docs/method.md, and the general Fourier sum.
enum class TpmsType { Gyroid, Primitive, Diamond, Iwp, Neovius, Frd, Lidinoid, SplitP, Fourier };

/// One term of a `fourier` lattice: amplitude · cos(2π(h x/Tx + k y/Ty + l z/Tz) + phase), with
/// (x, y, z) the lattice coordinates. (0, 0, 0) is a constant (the lidinoid's + 0.15).
struct FourierTerm {
  double amplitude = 1;
  std::array<int, 3> wave = {1, 0, 0};  ///< (h, k, l): whole periods per cell along each axis
  double phase = 0;                     ///< P, radians
  bool operator==(const FourierTerm&) const = default;
};

/// Whole periods of one term along one axis at most (a finer term needs a finer grid anyway).
inline constexpr int kMaxFourierWave = 16;
/// Terms of one `fourier` lattice at most.
inline constexpr std::size_t kMaxFourierTerms = 256;

/// What a level and a thickness are measured in: mm on f̃ (the default), or the seeds' raw C on f.
enum class LevelUnit { Millimetre, Raw };

/// Network: the solid is one side of the level set. Sheet: a shell around the surface.
enum class TpmsStyle { Network, Sheet };

/// One TPMS: its type, style and cell, and where and how it sits in space.
struct TpmsOptions {
  TpmsType type = TpmsType::Gyroid;
  /// type == Fourier: its terms (1 to kMaxFourierTerms, at least one not constant); else empty.
  std::vector<FourierTerm> terms = {};
  TpmsStyle style = TpmsStyle::Network;
  Vec3 cell = {2, 2, 2};  ///< cell size T per axis, mm (> 0)
  /// Network: offset of the solid's boundary, mm (+ = thinner). Sheet: the wall's centre lies
  /// at f̃ = −level, so a sheet between two levels C1 ≤ f̃ ≤ C2 (the "nesting TPMS of
  /// different C" of Yang et al. 2023, an asymmetric sheet) has level −(C1 + C2)/2 and
  /// thickness C2 − C1.
  double level = 0;
  double thickness = 0.3;  ///< sheet: wall thickness, mm (> 0)
  /// Raw: `level` and `thickness` are the seeds' C on f, not mm (no porosity target then).
  LevelUnit unit = LevelUnit::Millimetre;
  Vec3 origin = {0, 0, 0};  ///< where the phase is zero, mm (shifts the lattice)
  /// Orientation: the lattice's axes are R's columns (rotation_from_euler makes one).
  Mat3 rotation = {};
  /// Porosity to reach (0 < porosity < 1): when set, resolve_porosity() replaces `level`
  /// (network) or `thickness` (sheet) by the value that gives it, and fill() does so first.
  std::optional<double> porosity = {};
};

/// "primitive", "gyroid", "diamond", "iwp", "neovius", "frd", "lidinoid", "splitp", "fourier".
std::string_view tpms_type_name(TpmsType type);
/// Inverse of tpms_type_name (also accepts "schwarz-p" for primitive, "schwarz-d" for diamond,
/// "i-wp", "split-p").
/// @throws InputError  unknown name (the message lists the known ones)
TpmsType tpms_type_from_name(std::string_view name);
/// "network", "sheet".
std::string_view tpms_style_name(TpmsStyle style);
/// @throws InputError  neither "network" nor "sheet"
TpmsStyle tpms_style_from_name(std::string_view name);
/// "gyroid network", "iwp sheet", "fourier (6 terms) network", ...
std::string tpms_label(const TpmsOptions& options);

/// The `fourier` terms of options' f: a named type's formula written as a sum of cosines (the
/// same f to round-off), a fourier type's own terms as they are.
std::vector<FourierTerm> fourier_terms(const TpmsOptions& options);

/// Rotation about x by rx, then about the (fixed) y by ry, then about z by rz, in degrees:
/// R = Rz · Ry · Rx.
Mat3 rotation_from_euler(Vec3 degrees);
/// The angles rotation_from_euler takes to make `rotation` (a rotation matrix), degrees in
/// (−180, 180] (y in [−90, 90]).
Vec3 euler_from_rotation(const Mat3& rotation);

/// @throws InputError  a cell size or the thickness is not positive and finite, the level or
///                     origin is not finite, the rotation is not a rotation (orthonormal with
///                     determinant +1, to 1e-6), the porosity is not in (0, 1) or comes with
///                     raw levels, or the terms do not suit the type (a named type has none;
///                     fourier's are 1 to kMaxFourierTerms finite ones, waves within
///                     ±kMaxFourierWave, at least one not constant)
void require_valid(const TpmsOptions& options);

/// φ_TPMS as a field source (field.hpp), with a porosity solved first (resolve_porosity).
/// Without rotation its per-axis trigonometry is tabled once per grid line. Its bound is
/// twice the largest cell size (f̃ is clamped to ± the largest cell size).
/// @throws InputError  invalid options (require_valid)
FieldSource tpms_source(const TpmsOptions& options);

/// Samples of f̃ (mm; f itself for raw levels) over one unit cell at samples³ cell-centred
/// points, sorted ascending.
/// The solid fraction of a network with level ℓ is the share of samples below −ℓ, and of a
/// sheet of thickness t the share of |f̃| below t/2, so any porosity is read off by bisection
/// (a binary search) on these samples. Rotation and origin do not change it.
struct CellSamples {
  std::vector<float> values;    ///< f̃, sorted
  std::vector<float> absolute;  ///< |f̃|, sorted
};
/// @throws InputError  invalid options, or samples < 2
CellSamples sample_cell(const TpmsOptions& options, int samples = 96);

/// The level (network) or thickness (sheet), mm, whose solid fraction over the sampled cell is
/// 1 − porosity.
/// @throws InputError  porosity not in (0, 1)
double level_for_porosity(const CellSamples& cell, TpmsStyle style, double porosity);

/// `options` with `level` (network) or `thickness` (sheet) solved for options.porosity; the
/// porosity stays set, as a record of what was asked. Unchanged without a porosity.
TpmsOptions resolve_porosity(const TpmsOptions& options);

/// Solid volume fraction of the unclipped TPMS (1 − porosity), by sampling one unit cell at
/// samples³ cell-centred points.
double tpms_solid_fraction(const TpmsOptions& options, int samples = 96);

}  // namespace tpmsfill
