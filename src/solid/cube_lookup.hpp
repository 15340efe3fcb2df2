/// @file cube_lookup.hpp
/// @brief The cube map's inverse, I_G and I_M of seed 001 §2.3.1 (issue 18): a point (u, v, w)
/// of the unit cube → the tet whose image under the cube map holds it → its barycentric weights
/// → the position in mm, and the material, by the same weights. What the spline fit samples.
///
/// Tets are found through a uniform grid of buckets over the cube (each tet listed in the
/// buckets its image's box meets). A point in no tet's image (a gap left by folded or flat
/// tets, or round-off on the cube's faces) takes the tet it is least outside of, with its
/// weights clamped to the tet: the seed's "nearest tet" fallback.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "tpmsfill/solid/cube_map.hpp"
#include "tpmsfill/solid/tet_mesh.hpp"

namespace tpmsfill {

/// The data cube_lookup() needs, copied from the mesh and its map (a value: it owns it all).
struct CubeLookup {
  std::vector<std::array<double, 3>> uvw;  ///< per point, the cube map's image
  std::vector<Vec3> points;                ///< per point, mm
  std::vector<double> material;            ///< per point, or empty
  std::vector<Tet> tets;
  int buckets = 1;                          ///< per axis
  std::vector<std::uint32_t> bucket_start;  ///< buckets³ + 1 offsets into bucket_tets
  std::vector<std::uint32_t> bucket_tets;   ///< tet ids, bucket after bucket (x fastest)
};

/// Builds the lookup: about two tets per bucket (at most 256 buckets per axis). Flat tets
/// (images with no volume) are left out.
/// @pre map = map_to_cube(mesh)
CubeLookup build_cube_lookup(const TetMesh& mesh, const CubeMap& map);

struct CubeSample {
  Vec3 position;        ///< I_G, mm
  double material = 0;  ///< I_M (0 when the mesh has none)
  std::uint32_t tet = 0;
  std::array<double, 4> weights{};  ///< barycentric, ≥ 0, summing to 1
  bool inside = true;               ///< false: the nearest tet's clamped weights
};

/// I_G and I_M at (u, v, w) (clamped onto the cube). A point inside several images (folds)
/// takes the first tet in bucket order whose image holds it, so answers never depend on the
/// order of calls or threads.
CubeSample cube_lookup(const CubeLookup& lookup, std::array<double, 3> uvw);

}  // namespace tpmsfill
