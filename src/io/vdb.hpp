/// @file vdb.hpp
/// @brief Internal: OpenVDB's .vdb files, the only header whose source (vdb.cpp) sees OpenVDB.
/// Built without OpenVDB (libopenvdb-dev absent), every function but looks_like_vdb() refuses
/// with a sentence saying so.
#pragma once

#include <cstdint>
#include <string>
#include <string_view>

#include "tpmsfill/io/volume.hpp"

namespace tpmsfill::io {

/// Whether the bytes start with OpenVDB's magic number (0x56444220 little-endian, " BDV").
bool looks_like_vdb(std::string_view data);

/// Reads the first float (or double) grid of a .vdb as a dense volume over its active voxels'
/// box: a level set is FieldSign::Signed (negative inside, as tpmsfill's), anything else
/// (a fog volume's density) Unknown, unless tpmsfill wrote the sign into the grid's metadata.
/// The transform must be a scale (equal or not per axis, positive) and a translation.
/// @throws ParseError  OpenVDB cannot read the bytes, no float grid, a rotated or sheared transform
/// @throws InputError  no active voxel, or a box past the dimension or max_bytes limits
VolumeFile parse_vdb(std::string_view data, const std::string& source, std::uint64_t max_bytes);

/// `volume` as a .vdb holding one float grid "field": every cell an active voxel; a signed
/// field's grid is a level set. Needs a physical size.
/// @throws InputError  the volume has no physical size, or this build has no OpenVDB
std::string vdb_bytes(const ScalarVolume& volume);

}  // namespace tpmsfill::io
