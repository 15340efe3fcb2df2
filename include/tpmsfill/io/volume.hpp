/// @file volume.hpp
/// @brief Stage "volume": a discrete scalar field on a uniform grid of cells (a scanned
/// distance field, a CT, a threshold field) and its files.
///
/// Porous structures fitted to a scanned field (Lin & Gao's patent) start from "a discrete
/// distance field": w × h × d values, one per cell, at the cell centres of the unit cube.
/// Scanners and 3D Slicer write the same thing as NRRD or MetaImage with a voxel spacing in mm;
/// CGAL writes .inr. ScalarVolume holds any of them: values at cell centres, x fastest, with an
/// optional physical size.
///
/// Readers are our own, with the mesh readers' rules: every declared count is checked against
/// the bytes before anything is allocated, every error names the line or byte offset, values
/// that are not finite are refused, gzip is unwrapped. Writers are atomic (io.hpp).
#pragma once

#include <array>
#include <cstdint>
#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

#include "tpmsfill/types.hpp"

namespace tpmsfill {

/// What a field's values mean with respect to the solid it describes.
enum class FieldSign {
  Unknown,   ///< the file does not say (a CT's intensities, a threshold field)
  Signed,    ///< a signed distance, negative in the solid (tpmsfill's convention)
  Unsigned,  ///< a distance to a scanned surface or point cloud, ≥ 0 everywhere
};

/// w × h × d values at the centres of a box's cells, x fastest (as Grid's fields).
struct ScalarVolume {
  std::array<int, 3> dims{};  ///< cells along x, y, z (each ≥ 1)
  /// Size of one cell, mm; all zero when the file gives no physical size (a discrete distance
  /// field's unit-cube form): the volume is then the unit cube, unitless.
  std::array<double, 3> spacing{};
  /// Centre of the first cell (0, 0, 0), mm (NRRD "space origin", MetaImage "Offset").
  Vec3 origin{};
  std::vector<double> values;  ///< dims product, x fastest, all finite
  FieldSign sign = FieldSign::Unknown;

  std::size_t count() const { return std::size_t(dims[0]) * dims[1] * dims[2]; }
  bool has_physical_size() const { return spacing[0] > 0 && spacing[1] > 0 && spacing[2] > 0; }
  double at(int i, int j, int k) const {
    return values[std::size_t(i) +
                  std::size_t(dims[0]) * (std::size_t(j) + std::size_t(dims[1]) * k)];
  }
};

enum class VolumeFormat {
  Auto,         ///< reading: detect from content, then extension; writing: from the extension
  FieldText,    ///< a distance field as text: optional header lines, "w h d", values (.tdf)
  FieldBinary,  ///< a distance field as binary: magic, counts, float32/float64 values (.tdfb)
  Nrrd,         ///< NRRD, attached or detached data, raw or gzip (.nrrd, .nhdr)
  MetaImage,    ///< MetaImage, local or separate data, raw or zlib (.mha, .mhd)
  Inr,          ///< CGAL / INRIA image (.inr, .inr.gz)
  /// OpenVDB (.vdb) through OpenVDB itself, where the build has it (libopenvdb-dev): the first
  /// float grid, dense over its active voxels; written as one float grid, a level set when signed
  Vdb,
};

/// "field-text", "field-binary", "nrrd", "metaimage", "inr", "vdb".
std::string_view volume_format_name(VolumeFormat format);
/// The format an extension names (case-insensitive; ".inr.gz" counts as ".inr"), or Auto.
VolumeFormat volume_format_from_extension(const std::filesystem::path& path);
/// "unknown", "signed", "unsigned"; and back (throws InputError listing the names).
std::string_view field_sign_name(FieldSign sign);
FieldSign field_sign_from_name(std::string_view name);

struct VolumeReadOptions {
  VolumeFormat format = VolumeFormat::Auto;
  std::uint64_t max_bytes = std::uint64_t{4} << 30;  ///< largest file or decompressed data
};

/// What a reader found, beside the volume.
struct VolumeFile {
  ScalarVolume volume;
  VolumeFormat format = VolumeFormat::Auto;  ///< the format actually parsed
  std::string element_type;                  ///< as stored: "uint8", "int16", "float32", ...
  bool compressed = false;                   ///< gzip / zlib data was unwrapped
  std::vector<std::string> warnings;         ///< read around, not refused (one sentence each)
};

/// Reads a volume file. Detached data (NRRD "data file", MetaImage "ElementDataFile") is
/// read relative to the header's folder.
/// @throws IoError     the file (or its data file) cannot be opened or read
/// @throws ParseError  malformed bytes, or a header asking for what is not read (an element
///                     type, encoding or rotation): the message names the line or byte offset
/// @throws InputError  empty, over max_bytes, a negative spacing
VolumeFile read_volume_file(const std::filesystem::path& path,
                            const VolumeReadOptions& options = {});

/// Parses bytes already in memory (detached data cannot be followed and is refused).
VolumeFile parse_volume(std::string_view bytes, const std::string& source_name,
                        const VolumeReadOptions& options = {});

/// Writes atomically (write_file_atomically). FieldText, FieldBinary (float32 unless a value
/// would lose more than float rounding... always float64 when `exact`), Nrrd (raw, attached),
/// Vdb (float32, every cell an active voxel; needs a physical size).
/// @throws InputError  Auto with an extension that names no writable format, an invalid
///                     volume (count mismatch, a dimension < 1, a value not finite)
/// @throws IoError     the folder is not writable, the disk is full, ...
void write_volume(const std::filesystem::path& path, const ScalarVolume& volume,
                  VolumeFormat format = VolumeFormat::Auto, bool exact = false);

/// @throws InputError  a dimension < 1, values.size() != count(), a value not finite, a
///                     negative or non-finite spacing, spacing partly zero
void require_valid(const ScalarVolume& volume);

/// Whether this build reads and writes .vdb (OpenVDB was found when it was built).
bool vdb_available();

struct LevelSetOptions {
  double voxel = 0;       ///< voxel size, mm (> 0)
  double half_width = 3;  ///< the band's half-width, voxels (OpenVDB's default 3; ≥ 1)
};

/// Writes the narrow-band level set of a closed mesh as a .vdb that OpenVDB's tools open: one
/// float grid "surface" of class level set, the exact distance to the mesh (negative inside) at
/// voxels within the band, ±half-width outside it; voxel centres on multiples of the voxel
/// (OpenVDB's meshToLevelSet). Atomic, like every writer.
/// @throws InputError  no OpenVDB in this build, a voxel or half-width out of range, an empty
///                     mesh, or a band of more than 2^31 voxels per axis
/// @throws IoError     the folder is not writable, the disk is full, ...
void write_level_set(const std::filesystem::path& path, const TriangleSoup& mesh,
                     const LevelSetOptions& options);

/// The value at p (mm), interpolated trilinearly between the cell centres; a point beyond the
/// outermost centres takes the nearest border value (constant extrapolation), and `outside`,
/// when given, says whether p lies beyond the volume's box (more than half a cell out).
/// Preconditions: the volume has a physical size and count() values (require_valid).
double sample_volume(const ScalarVolume& volume, Vec3 p, bool* outside = nullptr);

}  // namespace tpmsfill
