/// @file types.hpp
/// @brief Plain data passed between pipeline stages: points, boxes, triangle soups, and the
/// sampling grid with the masks and fields that live on its nodes.
///
/// All lengths are millimetres. Nothing here owns behaviour beyond small arithmetic helpers:
/// stages are free functions over these values (see the headers named after each stage).
#pragma once

#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <vector>

namespace tpmsfill {

/// A point or vector in millimetres.
struct Vec3 {
  double x = 0, y = 0, z = 0;

  friend bool operator==(const Vec3&, const Vec3&) = default;
  friend Vec3 operator+(Vec3 a, Vec3 b) { return {a.x + b.x, a.y + b.y, a.z + b.z}; }
  friend Vec3 operator-(Vec3 a, Vec3 b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
  friend Vec3 operator*(double s, Vec3 a) { return {s * a.x, s * a.y, s * a.z}; }
  double operator[](int axis) const { return axis == 0 ? x : (axis == 1 ? y : z); }
};

inline double dot(Vec3 a, Vec3 b) {
  return a.x * b.x + a.y * b.y + a.z * b.z;
}
inline Vec3 cross(Vec3 a, Vec3 b) {
  return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
inline double norm(Vec3 a) {
  return std::sqrt(dot(a, a));
}

/// A 3×3 matrix, row-major; default-constructed it is the identity. Used for rotations.
struct Mat3 {
  std::array<double, 9> m{1, 0, 0, 0, 1, 0, 0, 0, 1};

  friend bool operator==(const Mat3&, const Mat3&) = default;
  friend Vec3 operator*(const Mat3& a, Vec3 v) {
    const auto& m = a.m;
    return {m[0] * v.x + m[1] * v.y + m[2] * v.z, m[3] * v.x + m[4] * v.y + m[5] * v.z,
            m[6] * v.x + m[7] * v.y + m[8] * v.z};
  }
  friend Mat3 operator*(const Mat3& a, const Mat3& b) {
    Mat3 r;
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j)
        r.m[3 * i + j] =
            a.m[3 * i] * b.m[j] + a.m[3 * i + 1] * b.m[3 + j] + a.m[3 * i + 2] * b.m[6 + j];
    return r;
  }
  Mat3 transposed() const { return {{m[0], m[3], m[6], m[1], m[4], m[7], m[2], m[5], m[8]}}; }
  bool is_identity() const { return *this == Mat3{}; }
};

/// Axis-aligned box. Default-constructed it is empty (min > max), so extend() works from it.
struct Box3 {
  Vec3 min{std::numeric_limits<double>::infinity(), std::numeric_limits<double>::infinity(),
           std::numeric_limits<double>::infinity()};
  Vec3 max{-std::numeric_limits<double>::infinity(), -std::numeric_limits<double>::infinity(),
           -std::numeric_limits<double>::infinity()};

  bool empty() const { return !(min.x <= max.x && min.y <= max.y && min.z <= max.z); }
  Vec3 size() const { return empty() ? Vec3{} : max - min; }
  Vec3 centre() const { return empty() ? Vec3{} : 0.5 * (min + max); }
  void extend(Vec3 p) {
    min = {std::fmin(min.x, p.x), std::fmin(min.y, p.y), std::fmin(min.z, p.z)};
    max = {std::fmax(max.x, p.x), std::fmax(max.y, p.y), std::fmax(max.z, p.z)};
  }
};

/// Indices of a triangle's three corners into TriangleSoup::points, counter-clockwise seen
/// from outside (right-hand rule: the normal points out of the solid).
using Triangle = std::array<std::uint32_t, 3>;

/// A triangle soup: points and triangles that index them. It promises only that every index
/// is < points.size(); points may repeat (STL stores three per facet), triangles may be
/// degenerate, duplicated, non-manifold or inconsistently oriented. check_mesh() says which.
struct TriangleSoup {
  std::vector<Vec3> points;
  std::vector<Triangle> triangles;
};

/// Bounding box of the points referenced by at least one triangle (empty if there are none).
inline Box3 bounding_box(const TriangleSoup& soup) {
  Box3 box;
  for (const Triangle& t : soup.triangles)
    for (std::uint32_t v : t) box.extend(soup.points[v]);
  return box;
}

/// The box as a closed mesh: 8 corners, 12 outward triangles (the model fill_box() fills).
inline TriangleSoup box_soup(const Box3& b) {
  TriangleSoup box;
  for (int c = 0; c < 8; ++c)
    box.points.push_back(
        {c & 1 ? b.max.x : b.min.x, c & 2 ? b.max.y : b.min.y, c & 4 ? b.max.z : b.min.z});
  box.triangles = {{0, 2, 1}, {1, 2, 3}, {4, 5, 6}, {5, 7, 6}, {0, 1, 4}, {1, 5, 4},
                   {2, 6, 3}, {3, 6, 7}, {0, 4, 2}, {2, 4, 6}, {1, 3, 5}, {3, 7, 5}};
  return box;
}

/// A regular grid of sample nodes: node (i, j, k) sits at origin + spacing·(i, j, k), for
/// 0 <= i < dims[0], 0 <= j < dims[1], 0 <= k < dims[2]. Cells (voxels) are the cubes between
/// nodes; cell (i, j, k) has node (i, j, k) as its lowest corner. Per-node data is stored flat
/// with x fastest: index(i, j, k) = i + dims[0]·(j + dims[1]·k).
///
/// Every stage computes a node's coordinate with coordinate()/node(), so a node has one set of
/// bit-identical coordinates everywhere (classification, distances, marching cubes).
struct Grid {
  Vec3 origin;                ///< position of node (0, 0, 0), mm
  double spacing = 1.0;       ///< voxel size a (same on all axes), mm
  std::array<int, 3> dims{};  ///< nodes along x, y, z
  /// For a slab of a larger grid (a run of its z planes): the larger grid's index of this
  /// grid's plane 0, so node k lies at origin.z + spacing·(k + z_offset), bit for bit where
  /// the larger grid puts its plane k + z_offset. 0 for a whole grid.
  int z_offset = 0;

  std::size_t node_count() const {
    return static_cast<std::size_t>(dims[0]) * static_cast<std::size_t>(dims[1]) *
           static_cast<std::size_t>(dims[2]);
  }
  /// Rows of nodes along x: the unit stages parallelise over.
  std::size_t row_count() const {
    return static_cast<std::size_t>(dims[1]) * static_cast<std::size_t>(dims[2]);
  }
  std::size_t index(int i, int j, int k) const {
    return static_cast<std::size_t>(i) +
           static_cast<std::size_t>(dims[0]) *
               (static_cast<std::size_t>(j) +
                static_cast<std::size_t>(dims[1]) * static_cast<std::size_t>(k));
  }
  /// Coordinate of node number i along axis (0 = x, 1 = y, 2 = z), mm.
  double coordinate(int axis, int i) const {
    return origin[axis] + spacing * (axis == 2 ? i + z_offset : i);
  }
  Vec3 node(int i, int j, int k) const {
    return {coordinate(0, i), coordinate(1, j), coordinate(2, k)};
  }
  friend bool operator==(const Grid&, const Grid&) = default;
};

/// One byte per grid node (Grid's index order): 1 where the node is set (e.g. inside the
/// model), 0 elsewhere. Bytes rather than bits so threads write disjoint nodes freely.
struct Mask {
  Grid grid;
  std::vector<std::uint8_t> values;
};

/// One float per grid node (Grid's index order): a signed field in mm, negative inside the
/// solid it describes.
struct Field {
  Grid grid;
  std::vector<float> values;
};

/// A sparse set of grid nodes: node indices (Grid's index order), strictly increasing.
struct Band {
  Grid grid;
  std::vector<std::uint64_t> nodes;
};

/// A point in a layer's plane, mm.
struct Vec2 {
  double x = 0, y = 0;
  friend bool operator==(const Vec2&, const Vec2&) = default;
};

/// A closed contour: the last point joins the first (it is not repeated).
struct Contour {
  std::vector<Vec2> points;
  /// Signed area (shoelace), mm²: positive for an outer boundary of solid (counter-clockwise
  /// seen from +z), negative for a hole (clockwise).
  double area = 0;
  bool outer() const { return area > 0; }
};

/// Signed area of the closed polygon through `points` (shoelace), mm²: positive when
/// counter-clockwise seen from +z.
inline double signed_area(const std::vector<Vec2>& points) {
  double twice = 0;
  for (std::size_t k = 0, n = points.size(); k < n; ++k) {
    const Vec2 p = points[k], q = points[(k + 1) % n];
    twice += p.x * q.y - q.x * p.y;
  }
  return 0.5 * twice;
}

/// A layer's filled section as triangles with a material per point (a fitted solid's direct
/// slices: material_layers.hpp). Writers draw it when it has triangles: SVG fills
/// each triangle with its mean material's colour, PNG writes the material as grey.
struct MaterialSection {
  std::vector<Vec2> points;
  std::vector<double> material;  ///< per point
  std::vector<std::array<std::uint32_t, 3>> triangles;
  double material_min = 0, material_max = 1;  ///< the colour and grey scale's ends
};

/// One printer layer: the solid's cross-section at its centre height.
struct Layer {
  std::uint64_t index = 0;     ///< 0 for the lowest
  double bottom = 0, top = 0;  ///< the layer spans [bottom, top], mm
  double z = 0;                ///< the height sampled: the layer's centre, mm
  std::vector<Contour> contours;
  double area = 0;  ///< solid area: the contours' signed areas summed, mm²
  /// φ at the plane's nodes (grid.dims[2] == 1, grid.origin.z == z), negative in the solid:
  /// what writers rasterise with antialiasing (a pixel's coverage from φ at its centre).
  Field field;
  MaterialSection material = {};  ///< a fitted solid's sections: drawn with their material
};

/// How a format stores coordinates, for rounding a mesh to what its file will hold *before* it
/// is validated: the file then holds exactly the mesh that was proven valid.
enum class CoordinateRounding {
  None,   ///< doubles, read back bit-identical (OBJ, OFF: shortest round-trip text; PLY: binary)
  Float,  ///< nearest float (STL)
  /// What lib3mf 1.8 writes and reads back: the float times 10^6 in float arithmetic,
  /// truncated to an integer, printed as micrometres, parsed to the nearest float; repeated
  /// until it stands still, so writing a rounded point again changes nothing. Up to one
  /// micrometre off below 16 mm, 8 micrometres at 100 mm (docs/formats.md).
  ThreeMf,
  /// Fixed point with six decimals, read back as the nearest double: the layer files' text
  /// (ASCII CLI, SVG; layer_files.hpp).
  SixDecimals,
};

}  // namespace tpmsfill
