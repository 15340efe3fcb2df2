/// @file repair.hpp
/// @brief Stage "repair": turn a defective triangle soup (a scan with holes, flipped faces,
/// unwelded or duplicated vertices, overlapping shells, self-intersections, non-manifold edges
/// and vertices, degenerate slivers, stray specks) into what check_mesh() accepts: a closed,
/// outward-oriented 2-manifold without self-intersections or degenerate faces.
///
/// Steps 1-6 (CGAL Polygon Mesh Processing, Epick) weld, orient, stitch, remove specks, fill
/// holes, resolve self-intersections and orient shells outward; step 7 checks the result
/// (check_mesh(), self-intersections searched) and its deviation from the input
/// (RepairDeviation), and when it is invalid or beyond the tolerance tries alpha wraps and a
/// volumetric route (7a-c): the result is the valid candidate nearest the input
/// (RepairReport::route, candidates, within_tolerance). CGAL's own warnings are caught into
/// RepairReport::warnings. Deterministic: the same soup and options give the same mesh,
/// whatever the thread count. The method, with the steps as options and report number them:
/// docs/method.md, section "Repairing a triangle soup".
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "tpmsfill/check.hpp"
#include "tpmsfill/io.hpp"
#include "tpmsfill/progress.hpp"
#include "tpmsfill/types.hpp"

namespace tpmsfill {

struct RepairOptions {
  /// Connected components (joined through edges, after step 2) whose area is below this
  /// fraction of the largest component's area are removed as stray specks. 0 keeps every
  /// component. In [0, 1).
  double min_component_fraction = 1e-3;
  bool fill_holes = true;  ///< step 4 (off: holes stay, so the mesh is repaired only by a wrap)
  bool fair_holes = true;  ///< fair hole patches (smooth); off: triangulate and refine only
  bool self_intersections = true;  ///< step 5 (off: self-intersecting meshes go to step 7)
  /// Step 7a and c. Alpha wrapping always yields a valid mesh but moves the surface: it lies
  /// about `offset` outside the input and does not enter cavities narrower than about `alpha`.
  /// The wrap's input is the mesh after hole filling, not the original soup: specks are gone
  /// (the original would wrap each of them) and holes are closed (an open surface would be
  /// wrapped on both sides, as a thin shell instead of a solid).
  bool wrap = true;
  /// Alpha (mm): the radius of the ball that carves space around the input. 0 = searched: the
  /// bounding-box diagonal of the wrapped mesh / 100 (details down to about 1% of the part),
  /// then / 200 and / 400 if the volumetric route too lies beyond the tolerance. A value > 0
  /// is the only wrap tried.
  double alpha = 0;
  /// Offset (mm): how far outside the input the wrap lies. 0 = alpha / 30 (CGAL's own
  /// default ratio), i.e. diagonal / 3000: 0.03 mm for a 100 mm part.
  double offset = 0;
  /// Step 7b, the volumetric route (needs fill_holes: it closes holes itself). Exact where the
  /// winding number decides, approximate by about a voxel where the surface is remade; parts
  /// thinner than a voxel may be lost, which the deviation then shows.
  bool volume = true;
  /// The volumetric route's voxel (mm): 0 = half the tolerance. Grids over 2^26 nodes are
  /// not sampled (the route is then reported as failed).
  double voxel = 0;
  /// Round the result's coordinates as the output file will hold them before the final check
  /// (rounding_for(format), io.hpp: Float for STL, ThreeMf for 3MF), so that the file holds
  /// exactly the mesh that was checked. If rounding breaks validity, the other routes run (their
  /// output is rounded and checked too).
  CoordinateRounding rounding = CoordinateRounding::None;
  /// Largest deviation from the input (RepairDeviation::worst) a repair may have to be
  /// accepted, mm. 0 = 1 % of the input's bounding-box diagonal.
  double tolerance = 0;
  Progress* progress = nullptr;
};

/// Distances between two surfaces, mm: over sample points (corners and centroids).
struct Deviation {
  double max = 0, p95 = 0;
};

/// How far a repaired mesh lies from its input. The input side is the input as cleaned (merged,
/// stitched, specks removed) with its hole patches, so a flat patch over a flat hole is no
/// deviation, and a patch is held to its hole by step 4's rule instead.
struct RepairDeviation {
  Deviation to_input;  ///< output → input surface (patches included)
  /// Input surface away from the hole patches → output. Unless the output is a wrap, samples
  /// inside the output are left out (surface a union of overlapping shells removed is no lost
  /// feature); a wrap encloses its input, so there every sample counts.
  Deviation from_input;
  /// (V_output − V_input) / V_input, 0 without an input volume. V is the summed signed volume's
  /// magnitude; where the input has several components or self-intersections (shells that may
  /// overlap or nest, which the sum counts twice), both are the winding-number solid's volume
  /// measured on one grid of rays (400 per bounding-box diagonal).
  double volume_change = 0;
  double bbox_growth = 0;  ///< mm, how far the output's box reaches beyond the input's
  /// mm: volume gained over the input's area (a filled cavity, which no distance sees once
  /// its walls are inside the solid; 0 when the volume shrank, as a union of shells does).
  double added_thickness = 0;
  /// The figure held against the tolerance: the largest of the two maxima, the growth and
  /// the added thickness.
  double worst() const;
};

/// One line of the repair log per defect class.
struct RepairAction {
  std::string defect;       ///< e.g. "holes"
  std::uint64_t found = 0;  ///< how many the step found (in its own unit, named in `defect`)
  std::string action;       ///< what was done, one phrase ("" when nothing was found)
  std::uint64_t fixed = 0;  ///< of those, how many were resolved by the step
};

/// One route tried in step 7 (the repair steps themselves first).
struct RepairCandidate {
  std::string route;             ///< "repair", "wrap" or "volume"
  double alpha = 0, offset = 0;  ///< wrap: its parameters, mm (0 otherwise)
  double voxel = 0;              ///< volume: the voxel, mm (0 otherwise)
  /// volume: the tolerance its marching-cubes surface was decimated within, mm (0: not
  /// decimated, when the surface alone used the tolerance up or decimation could not prove
  /// a valid result)
  double decimation = 0;
  std::uint64_t triangles = 0;  ///< of its mesh
  bool valid = false;           ///< its mesh passes check_mesh()
  bool taken = false;           ///< its mesh is the result
  RepairDeviation deviation;    ///< when valid
  std::string failure;          ///< why it gave no valid mesh ("" when valid), one sentence
};

struct RepairReport {
  MeshCheck before;  ///< check_mesh() of the input (self-intersections searched)
  /// In pipeline order, always the same defect classes (found may be 0): "duplicate points",
  /// "degenerate triangles" (repeated or collinear corners), "duplicate triangles",
  /// "inconsistently oriented edges", "non-manifold edges", "non-manifold vertices" (in the
  /// input, plus those split after stitching), "coincident border edge pairs" (stitched),
  /// "small components", "holes", "self-intersecting triangle pairs" (after hole filling),
  /// "shells oriented inward". The first five count what check_mesh() found in the input.
  std::vector<RepairAction> actions;
  double min_component_fraction = 0;     ///< the option used
  double small_component_threshold = 0;  ///< mm^2: components with less area were removed
  std::uint64_t components = 0;          ///< edge-connected components before removal
  std::uint64_t holes_faired = 0;        ///< holes filled and faired (of the filled ones)
  std::uint64_t holes_flat = 0;          ///< planar holes filled flat (of the filled ones)
  /// Holes whose faired patch would have left its rim's box (+ a tenth of the rim's
  /// diameter): their refined, unfaired patch was kept.
  std::uint64_t fairing_undone = 0;
  /// Why routes other than the repair ran: check_mesh()'s problems with the repaired mesh
  /// (a CGAL failure first), or its deviation past the tolerance; empty when none ran.
  std::vector<std::string> unresolved;
  /// Times steps 1-6 ran again on the result because rounding it
  /// (RepairOptions::rounding) broke its validity (at most 2; then the other routes).
  std::uint64_t float_repasses = 0;
  /// The route whose mesh is the result: "repair", "wrap" or "volume"; "" when none gave a
  /// valid mesh (the result is then the repair's, not valid).
  std::string route;
  std::vector<RepairCandidate> candidates;  ///< every route tried, in the order tried
  bool wrapped = false;                     ///< route == "wrap"
  double alpha = 0;                         ///< mm, the wrap's (0 when not wrapped)
  double offset = 0;                        ///< mm, the wrap's (0 when not wrapped)
  double voxel = 0;              ///< mm, the volumetric route's (0 when route != "volume")
  MeshCheck after;               ///< check_mesh() of the result (self-intersections searched)
  double tolerance = 0;          ///< mm, the value used (RepairOptions::tolerance)
  RepairDeviation deviation;     ///< of the result
  bool within_tolerance = true;  ///< valid() and deviation.worst() <= tolerance
  /// Sentences for what the result does not say by itself: a wrap that filled cavities, a box
  /// that grew, CGAL's own warnings (translated), ... One sentence each.
  std::vector<std::string> warnings;

  /// after.valid(): the result is a closed, outward-oriented 2-manifold without
  /// self-intersections or degenerate faces.
  bool valid() const { return after.valid(); }
};

struct RepairResult {
  TriangleSoup mesh;  ///< the repaired mesh (valid when report.valid())
  RepairReport report;
};

/// Repairs `soup`.
/// @param[in] soup     any triangle soup, mm
/// @param[in] options  which steps run, specks threshold, wrap parameters
/// @return the repaired mesh (shared points, no unreferenced ones) and what was done. When
///         report.valid() is false (the wrap was off or failed) the mesh is the best repair
///         reached, not a valid one. The same surface in any order of points, triangles or
///         corners (the same mesh as STL, OBJ, PLY or OFF) gives the same result, point for
///         point: the steps start from the welded points in order of position.
/// @throws InputError  the soup has no triangles, none with three distinct corners, or an
///                     index out of range; an option is out of range (negative alpha or
///                     offset, fraction outside [0, 1))
/// @throws Cancelled   options.progress cancelled the job
/// @throws Error       internal: CGAL's oriented soup is not a polygon mesh
RepairResult repair_mesh(const TriangleSoup& soup, const RepairOptions& options = {});

/// The JSON object `tpmsfill repair --json` prints (2-space indent, keys in this order):
///
///   valid, problems (check_mesh's sentences for the result), warnings, within_tolerance,
///   tolerance (mm), deviation {to_input {max, p95}, from_input {max, p95} (mm),
///   volume_change (fraction), bbox_growth (mm), added_thickness (mm)}, route (null when none
///   gave a valid mesh), candidates: [{route, alpha, offset, voxel (mm; null where not that
///   route's), decimation (mm, null when not decimated), triangles, valid, taken, deviation (the
///   same object, or null), failure (null when valid)}], wrapped, alpha, offset (mm; null when not
///   wrapped), voxel (mm; null unless route is "volume"), unresolved (sentences that made the
///   other routes run), float_repasses, min_component_fraction,
///   small_component_threshold (mm^2), components, holes_faired, holes_flat, fairing_undone,
///   actions: [{defect, found, action, fixed}], before, after (each the object
///   to_json(MeshCheck) gives). Each field means what the RepairReport member of the same
///   name means.
std::string to_json(const RepairReport& report);

/// The report as the CLI prints it: one line per defect class found, thresholds, the wrap's
/// alpha and offset, and the final verdict with its problems.
std::string to_text(const RepairReport& report);

}  // namespace tpmsfill
