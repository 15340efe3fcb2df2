/// @file marching_cubes.hpp
/// @brief Stage "marching cubes": the iso-surface of a sampled field as an indexed triangle
/// mesh (Lorensen & Cline 1987, written here).
///
/// Guarantees, for any field whose nodes on the grid's six faces are all above the iso-value
/// and which has no node exactly at the iso-value:
/// - the mesh is a closed 2-manifold: ambiguous cube faces are resolved by the asymptotic
///   decider (Nielson & Hamann 1991), which depends only on the face's four values, so the two
///   cubes sharing a face always agree;
/// - vertices lie on grid edges and belong to them: one vertex per crossed edge, shared by
///   every triangle using that edge (no welding tolerance anywhere), strictly inside the edge
///   (the edge parameter is clamped to [1e-4, 1 - 1e-4]); the two coordinates across the edge
///   are exactly Grid::coordinate() values. A cube whose surface piece is bounded by five or
///   more edge vertices also gets one vertex at their centroid, strictly inside the cube, and
///   the piece is a fan around it. With McOptions::rounding, all of this holds of the grid
///   and the points as the file holds them (a grid too fine for that is refused);
/// - the surface meets each cube face only in that face's segments (never a chord lying in a
///   face), so triangles of neighbouring cubes meet only along shared edges and vertices;
/// - triangles are oriented outward: their normals point from the solid (values below the
///   iso-value) to the outside;
/// - no degenerate triangle, and no two triangles intersect except along shared edges and
///   vertices;
/// - the output (point and triangle order) is the same whatever the thread count.
/// Nodes exactly at the iso-value are treated as outside (above).
#pragma once

#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "tpmsfill/field.hpp"
#include "tpmsfill/io.hpp"
#include "tpmsfill/mesh/validate.hpp"
#include "tpmsfill/progress.hpp"
#include "tpmsfill/types.hpp"

namespace tpmsfill {

namespace detail {
class RoundedGrid;
}

struct McOptions {
  float iso = 0.0f;              ///< iso-value; the solid is where field < iso
  Progress* progress = nullptr;  ///< reports per slab of cells; may cancel
  /// Points come out as a file with this rounding holds them (rounding_for(format), io.hpp),
  /// each edge vertex strictly inside its edge and each centroid strictly inside its cube of
  /// the grid as rounded, so the guarantees below hold for the file wherever the grid sits.
  /// None: doubles, edge parameters clamped to [1e-4, 1 - 1e-4].
  CoordinateRounding rounding = CoordinateRounding::None;
};

/// Extracts the iso-surface of `field`. Points are numbered by layer of grid nodes along z
/// (edge vertices, then that layer's cube centroids), triangles by layer of cells.
/// Memory beyond the output: two layers of vertex ids per worker thread (24·dims[0]·dims[1]
/// bytes) and a few counters per layer.
/// @throws InputError  when field.values.size() != field.grid.node_count(), a grid dimension
///                     is below 2, or the mesh would need 2^32 or more points
/// @throws Cancelled   when options.progress says so
TriangleSoup marching_cubes(const Field& field, const McOptions& options = {});

/// A marching-cubes mesh and what its construction proves of it.
struct ProvedMesh {
  TriangleSoup mesh;
  /// For validate_mesh() (ValidateOptions::proof): the guarantees above hold of `mesh`, each
  /// assumption checked, with no triangle pair left to test. Unset when an assumption failed
  /// (`unproved` says which): then validate the mesh by searching it.
  std::optional<ConstructionProof> proof;
  std::string unproved;
};

/// marching_cubes(field, options), bit for bit, with the proof of its validity. What is
/// checked:
/// - the case table keeps the rules mc_table_violations() (sampling/mc_tables.hpp) lists,
///   over every entry, once per process;
/// - every vertex, as stored and as the file holds it, lies strictly inside its grid edge (a
///   centroid, inside its cube), and the grid's nodes as held increase strictly;
/// - every node on the grid's border is outside.
/// Why that is enough. A triangle lies in its cube's closed box, so triangles of cubes that
/// share nothing cannot meet. Across a shared face both cubes cut it along the same segments
/// (the same edge vertices by id, the same exact decision), and a triangle meets the face only
/// in one of those segments or in one vertex; across an edge, only in its vertex; at a corner,
/// not at all. So triangles of different cubes meet only in shared vertices and edges. Within
/// a cube, pieces are separated by planes. Within a piece: a quad's two triangles lie on either
/// side of their diagonal in any plane holding both (the quad's corners lie on the boundary of
/// the convex polygon that plane cuts from the cube, in order); a fan's triangles are the cones
/// from its centroid, strictly inside the cube, over the loop's segments on the cube's
/// surface, and every ray from an inner point leaves the cube once, so two of them meet beyond
/// the centroid only where their segments meet, which only neighbours do, at their shared
/// vertex. The edge and fan rules make the surface closed, oriented and a disk around every
/// vertex; vertices on distinct open edges or in distinct open cubes cannot coincide; three
/// points of a cube's surface are collinear only within one face, which no triangle lies in,
/// and a centroid lies off every face.
/// Costs about what marching_cubes() does, plus the checks.
/// @throws as marching_cubes(field, options)
ProvedMesh marching_cubes_proved(const Field& field, const McOptions& options = {});

/// The same mesh (bit for bit) as marching_cubes(sample_field(source, grid)), straight from a
/// field source (field.hpp): each task evaluates the slab of node layers it reads, so the
/// field is never held whole. Memory beyond the output: about ten node layers of floats per
/// worker thread; slabs overlap by two layers and both passes evaluate, so each node is
/// evaluated about 2.5 times.
/// @throws InputError  a grid dimension is below 2, bind_source refuses the source, or the mesh
/// would
///                     need 2^32 or more points
/// @throws Cancelled   when options.progress says so
/// @throws whatever the source throws
TriangleSoup marching_cubes(const FieldSource& source, const Grid& grid,
                            const McOptions& options = {});

/// Marching cubes fed slab by slab, lowest first, for grids whose field does not fit in memory:
/// after the last slab, `mesh` is marching_cubes() of the whole field, bit for bit (points
/// and triangles in the same order), though no more than one slab of the field was held.
class SlabMarchingCubes {
 public:
  /// @param grid         the whole grid (z_offset 0)
  /// @param first_plane  where to start: 0, or the first plane of one process's share of the
  ///                     grid (its points are then numbered from 0, and its last cell layer's
  ///                     triangles refer to the next share's first points from
  ///                     mesh.points.size() on, as that share numbers them from 0)
  /// @throws InputError  a grid dimension is below 2, or first_plane is not in the grid
  explicit SlabMarchingCubes(const Grid& grid, const McOptions& options = {}, int first_plane = 0);

  /// Extracts node layers [next_plane(), next_plane() + owned) — their points and the
  /// triangles of their cell layers — appending them to `mesh`, which must hold the points
  /// the earlier slabs appended (but those drop_points() took; ids are the whole mesh's).
  /// @param planes  φ on the grid's planes next_plane() .. min(next_plane() + owned + 1,
  ///                dims[2] − 1): the owned ones and the two above them that their edges and
  ///                the next layer's numbering read (a slab: Grid::z_offset = next_plane())
  /// @throws InputError  planes is not that slab, or the mesh would need 2^32 points
  void add(const Field& planes, int owned, TriangleSoup& mesh);

  int next_plane() const { return next_; }
  bool done() const { return next_ == grid_.dims[2]; }

  /// Node layer k's first point id (k == next_plane(): the points made so far), for layers
  /// from the first plane to next_plane(): a layer's points are ids [first_point(k),
  /// first_point(k + 1)).
  /// @throws InputError  layer k is not made yet
  std::uint64_t first_point(int k) const;
  /// Triangles made before cell layer k (counted from the first plane's, whatever the caller
  /// has taken out of `mesh` since), for the same layers: cell layer k's triangles are
  /// [first_triangle(k), first_triangle(k + 1)) in the order they were appended.
  std::uint64_t first_triangle(int k) const;

  /// Takes the points with ids below `below` out of `mesh` (the caller is done with them, so a
  /// mesh far larger than memory can stream through): `mesh` then holds ids from `below` on,
  /// id p at mesh.points[p - below], and add() continues that way. Triangles are the caller's:
  /// add() only appends to them.
  /// @throws InputError  `below` is not within the points held
  void drop_points(TriangleSoup& mesh, std::uint64_t below);

  /// Empty when marching_cubes_proved()'s proof holds of the layers made so far: the table
  /// keeps its rules, the grid as held increases strictly, every vertex lies strictly inside
  /// its edge or cube as held, and no node of the grid's border is inside. Else which
  /// assumption failed. Once done() from plane 0, an empty answer proves the whole mesh (what
  /// validate_mesh() takes as a ConstructionProof).
  std::string unproved() const;

 private:
  Grid grid_;
  McOptions options_;
  std::shared_ptr<const detail::RoundedGrid> held_;
  std::string unproved_grid_;                        ///< the table's or the grid's failure, if any
  bool border_inside_ = false, vertex_off_ = false;  ///< what the slabs so far found
  int first_ = 0;
  int next_ = 0;
  std::uint64_t dropped_ = 0;
  std::vector<std::uint64_t> first_point_, first_triangle_;  // from the first plane on
};

}  // namespace tpmsfill
