/// @file mc_tables.hpp
/// @brief Marching-cubes case table, built in code from a loop-linking rule (see mc_tables.cpp).
///
/// Cube numbering. Corner c sits at (c & 1, (c >> 1) & 1, (c >> 2) & 1). Edge e = 4·a + ub + 2·vb
/// runs along axis a from the corner with bit a = 0, bit u = ub and bit v = vb (u = (a + 1) % 3,
/// v = (a + 2) % 3) to the corner with bit a = 1. Face f = 2·a + s is the face at coordinate s
/// on axis a; its corners are listed counter-clockwise seen from outside the cube.
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "tpmsfill/sampling/marching_cubes.hpp"

namespace tpmsfill::detail {

/// Triangles of one cube for one corner configuration and one set of ambiguous-face decisions.
/// Triangle corners are slots: 0..11 the vertex on that cube edge, 12 + c the extra vertex of
/// centroid c (the mean of the edge vertices in centroid_edges[c]; it lies inside the cube).
struct McCase {
  std::uint8_t triangle_count = 0;
  std::uint8_t centroid_count = 0;
  std::array<std::uint16_t, 2> centroid_edges{};  ///< bit e: cube edge e is in that loop
  /// Centroid c's fan: triangles [fan_first[c], fan_first[c] + fan_size[c]), in loop order
  /// (triangle i and i + 1 share an edge, and so do the last and the first).
  std::array<std::uint8_t, 2> fan_first{}, fan_size{};
  std::array<std::array<std::uint8_t, 3>, 12> triangles{};
};

struct McTables {
  std::array<std::array<std::uint8_t, 4>, 6> face_corners{};  ///< counter-clockwise from outside
  std::array<std::array<std::uint8_t, 2>, 12> edge_corners{};
  /// Bit f set when face f is ambiguous in configuration `config` (bit c = corner c inside):
  /// its two inside corners sit on one diagonal.
  std::array<std::uint8_t, 256> ambiguous_faces{};
  /// Bit e set when cube edge e joins an inside and an outside corner in `config`.
  std::array<std::uint16_t, 256> crossed_edges{};
  /// cases[config | decisions << 8]; decisions bit f = 1: on ambiguous face f the two inside
  /// corners are connected (the segments cut off the outside corners). Bits of faces that are
  /// not ambiguous in `config` must be 0.
  std::vector<McCase> cases;
  /// Loops of each case as cube-edge lists in traversal order (for tests and documentation).
  std::vector<std::vector<std::vector<std::uint8_t>>> loops;
};

/// The tables, built once (thread-safe) on first use.
const McTables& mc_tables();

/// Whether `decisions` can come out of mc_case_key() for `config`. On the two checkerboard
/// configurations all six faces are ambiguous, and each pair of opposite faces compares the
/// same products (|inside values| P against |outside values| Q), so a pair with both faces
/// connected (P > Q) and a pair with both separated (P <= Q) never occur together.
bool mc_decisions_realizable(const McTables& tables, unsigned config, unsigned decisions);

/// What marching-cubes output is valid by, checked entry by entry over every realizable key of
/// `tables`; one sentence per violation (empty: the table holds them all). For each entry:
/// 1. the triangles use exactly the crossed edges, each triangle three distinct slots, and no
///    triangle has its three edge vertices on one cube face;
/// 2. a triangle edge whose two ends lie on edges of one cube face is a segment of that face
///    as the face rule makes it (mc_tables.cpp, step 1, from the face's corners and decision
///    alone), walked in its direction, and every such segment is one triangle's edge: the two
///    cubes sharing a face walk its segments in opposite directions;
/// 3. every other triangle edge is walked once each way within the entry;
/// 4. the triangles around each slot form one fan: for an edge vertex a path between its two
///    face segments, for a centroid a closed cycle (so the surface is a disk there);
/// 5. triangles joined through edges form pieces whose edge vertices are separated by a
///    plane from those of every other piece in the cube, for any positions on their edges;
/// 6. within a piece, two triangles that share no edge both lie in one centroid's fan.
/// Together with vertices strictly inside their edges (centroids inside their cubes) and a
/// grid border that is all outside, these make the mesh closed, oriented, manifold, without
/// degenerate triangles or repeated points, and free of intersections but possibly between
/// two triangles of one fan that share only its centroid (marching_cubes.hpp says why).
std::vector<std::string> mc_table_violations(const McTables& tables);

/// marching_cubes_proved() by `tables` (a test hands in a broken copy, whose mesh must then go
/// unproved); the real table's violations are computed once, any other's on every call.
ProvedMesh marching_cubes_proved(const Field& field, const McOptions& options,
                                 const McTables& tables);

/// The key into McTables::cases of one cube: `config` (bit c: corner c inside) plus the
/// asymptotic decider on each ambiguous face, inside corners (a, c) connected when
/// (a − iso)(c − iso) > (b − iso)(d − iso). Each difference, offset(corner) = value − iso, is
/// rounded to float once, the same way for every cube (its sign kept: two distinct floats never
/// differ by less than the smallest subnormal), and the product of two floats is exact in
/// double, so the comparison is exact: both cubes sharing a face agree, and on the checkerboard
/// configurations opposite faces cannot contradict each other (see the table test). A tie
/// counts as separated: the saddle at the iso-value is outside, as corners at it are.
template <class Offset>
unsigned mc_case_key(const McTables& tables, unsigned config, const Offset& offset) {
  unsigned decisions = 0;
  for (unsigned amb = tables.ambiguous_faces[config]; amb; amb &= amb - 1) {
    const int f = __builtin_ctz(amb);
    const auto& q = tables.face_corners[f];
    double d[4];
    for (int i = 0; i < 4; ++i) d[i] = static_cast<float>(offset(q[i]));
    const bool first_diagonal_inside = (config >> q[0] & 1) != 0;
    const double in = first_diagonal_inside ? d[0] * d[2] : d[1] * d[3];
    const double out = first_diagonal_inside ? d[1] * d[3] : d[0] * d[2];
    if (in > out) decisions |= 1u << f;
  }
  return config | decisions << 8;
}

}  // namespace tpmsfill::detail
