/// @file clean.hpp
/// @brief Stage "clean": a triangle soup as scanners and exporters write it, turned into one
/// whose generalized winding number means what a person means by "inside".
///
/// The winding number w(p) (Jacobson, Kavan, Sorkine-Hornung 2013) sums the signed solid
/// angles of the triangles: 1 inside a closed outward shell, 0 outside, and in between across
/// a hole. It is only as good as the orientation, so this stage
///  1. merges points with bit-identical coordinates (no tolerance),
///  2. drops triangles with a repeated corner, keeps one of each set of duplicate triangles
///     (the orientation most of the set has) and drops a set whose orientations cancel (two
///     shells glued along a face: the face is interior),
///  3. orients every piece (triangles joined through edges used by exactly two triangles)
///     consistently, keeping the orientation most of its area already has,
///  4. turns each piece outward: a piece bounding a negative volume (closed with its caps) is
///     reversed unless it lies inside an odd number of other pieces (a cavity's wall),
///  5. closes the holes that remain with caps: every border loop (edges whose uses do not
///     cancel) gets a fan of triangles from the loop's centroid, oriented so that model and
///     caps together bound a volume.
///
/// Caps are not part of the cleaned mesh; the winding number subtracts them again (see
/// classify.hpp). The stage is plain data and exact (orientation tests are CGAL Epick
/// predicates); the same input gives the same output whatever the thread count.
#pragma once

#include <cstdint>
#include <vector>

#include "tpmsfill/progress.hpp"
#include "tpmsfill/types.hpp"

namespace tpmsfill {

struct CleanOptions {
  /// Orient pieces consistently and outward (steps 3 and 4). Off: triangles keep the
  /// orientation they came with.
  bool orient = true;
  Progress* progress = nullptr;  ///< reports the stage's start; cannot cancel mid-way
};

/// What clean_soup() found and did. Triangle counts refer to the input soup.
struct CleanReport {
  std::uint64_t input_points = 0;
  std::uint64_t input_triangles = 0;
  std::uint64_t vertices = 0;                   ///< distinct referenced positions kept
  std::uint64_t merged_points = 0;              ///< points whose position an earlier one has
  std::uint64_t repeated_corner_triangles = 0;  ///< dropped
  std::uint64_t duplicate_triangles = 0;        ///< dropped: same corners as a kept triangle
  std::uint64_t cancelled_triangles = 0;        ///< dropped: duplicates whose orientations cancel
  std::uint64_t pieces = 0;                     ///< edge-connected pieces of the kept triangles
  std::uint64_t flipped_triangles = 0;          ///< reversed to agree with their piece (step 3)
  std::uint64_t reversed_pieces = 0;  ///< pieces reversed as a whole to face outward (step 4)
  std::uint64_t nested_pieces = 0;    ///< pieces inside an odd number of others (cavities)
  std::uint64_t border_edges = 0;     ///< edges whose uses do not cancel, after cleaning
  std::uint64_t holes = 0;            ///< border loops closed by caps
  std::uint64_t cap_triangles = 0;

  /// The output has the input's triangles, orientation and connectivity (up to merging
  /// bit-identical points): nothing was dropped or reversed.
  bool unchanged() const {
    return repeated_corner_triangles + duplicate_triangles + cancelled_triangles +
               flipped_triangles + reversed_pieces ==
           0;
  }
};

struct CleanResult {
  /// Kept triangles over the distinct referenced positions, oriented. Triangle order is the
  /// input's, without the dropped ones.
  TriangleSoup soup;
  /// Triangles closing soup's holes, with points of their own (loop corners and centroids).
  /// Empty when soup is closed: every edge's uses cancel.
  TriangleSoup caps;
  CleanReport report;
  /// Input indices of the kept triangles that `soup` turns round (steps 3 and 4), ascending:
  /// the faces that point the wrong way (what `check --picture` shows as flipped).
  std::vector<std::uint32_t> reversed;
};

/// Cleans `soup` as described above.
/// @param[in] soup  any triangle soup; indices must be in range (readers guarantee it)
/// @throws InputError  an index is out of range
CleanResult clean_soup(const TriangleSoup& soup, const CleanOptions& options = {});

}  // namespace tpmsfill
