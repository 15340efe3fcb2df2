/// @file design.hpp
/// @brief Stage "design": what the lattice is made of. A base TPMS (tpms.hpp) whose porosity,
/// level, thickness and cell size vary in space, other TPMS blended in over regions, or a
/// field source the caller supplies in place of the base.
///
/// A design is one implementation of the field seam (field.hpp): design_source() evaluates it
/// to one field φ_L (mm, solid where φ_L < 0), which compose.hpp clips to the model as it
/// clips any source:
///  - Grading: a quantity follows a Ramp (linear along a direction, radial from an axis or a
///    point, or by depth below the model's surface). Cell-size grading warps the coordinates
///    so that the phase is the integral of 1/T along the ramp: cells stretch, none is torn.
///    Depth and volume ramps give no direction to integrate along: there the design is made
///    at a ladder of fixed cell sizes (neighbours at most 1.2× apart) and each node mixes the
///    two rungs around its size, linearly in log size.
///  - Blending: φ_L = (1 − μ)·φ_base + μ·φ_k for each Blend in turn, μ rising from 0 to 1
///    across a transition band of the given width centred on the region's boundary (a sigmoid,
///    or the Beta growth function of Yin et al. 2003 as used by Yang et al. 2023).
///  - A custom source replaces the base TPMS; blends still apply on top of it.
#pragma once

#include <array>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "tpmsfill/field.hpp"
#include "tpmsfill/io/volume.hpp"
#include "tpmsfill/lattice/tpms.hpp"
#include "tpmsfill/scan/porous.hpp"
#include "tpmsfill/types.hpp"

namespace tpmsfill {

/// Where a graded quantity changes.
enum class RampShape {
  Linear,  ///< along `axis` from `point`: t = (p − point)·axis/|axis|
  Radial,  ///< distance from the line through `point` along `axis` (zero axis: from `point`)
  Depth,   ///< depth below the model's surface (0 on it), from the occupancy's voxel distance
  /// the value of a scalar volume at the point (`volume`, trilinear, the nearest border value
  /// beyond it): a CT's intensity, or a fitted solid's material M(G⁻¹(p)) sampled by
  /// material_volume.hpp, so that a lattice follows a density or stiffness map
  Volume,
};

/// A value that goes linearly from `start` at ramp coordinate `from` to `end` at `to` (mm;
/// the volume's own values for a Volume ramp), constant beyond. Unset positions are resolved
/// from the model's bounding box by resolve_design(): the ramp then spans the model (linear:
/// the box's extent along the axis; radial: 0 at the box centre to the farthest corner; depth:
/// 0 to a quarter of the box's smallest side; volume: the volume's range over the box).
struct Ramp {
  RampShape shape = RampShape::Linear;
  std::optional<Vec3> point = {};  ///< unset: the box centre (radial) or the origin (linear)
  Vec3 axis = {0, 0, 1};           ///< direction (linear) or axis (radial; zero = spherical)
  std::optional<double> from = {}, to = {};
  double start = 0, end = 0;  ///< the values at `from` and `to`
  /// Volume ramps: the values, in mm (a physical size), shared by copies of the design.
  std::shared_ptr<const ScalarVolume> volume = {};
  std::string volume_file = {};  ///< the file it was read from ("" none): for recipes, labels
};

/// What a Grading varies.
enum class Graded {
  Porosity,   ///< of every layer, through its CellSamples (level or thickness follows)
  Level,      ///< network level, mm
  Thickness,  ///< sheet thickness, mm
  Cell,       ///< cell size, mm (scales the base cell: local cell = cell × value / cell.x)
};

struct Grading {
  Graded what = Graded::Porosity;
  Ramp ramp = {};
};

/// A region of space, for blending: inside it the blended lattice takes over.
enum class RegionShape {
  HalfSpace,  ///< the side of the plane through `point` that `axis` points to
  Slab,       ///< within size/2 of the plane through `point` normal to `axis`
  Sphere,     ///< within `size` (radius) of `point`
  Cylinder,   ///< within `size` (radius) of the line through `point` along `axis`
  Polygon,    ///< a ring region: inside `loop`, drawn in the plane of `u` and `v`
};

/// How a polygon region's rings follow its outline (the "tangent-connected" offsets of
/// Yang et al. 2023 are mitered).
enum class RingJoin {
  Round,  ///< the Euclidean distance to the outline: rounded corners, C1 off the medial axis
  Miter,  ///< mitered offsets, straight lines meeting on the corners' bisectors (simple outlines)
};

struct Region {
  RegionShape shape = RegionShape::HalfSpace;
  Vec3 point = {0, 0, 0};
  Vec3 axis = {0, 0, 1};
  double size = 0;  ///< slab thickness or radius, mm
  /// Polygon: the outline's corners (at least 3, a simple polygon) in mm along `u` and `v`
  /// from `point`; the region is the prism over it along u × v. The transition runs from the
  /// outer ring, `outer` mm outside the outline, to the inner ring, `inner` mm inside it (both
  /// signed, so the band need not straddle the outline; inner + outer > 0); the blend's
  /// width is not used, and a Beta peak is measured from the inner ring (Yang et al. 2023).
  std::vector<std::array<double, 2>> loop = {};
  Vec3 u = {1, 0, 0}, v = {0, 1, 0};  ///< the outline's plane (v is made orthogonal to u)
  double inner = 1, outer = 1;
  RingJoin join = RingJoin::Round;
};

/// How μ rises across the transition band (t = 0 at its outer edge, 1 at its inner edge).
enum class Transition {
  Sigmoid,  ///< logistic 1/(1 + e^{−10(t − ½)}), rescaled to exactly 0 and 1 at the edges
  Beta,     ///< Beta growth (1 + (1 − t)/(1 − t_m))·t^{1/(1 − t_m)}, t_m = `peak`
};

struct Blend {
  TpmsOptions tpms = {};  ///< what grows in the region (its own type, style, level, porosity...)
  Region region = {};
  double width = 1;  ///< transition width across the region's boundary, mm (> 0)
  Transition transition = Transition::Sigmoid;
  double peak = 0.5;  ///< Beta: where μ grows fastest, 0 < peak < 1 (0.5 is smoothstep)
};

/// The most blends a design may hold: each is evaluated at every sample, so 100,000 of them ran
/// for minutes before a single voxel was meshed.
inline constexpr std::size_t kMaxBlends = 64;

/// A base TPMS (the TpmsOptions part) with grading and blends, or a caller's field in its place.
struct LatticeDesign : TpmsOptions {
  std::vector<Grading> grading = {};  ///< at most one per Graded quantity
  std::vector<Blend> blends = {};     ///< applied in order
  /// Replaces the base TPMS when set: any field source (field.hpp), e.g. function_source() of
  /// a strut network's distance. Grading applies to TPMS only; blends still apply on top.
  FieldSource custom = {};
  /// A porous structure fitted to a scanned field (porous.hpp), in place of the base TPMS:
  /// resolve_design places it over the model's box (or tiles it) and sets `custom` from it,
  /// after solving `porosity` on it when that is set. Where `custom` is already set, it wins.
  std::optional<PorousStructure> structure = {};
  std::string structure_file = {};  ///< the ITDF file it was read from ("" none): for recipes
};

/// @throws InputError  a layer fails require_valid(TpmsOptions), a quantity is graded twice,
///                     porosity and level/thickness are both graded, a level grading on a
///                     sheet or a thickness grading on a network, a non-positive cell
///                     value, a zero ramp axis for linear ramps, a volume ramp without a valid
///                     volume in mm, a blend width ≤ 0, peak ∉ (0, 1), or a region of
///                     non-positive size
void require_valid(const LatticeDesign& design);

/// The design with everything fill() needs fixed: porosities solved into levels or
/// thicknesses (resolve_porosity, per layer) and unset ramp positions taken from `model` (the
/// model's bounding box). What the report echoes.
LatticeDesign resolve_design(const LatticeDesign& design, const Box3& model);

/// The design as a field source (field.hpp): φ_L, with porosities solved (resolve_design;
/// ramps need their positions set, which resolve_design against the model does). Its bound
/// is twice the largest cell size of its layers.
/// @param depth  depth below the model's surface at every node of the grid it will be
///               evaluated on, mm (Depth ramps only; voxel.hpp's distance_transform of the
///               occupancy); it must outlive the source
/// @throws InputError  invalid design, a ramp without positions; when bound to a grid, a Depth
///                     ramp without `depth` or a `depth` on another grid
FieldSource design_source(const LatticeDesign& design, const Field* depth = nullptr);

/// A porous structure's threshold (porous.hpp) that follows `ramp` across its unit cube placed
/// with `size` (mm; positions unset span the cube as resolve_design spans a model's box):
/// sampled at 16³ cell centres and fitted with `counts`³ coefficients (a linear ramp is
/// reproduced exactly between its ends).
/// @throws InputError  a depth ramp (a structure has no surface to be deep below), counts
///                     outside 2 to 16, a size not positive
Threshold ramp_threshold(const Ramp& ramp, std::array<double, 3> size, int counts = 6);

/// The ramp with its unset point, from and to taken from `model`'s box, as resolve_design()
/// does (linear: the box's extent along the axis; radial: 0 at the box centre to the farthest
/// corner; depth: 0 to a quarter of the smallest side). `what` names the ramp in errors.
/// @throws InputError  positions unset and an empty model, from == to
Ramp resolve_ramp(Ramp ramp, const Box3& model, const std::string& what = "ramp");

/// A ramp's coordinate at p: mm along its axis or from its centre, or the volume's value
/// there (a point unset counts as the origin).
/// @throws InputError  a depth ramp (depth needs the model's occupancy), a volume ramp without
///                     its volume
double ramp_coordinate(const Ramp& ramp, Vec3 p);

/// A resolved ramp's value at p: start at ramp coordinate from, end at to, constant beyond.
/// @throws InputError  as ramp_coordinate
double ramp_value(const Ramp& resolved, Vec3 p);

/// Names used by the CLI and recipes: "porosity", "level", "thickness", "cell"; "linear",
/// "radial", "depth"; "half-space", "slab", "sphere", "cylinder"; "sigmoid", "beta".
std::string_view graded_name(Graded what);
/// "porosity 0.5 to 0.8 by depth (0 to 7.5 mm)", "cell 2 to 4 along x (0 to 60 mm)", ...
std::string grading_label(const Grading& grading);
std::string_view ramp_name(RampShape shape);
std::string_view region_name(RegionShape shape);
std::string_view transition_name(Transition transition);
std::string_view ring_join_name(RingJoin join);  ///< "round", "miter"
/// @throws InputError  unknown name (the message lists the known ones)
Graded graded_from_name(std::string_view name);
RampShape ramp_from_name(std::string_view name);
RegionShape region_from_name(std::string_view name);
Transition transition_from_name(std::string_view name);
RingJoin ring_join_from_name(std::string_view name);

}  // namespace tpmsfill
