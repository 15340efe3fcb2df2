/// @file spatial.hpp
/// @brief Stage "spatial": the search structure over the input triangles (CGAL's AABB tree on
/// the exact-predicate kernel Epick), built once and shared by classify_grid() and the
/// distance stage.
///
/// MeshIndex is opaque: CGAL stays inside src/. It keeps its own copy of the triangles, so
/// the soup it was built from may be destroyed afterwards.
#pragma once

#include <cstddef>
#include <memory>

#include "tpmsfill/types.hpp"

namespace tpmsfill {

struct IndexOptions {
  /// Triangles with a repeated corner are always left out (they bound nothing). Collinear
  /// triangles are kept: rays and distances treat them exactly.
};

/// An AABB tree over a triangle soup's triangles (Epick). Move-only.
class MeshIndex {
 public:
  struct Impl;  ///< defined in src/detail/mesh_index_impl.hpp

  explicit MeshIndex(std::unique_ptr<Impl> impl);
  MeshIndex(MeshIndex&&) noexcept;
  MeshIndex& operator=(MeshIndex&&) noexcept;
  ~MeshIndex();

  std::size_t triangle_count() const;  ///< triangles in the tree
  Box3 bounds() const;                 ///< of the triangles in the tree

  const Impl& impl() const { return *impl_; }

 private:
  std::unique_ptr<Impl> impl_;
};

/// Builds the AABB tree.
/// @param[in] soup  any triangle soup; indices must be in range (readers guarantee it)
/// @throws InputError  an index is out of range, or no triangle has three distinct corners
MeshIndex build_index(const TriangleSoup& soup, const IndexOptions& options = {});

}  // namespace tpmsfill
