/// @file tpms.hpp
/// @brief Stage "tpms": the lattice's implicit field φ_TPMS in millimetres (paper eq. 1–4).
///
/// With X = 2πx/Tx, Y = 2πy/Ty, Z = 2πz/Tz (T = cell size per axis) each type has a
/// periodic function f (table in docs/method.md and DESIGN.md). f is not a distance, so
/// tpmsfill uses f̃ = f/|∇f|, a first-order distance in mm, clamped to ±max(T) where |∇f|
/// vanishes away from the surface. Then:
///   network:  φ_TPMS = f̃ + level          (solid where φ < 0; level in mm, 0 = the minimal
///   surface) sheet:    φ_TPMS = |f̃| − thickness/2  (solid within thickness/2 of the minimal
///   surface)
/// Evaluation is separable: the per-axis sines and cosines are computed once per grid line,
/// so a sample costs a few multiply-adds, a square root and a division.
#pragma once

#include <string>
#include <string_view>

#include "tpmsfill/progress.hpp"
#include "tpmsfill/types.hpp"

namespace tpmsfill {

/// Triply periodic minimal surface types. The evaluation table is indexed by this enum and
/// takes per-axis cos/sin of X and 2X, so the other types of DESIGN.md's table fit as rows.
enum class Lattice { Gyroid, Primitive, Diamond };

/// Network: the solid is one side of the level set. Sheet: a shell around the surface.
enum class LatticeStyle { Network, Sheet };

struct TpmsOptions {
  Lattice type = Lattice::Gyroid;
  LatticeStyle style = LatticeStyle::Network;
  Vec3 cell = {2, 2, 2};    ///< cell size T per axis, mm (> 0)
  double level = 0;         ///< network: offset of the solid's boundary, mm (+ = thinner)
  double thickness = 0.3;   ///< sheet: wall thickness, mm (> 0)
  Vec3 origin = {0, 0, 0};  ///< where the phase is zero, mm (shifts the lattice)
};

/// "gyroid", "primitive", "diamond".
std::string_view lattice_name(Lattice type);
/// Inverse of lattice_name (also accepts "schwarz-p" for primitive).
/// @throws InputError  unknown name (the message lists the known ones)
Lattice lattice_from_name(std::string_view name);

/// @throws InputError  a cell size or the thickness is not positive and finite, or the level
///                     is not finite
void validate(const TpmsOptions& options);

/// φ_TPMS at one point, mm.
float tpms_value(Vec3 p, const TpmsOptions& options);

/// Bounds of φ_TPMS over all space (from the clamp), mm: every value lies in [low, high].
struct FieldRange {
  float low = 0, high = 0;
};
FieldRange tpms_range(const TpmsOptions& options);

/// φ_TPMS at every node of `grid` (same values as tpms_value at Grid::node()).
Field tpms_field(const Grid& grid, const TpmsOptions& options, Progress* progress = nullptr);

/// Solid volume fraction of the unclipped lattice (1 − porosity), by sampling one unit cell
/// at samples³ cell-centred points.
double lattice_solid_fraction(const TpmsOptions& options, int samples = 96);

}  // namespace tpmsfill
