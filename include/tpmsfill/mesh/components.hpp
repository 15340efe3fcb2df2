/// @file components.hpp
/// @brief Stage "components": the connected pieces of a mesh (triangles joined through shared
/// points, exactly as indexed), each with its size, signed volume and area, and the mesh with
/// only the pieces one keeps. fill() uses them to count cavities and remove floating islands.
///
/// Plain data, serial and deterministic: components are numbered in order of their first
/// triangle, and sums run in triangle order.
#pragma once

#include <cstdint>
#include <vector>

#include "tpmsfill/mesh/validate.hpp"
#include "tpmsfill/types.hpp"

namespace tpmsfill {

/// Connected components (through shared vertices) of a mesh, with their size and extent.
struct Components {
  std::vector<std::uint32_t> triangle_component;  ///< per triangle, numbered from 0
  struct Info {
    std::uint64_t triangles = 0;
    double volume = 0;  ///< signed, mm^3 (about the mesh's bounding-box centre if open)
    double area = 0;    ///< mm^2
    std::uint32_t first_triangle = 0;  ///< lowest triangle index in the component
  };
  /// Numbered in order of their first triangle, so numbering is deterministic.
  std::vector<Info> info;
};

/// Labels the components of `mesh` and measures each.
/// @param[in] mesh  triangles over shared points, mm
/// @throws InputError  an index is out of range, or the mesh has more triangles or points
///                     than 32-bit corner numbers allow
Components mesh_components(const TriangleSoup& mesh);

/// The mesh with only the triangles whose component has keep[component] set; unreferenced
/// points are dropped, the remaining points and triangles keep their relative order.
/// @param[in] mesh        the mesh `components` was computed from
/// @param[in] components  mesh_components(mesh)
/// @param[in] keep        per component: keep it
/// @throws InputError  an index is out of range, or `components` / `keep` do not fit `mesh`
TriangleSoup keep_components(const TriangleSoup& mesh, const Components& components,
                             const std::vector<bool>& keep);

/// The same, made in `mesh`'s own storage: what is kept moves down in place instead of being
/// copied to new memory (fill drops islands this way: fresh pages for a lattice's millions of
/// points and triangles cost more than finding the components).
TriangleSoup keep_components(TriangleSoup&& mesh, const Components& components,
                             const std::vector<bool>& keep);

/// The proof of keep_components(mesh, components, keep), given `proof` of `mesh`: whole
/// components dropped keep what a construction proves (each is closed and meets no other).
/// @throws InputError  as keep_components, or `proof` does not speak of `mesh`
ConstructionProof keep_components(const ConstructionProof& proof, const TriangleSoup& mesh,
                                  const Components& components, const std::vector<bool>& keep);

}  // namespace tpmsfill
