/// @file solid_model.hpp
/// @brief The solid spline model file: a fitted G and M with their basis and the fit's report,
/// version 1 (layout in docs/formats.md, "Solid spline model").
///
/// The basis is stored as what makes it, not as its functions: the octree as one bit per node
/// (pre-order from the cube: 1 split, 0 leaf), or the uniform basis's count per axis. The
/// reader builds the basis again (knots are clamped uniform per level, so none are stored) and
/// checks that it has as many functions as the file has control values. The reader follows the
/// other readers' rules: counts checked against the bytes left before anything is allocated,
/// every error at its byte offset, nothing non-finite, a CRC-32 over it all.
#pragma once

#include <filesystem>
#include <string>
#include <string_view>

#include "tpmsfill/solid/solid_spline.hpp"

namespace tpmsfill {

struct SolidModel {
  SolidFit fit;            ///< the spline and the report of the fit that made it
  std::string provenance;  ///< one line: what it was made from, by what (UTF-8, < 64 KiB)
};

/// The file's bytes.
/// @throws InputError  a spline whose basis is neither an octree's THB nor a uniform basis,
///                     coefficient counts that do not match it, a provenance over 64 KiB
std::string solid_model_bytes(const SolidModel& model);

/// Writes the file atomically (a temporary beside it, then renamed).
/// @throws InputError  as solid_model_bytes
/// @throws IoError     the file cannot be written
void write_solid_model(const std::filesystem::path& path, const SolidModel& model);

/// True when the bytes start as a solid spline model does ("TSPL").
bool looks_like_solid_model(std::string_view bytes);

/// @throws ParseError  malformed bytes (with the byte offset)
/// @throws InputError  a version this tpmsfill does not read
SolidModel parse_solid_model(std::string_view bytes, const std::string& source);

/// @throws IoError     the file cannot be read
/// @throws ParseError  as parse_solid_model
SolidModel read_solid_model(const std::filesystem::path& path);

}  // namespace tpmsfill
