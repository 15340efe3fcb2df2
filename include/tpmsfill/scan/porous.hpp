/// @file porous.hpp
/// @brief Stage "porous": porous structures from a fitted field C (bspline.hpp) and its
/// threshold fields, as a field source (field.hpp) that fill() clips to a model like a TPMS.
///
///  - Solid type  Ω = { t1 ≤ C ≤ t2 }:  φ = max(t1 − C, C − t2) / |∇C|, in mm.
///    t1 = −∞ gives the network-like C ≤ t2; with an unsigned (scanned-surface) C, t1 = 0 and
///    t2 = r give the scan thickened to a shell.
///  - Surface type S = { C = t0 }: the open surface (porous_surface_mesh), or a printable sheet
///    |C − t0| / |∇C| ≤ thickness / 2.
/// Dividing by |∇C| (in mm, through the placement) turns value units into a first-order
/// distance, so marching cubes places vertices well and the band's mm widths mean mm.
///
/// Placement of the unit cube [0, 1]³ in a model: stretched over a box (the model's bounding
/// box, or the structure's own size from its origin), or tiled with the structure's physical
/// size as the cell (u = frac(x / Lx); seams unless the field is periodic).
///
/// Porosity (1 − solid share of the unit cube) is solved in closed form from sorted samples of
/// the cube, as level_for_porosity does for TPMS: a solid is widened or narrowed by one offset
/// δ on its finite thresholds (t1 − δ, t2 + δ), a sheet by its thickness.
#pragma once

#include <array>
#include <cstdint>
#include <limits>
#include <optional>
#include <string>
#include <string_view>

#include "tpmsfill/field.hpp"
#include "tpmsfill/io/volume.hpp"
#include "tpmsfill/scan/bspline.hpp"
#include "tpmsfill/types.hpp"

namespace tpmsfill {

enum class StructureType {
  Solid,    ///< t1 ≤ C ≤ t2
  Surface,  ///< C = t0 (a sheet of `sheet_thickness`, or the open surface)
};

enum class Placement {
  Stretch,  ///< the unit cube stretched over the model's box (or the structure's size)
  Tile,     ///< repeated with the structure's size as the cell
};

/// A threshold t0, t1 or t2: a constant (±∞ allowed for t1 and t2: that side is open) or a
/// B-spline of its own over the unit cube, usually small (claim 6 of Lin & Gao's patent).
struct Threshold {
  double constant = 0;
  std::optional<BSplineVolume> spline = {};
};

/// A structure as an ITDF file stores it (itdf.hpp).
struct PorousStructure {
  BSplineVolume field;  ///< C over the unit cube
  FieldSign sign = FieldSign::Unknown;
  StructureType type = StructureType::Solid;
  Threshold t1{-std::numeric_limits<double>::infinity()}, t2{0}, t0{0};
  double sheet_thickness = 0;  ///< surface type: mm; 0 = the open surface (not printable)
  /// Physical size of the unit cube, mm (all 0: none; it is then stretched over the model).
  std::array<double, 3> size{};
  Placement placement = Placement::Stretch;
};

/// A threshold from its own discrete grid (claim 6 of Lin & Gao's patent: a w1 × h1 × d1
/// field of the unit cube, independent of C's grid), fitted as C is with `counts`
/// coefficients per axis (at most the grid's cells; thresholds vary slowly, so a few
/// suffice).
/// @throws InputError  as fit_bspline
Threshold fitted_threshold(const ScalarVolume& grid, std::array<int, 3> counts);

/// A threshold's value at (u, v, w) of the unit cube.
double threshold_value(const Threshold& t, double u, double v, double w);

/// @throws InputError  a spline with bad counts, knots or coefficients (not finite); a threshold
///                     spline's value not finite; a solid with t1 > t2 as constants or both
///                     infinite, or t2 = −∞; a surface with an infinite t0 or a negative or
///                     non-finite thickness; a negative or non-finite size, or a size partly
///                     zero; tile placement without a size
void require_valid(const PorousStructure& structure);

/// Where the unit cube goes: u = (x − origin.x) / extent.x (stretch), or its fractional part
/// (tile). Each axis separately, so a grid's rows stay separable.
struct UnitCubeMap {
  Vec3 origin{};
  std::array<double, 3> extent{1, 1, 1};  ///< mm (> 0)
  bool tile = false;
};

/// The map for a structure placed in `model` (a box, mm): Tile → cells of the structure's
/// size from the box's lower corner; Stretch → the box itself (a stored size is then only
/// what `field mesh` uses when it is given no box).
UnitCubeMap unit_cube_map(const PorousStructure& structure, const Box3& model);

/// The structure's field φ (mm, solid where φ < 0) under `map`, clamped to ±bound with bound
/// twice the largest knot span in mm (|∇C| can vanish far from the structure). A surface with
/// no thickness gives the signed (C − t0)/|∇C|, whose zero set is the open surface.
/// @throws InputError  require_valid fails
FieldSource porous_source(const PorousStructure& structure, const UnitCubeMap& map);

/// The open surface C = t0 of a surface-type structure stretched over `box` (mm): marching
/// cubes of (C − t0)/|∇C| on a grid of `voxel` mm whose outer nodes lie on the box's faces, so
/// the surface ends there. Its validation (validate.hpp) must show a 2-manifold, consistently
/// oriented, without degenerate or intersecting triangles; border edges are allowed.
struct OpenSurface {
  TriangleSoup mesh;
  std::uint64_t border_edges = 0, components = 0;
  double area = 0;  ///< mm²
};
/// @throws InputError       not a surface type, an empty box, voxel <= 0
/// @throws ValidationError  the surface is not a 2-manifold with boundary (a bug)
OpenSurface porous_surface_mesh(const PorousStructure& structure, const Box3& box, double voxel);

/// The solid share of the unit cube, sampled at the centres of `samples`³ cells; `extent` is
/// the cube's size in mm where it is placed (it matters to sheets only, through |∇C| in mm).
/// An open surface has no volume: 0.
double porous_solid_share(const PorousStructure& structure, std::array<double, 3> extent,
                          int samples = 64);

/// The structure with its thresholds (solid) or thickness (surface) set so that its porosity
/// (1 − porous_solid_share) is `porosity`: solid: t1 − δ and t2 + δ on the finite ones, δ
/// the (1 − porosity) quantile of max(t1 − C, C − t2) over the samples; surface: thickness = 2
/// × that quantile of |C − t0| / |∇C|.
/// @throws InputError  porosity outside (0, 1), an invalid structure
PorousStructure with_porosity(const PorousStructure& structure, double porosity,
                              std::array<double, 3> extent, int samples = 64);

/// "scanned-field solid t1 <= C <= t2 (t1 = -0.02, t2 = 0.03; 24x24x24 cubic)", ...
std::string structure_label(const PorousStructure& structure);

std::string_view structure_type_name(StructureType type);  ///< "solid", "surface"
std::string_view placement_name(Placement placement);      ///< "stretch", "tile"
/// @throws InputError  unknown name (the message lists the known ones)
StructureType structure_type_from_name(std::string_view name);
Placement placement_from_name(std::string_view name);

}  // namespace tpmsfill
