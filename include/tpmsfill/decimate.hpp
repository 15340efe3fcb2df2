/// @file decimate.hpp
/// @brief Stage "decimate": fewer triangles for a valid closed 2-manifold (a filled lattice),
/// within a distance tolerance of it, and still valid.
///
/// Guarantees: every point of the result lies within `tolerance` of the input and every point
/// of the input within `tolerance` of the result (a proven bound on the symmetric Hausdorff
/// distance, up to double round-off, about 1e-15 of the coordinates); the result passes
/// validate_mesh() (closed, 2-manifold, outward, no degenerate faces, no duplicate points, no
/// self-intersections), or, when no round gives a valid mesh, the input is returned unchanged
/// with a warning: an invalid mesh is never returned. The result does not depend on the thread
/// count. The method: docs/method.md, section "Decimation that keeps the proof".
#pragma once

#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

#include "tpmsfill/io.hpp"
#include "tpmsfill/mesh/validate.hpp"
#include "tpmsfill/progress.hpp"
#include "tpmsfill/types.hpp"

namespace tpmsfill {

struct DecimateOptions {
  /// Largest distance between the result and the input, both ways (a bound on the Hausdorff
  /// distance), mm (> 0). For a marching-cubes lattice, voxel/4 keeps the result well inside
  /// the voxel's own error.
  double tolerance = 0;
  /// Stop once the result has at most this many triangles; 0: collapse as far as the
  /// tolerance and validity allow.
  std::uint64_t target_triangles = 0;
  /// Round the input's points (before bit-identical ones are merged) and every new vertex as
  /// the output file will hold them (rounding_for(format), io.hpp: Float for STL, ThreeMf for
  /// 3MF), so that the file holds exactly the mesh that was validated. None: the input's points
  /// are kept and new vertices are doubles.
  CoordinateRounding rounding = CoordinateRounding::Float;
  /// No collapse may make an edge longer than this, mm; 0: no limit. The proof's work per
  /// collapse grows with the input triangles under a result triangle, so on large flat areas
  /// (a remade CAD part: thousands of marching-cubes triangles in one plane) a limit keeps the
  /// decimation near linear; it also keeps triangles from spanning a whole face.
  double max_edge_length = 0;
  /// Simplifications from the input, at most, while locking where the result was invalid.
  int max_rounds = 8;
  bool self_intersections = true;  ///< validate with the self-intersection search (exact)
  Progress* progress = nullptr;
};

/// Why the edge collapse stopped.
enum class DecimateStop {
  Tolerance,  ///< no edge is left whose collapse keeps the distance bound and flips nothing
  Target,     ///< DecimateOptions::target_triangles reached
  Unchanged,  ///< no round gave a valid mesh: the input is returned as it came
};

/// "tolerance", "target", "unchanged".
const char* decimate_stop_name(DecimateStop stop);

/// Distances between the input and the result, mm, over sample points: on each triangle the
/// barycentric grid of order 4 (15 points) and the centroid, evenly thinned to about 2,000,000
/// points on large meshes, each measured to the nearest point of the other surface (CGAL's AABB
/// tree). A sampled maximum is a lower bound of the true one-sided Hausdorff distance.
struct DecimateDistance {
  double to_input = 0;        ///< result → input, max over the result's samples
  double to_input_p95 = 0;    ///< 95th percentile of the same
  double from_input = 0;      ///< input → result, max over the input's samples
  double from_input_p95 = 0;  ///< 95th percentile of the same
  /// The two maxima's larger: the measured (sampled) symmetric Hausdorff distance.
  double hausdorff() const { return to_input > from_input ? to_input : from_input; }
};

struct DecimateReport {
  double tolerance = 0;                ///< mm, the value used
  std::uint64_t target_triangles = 0;  ///< the value used (0: none)
  std::uint64_t triangles_before = 0;  ///< of the input
  std::uint64_t triangles_after = 0;   ///< of the result
  std::uint64_t vertices_before = 0;   ///< referenced, after merging bit-identical points
  std::uint64_t vertices_after = 0;
  std::uint64_t merged_points = 0;  ///< input points merged into an earlier identical one
  double volume_before = 0;         ///< signed, mm^3
  double volume_after = 0;          ///< signed, mm^3
  double area_before = 0;           ///< mm^2
  double area_after = 0;            ///< mm^2
  /// Proven bound on the symmetric Hausdorff distance between the result and the input: the
  /// tolerance; 0 when the result is the input unchanged.
  double hausdorff_bound = 0;
  DecimateDistance distance;          ///< measured (see DecimateDistance)
  int rounds = 0;                     ///< simplifications run (1 when the first was valid)
  std::uint64_t locked_vertices = 0;  ///< input vertices locked in the last round
  /// Self-intersecting pairs found in each round's result before the last (the reason for
  /// the next round), in round order.
  std::vector<std::uint64_t> invalid_pairs;
  DecimateStop stop = DecimateStop::Tolerance;
  double seconds = 0;                 ///< wall time of the whole stage
  MeshValidity validation;            ///< of the result
  std::vector<std::string> warnings;  ///< one sentence each

  /// (V_after − V_before) / |V_before|.
  double volume_change() const {
    return volume_before != 0 ? (volume_after - volume_before) / std::abs(volume_before) : 0.0;
  }
  /// triangles_before / triangles_after (1 when unchanged).
  double reduction() const {
    return triangles_after > 0
               ? static_cast<double>(triangles_before) / static_cast<double>(triangles_after)
               : 1.0;
  }
};

struct DecimateResult {
  TriangleSoup mesh;  ///< the decimated mesh (valid), points compacted, no unreferenced ones
  DecimateReport report;
};

/// Decimates `mesh` within `options.tolerance`.
/// @param[in] mesh     a closed, outward 2-manifold without degenerate faces or
///                     self-intersections, mm (points with bit-identical coordinates are
///                     merged first, as check_mesh() does, so an STL's soup is fine)
/// @param[in] options  tolerance (mm), target, rounds
/// @return the decimated mesh (valid: report.validation.valid()) and the report
/// @throws InputError  tolerance not positive and finite, max_rounds < 1, max_edge_length
///                     negative or not finite, or the mesh (after
///                     merging) is not valid (the message gives validate_mesh()'s problems)
/// @throws Cancelled   options.progress said so
DecimateResult decimate(const TriangleSoup& mesh, const DecimateOptions& options);

/// The JSON object of a decimation (2-space indent, keys in this order): tolerance,
/// target_triangles (null without a target), triangles_before, triangles_after, reduction,
/// vertices_before, vertices_after, merged_points, volume_before, volume_after, volume_change
/// (fraction), area_before, area_after, hausdorff_bound (mm), hausdorff (mm, sampled),
/// to_input {max, p95}, from_input {max, p95} (mm), rounds, locked_vertices, invalid_pairs,
/// stop, seconds, valid, problems, warnings. Each field means what the DecimateReport member
/// of the same name means.
std::string to_json(const DecimateReport& report);

/// The report as the CLI prints it: a few aligned lines.
std::string to_text(const DecimateReport& report);

}  // namespace tpmsfill
