/// @file itdf.hpp
/// @brief Stage "itdf": the compact implicit storage of a porous structure. Lin & Gao's patent
/// names ITDF but never defines it; tpmsfill's definition (docs/formats.md, "ITDF") stores the
/// structure type, sign convention, physical size and placement, then C and its thresholds
/// (each a constant or a B-spline: degrees, counts, knots, float32, float64 or quantized int16
/// coefficients), the fit's report and a provenance line, closed by a CRC-32.
///
/// The reader follows the mesh readers' rules: every count is checked against the bytes left
/// before anything is allocated, every error names its byte offset, nothing non-finite gets
/// through (but an infinite constant t1 or t2, which opens that side). Reading a file and
/// writing what was read gives the same bytes.
#pragma once

#include <array>
#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <string_view>

#include "tpmsfill/io/volume.hpp"
#include "tpmsfill/scan/bspline.hpp"
#include "tpmsfill/scan/porous.hpp"

namespace tpmsfill {

/// How a B-spline's coefficients are stored.
enum class CoefficientType : std::uint8_t {
  Float32 = 0,  ///< 4 bytes each (the default: far below any fit's error)
  Float64 = 1,  ///< 8 bytes each, exact
  Int16 = 2,    ///< 2 bytes each: c = offset + scale · q, q in [−32767, 32767]
};

/// One function's storage. For Int16 a zero scale means "choose it from the coefficients"
/// (offset the middle of their range, scale half the range / 32767); reading sets both.
struct CoefficientEncoding {
  CoefficientType type = CoefficientType::Float32;
  double scale = 0, offset = 0;
};

/// What the fit that made C reported (field fit), kept with the structure.
struct FitRecord {
  bool lspia = false;                ///< the method: LSPIA, else the direct solve
  std::array<int, 3> source_dims{};  ///< the fitted grid's cells
  int iterations = 0;
  double rms = 0, max_error = 0;        ///< of C − x over the grid
  double value_min = 0, value_max = 0;  ///< of the grid's values
  double iso = 0, flipped = 0;          ///< share of cells whose side of `iso` changed
  double seconds = 0;                   ///< the fit's wall time
};

struct ItdfFile {
  PorousStructure structure;
  /// Storage of C, t0, t1, t2 (in that order; a constant threshold ignores its entry).
  std::array<CoefficientEncoding, 4> encoding{};
  std::optional<FitRecord> fit = {};
  std::string provenance;  ///< one line: what it was made from, by what (UTF-8, < 64 KiB)
};

/// The file's bytes (version 1).
/// @throws InputError  an invalid structure (require_valid), a provenance over 64 KiB, or
///                     int16 coefficients outside the range a given scale and offset reach
std::string itdf_bytes(const ItdfFile& file);

/// Writes itdf_bytes atomically (write_file_atomically).
void write_itdf(const std::filesystem::path& path, const ItdfFile& file);

/// @throws ParseError  malformed bytes (the message names the byte offset), a CRC mismatch
/// @throws InputError  a newer version, an invalid structure
ItdfFile parse_itdf(std::string_view bytes, const std::string& source_name);

/// @throws IoError     the file cannot be read;  as parse_itdf otherwise
ItdfFile read_itdf(const std::filesystem::path& path);

/// Whether these bytes start like an ITDF file (its magic).
bool looks_like_itdf(std::string_view bytes);

/// Fits a field as `tpmsfill field fit` does: a B-spline C of `counts` coefficients per axis
/// (a 0 takes half the field's cells on that axis, at least degree + 1), the structure C ≤ 0
/// (the solid of a signed field; the caller sets another for other fields), the field's sign
/// and physical size, and the fit's record (iso 0).
/// @throws InputError  as fit_bspline (counts over the cells, a degree out of range, ...)
ItdfFile fit_field(const ScalarVolume& field, std::array<int, 3> counts, const FitOptions& options);

/// The porous structure a file holds: an ITDF's as stored, or a field file's (any
/// read_volume_file reads: .tdf, .tdfb, .nrrd, .mha, .inr, .vdb) fitted by fit_field with its
/// defaults. What `fill --field` and `field mesh` take.
/// @throws InputError  a field that is not signed (it needs `field fit` with --solid or
///                     --surface), or as read_itdf, read_volume_file and fit_field
ItdfFile read_structure(const std::filesystem::path& path);

}  // namespace tpmsfill
