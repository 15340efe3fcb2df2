/// @file spatial.hpp
/// @brief Stage "spatial": the search structure over the input triangles (CGAL's AABB tree on
/// the exact-predicate kernel Epick), built once and shared by classify_grid() and the
/// distance stage.
///
/// MeshIndex is opaque: CGAL stays inside src/. It keeps its own copy of the triangles, so
/// the soup it was built from may be destroyed afterwards, unless IndexOptions::borrow_points
/// asks it to read them in place.
#pragma once

#include <cstddef>
#include <memory>

#include "tpmsfill/types.hpp"

namespace tpmsfill {

namespace detail {
struct MeshIndexAccess;  // src/sampling/internal/mesh_index_impl.hpp: how classify and distance see
                         // inside
}

struct IndexOptions {
  /// Triangles that close the soup's holes (CleanResult::caps), or null. They join the
  /// tree, so rays cross them and distances reach them (the model's contour runs across a
  /// hole along its cap), and classify_grid()'s winding rule subtracts their own winding
  /// number again, so that the result is the winding number of the soup alone.
  const TriangleSoup* hole_caps = nullptr;
  /// Read the soup's corners in place instead of copying them (72 bytes a triangle), when its
  /// triangles are laid out one by one: triangle t is points 3t, 3t + 1 and 3t + 2, as STL
  /// readers and marching cubes give them. The soup must then outlive the index, unchanged.
  /// Other layouts are copied as without it.
  bool borrow_points = false;
  // Triangles with a repeated corner are always left out (they bound nothing). Collinear
  // triangles are kept: rays and distances treat them exactly.
};

/// An AABB tree over a triangle soup's triangles (Epick). Move-only; made by build_index().
class MeshIndex {
 public:
  MeshIndex(MeshIndex&&) noexcept;
  MeshIndex& operator=(MeshIndex&&) noexcept;
  ~MeshIndex();

  std::size_t triangle_count() const;  ///< triangles in the tree, caps included
  std::size_t cap_count() const;       ///< of those, hole caps
  Box3 bounds() const;                 ///< of the triangles in the tree

 private:
  struct Impl;
  friend struct detail::MeshIndexAccess;
  explicit MeshIndex(std::unique_ptr<Impl> impl);
  std::unique_ptr<Impl> impl_;
};

/// Builds the AABB tree.
/// @param[in] soup  any triangle soup; indices must be in range (readers guarantee it), also
///                  in options.hole_caps
/// @throws InputError  an index is out of range, or no triangle has three distinct corners
MeshIndex build_index(const TriangleSoup& soup, const IndexOptions& options = {});

}  // namespace tpmsfill
