/// @file scanned_field.hpp
/// @brief Stage "scanned field": the discrete distance fields that porous structures are
/// fitted to (bspline.hpp, porous.hpp), made from data a user has (volume.hpp's ScalarVolume,
/// values at cell centres, mm):
///
///  - a mesh, messy or not: the signed distance, negative inside. Inside is the generalized
///    winding number of the cleaned, capped mesh (classify.hpp, as `fill --inside winding`),
///    and every value is the exact distance to the nearest triangle (distance.hpp), so the
///    zero level is the mesh's surface (across holes: their caps);
///  - a point cloud (a scan): the unsigned distance from each cell centre to the nearest
///    point, exact (a k-d tree of our own, searched nearest-first);
///  - a CT volume: thresholded at an iso-value, then the signed distance in mm between the
///    centres of solid and empty cells (an exact separable transform with each axis's own
///    spacing), less half the smallest spacing, so the zero level lies between the two sides.
///    Its error against the iso-surface the CT would give is at most one (largest) voxel.
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

#include "tpmsfill/io/volume.hpp"
#include "tpmsfill/progress.hpp"
#include "tpmsfill/types.hpp"

namespace tpmsfill {

struct ScannedFieldOptions {
  double voxel = 0;  ///< cell size, mm (> 0)
  int padding = 2;   ///< cells added beyond the data's bounding box on every side (>= 2)
  /// Largest field made, in cells: a larger one is refused, naming the voxel that fits.
  std::uint64_t max_cells = std::uint64_t{256} * 256 * 256 * 4;
  Progress* progress = nullptr;
};

/// Signed distance to a mesh (see the file comment); sign = Signed.
/// @throws InputError     voxel <= 0, padding < 2, a mesh with no triangle or no volume
/// @throws ResourceError  more than max_cells cells
ScalarVolume field_from_mesh(const TriangleSoup& mesh, const ScannedFieldOptions& options);

/// Unsigned distance to the nearest point; sign = Unsigned.
/// @throws InputError     no point, a point not finite, voxel <= 0, padding < 2
/// @throws ResourceError  more than max_cells cells
ScalarVolume field_from_points(const std::vector<Vec3>& points, const ScannedFieldOptions& options);

/// Signed distance of the CT's solid (values >= iso, or <= iso with `solid_below`), in mm;
/// sign = Signed. A CT without a physical size is read as the unit cube.
/// @throws InputError  an invalid volume, iso not finite, no solid or no empty cell
ScalarVolume field_from_ct(const ScalarVolume& ct, double iso, bool solid_below = false);

/// The points of a point cloud: PLY (its vertices; faces, if any, are ignored) or XYZ text
/// (x y z per line, further columns such as normals ignored, '#' comments); gzip allowed.
/// @throws IoError, ParseError (line or byte), InputError (no point)
std::vector<Vec3> read_points(const std::filesystem::path& path);

/// read_points of bytes already in memory; `name` is for messages.
/// @throws ParseError (line or byte), InputError (no point, or over 4 GiB inflated)
std::vector<Vec3> parse_points(std::string_view bytes, const std::string& name);

}  // namespace tpmsfill
