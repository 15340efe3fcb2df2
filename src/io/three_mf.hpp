/// @file three_mf.hpp
/// @brief Internal: 3MF through lib3mf, the only file that sees lib3mf (three_mf.cpp).
#pragma once

#include <cstdint>
#include <filesystem>
#include <span>
#include <string>
#include <string_view>

#include "tpmsfill/io.hpp"

namespace tpmsfill::io {

/// The most objects a package may place (build items times their components' fan-out):
/// assemblies of thousands of parts pass; a 1 KB package of components 8 wide and 12 deep
/// (8^12 instances) is refused at once instead of running for days.
inline constexpr std::uint64_t kMax3mfInstances = 100000;

/// The most build items a package may hold: lib3mf registers each item's UUID against all
/// the others (32,768 items took 17.7 s to read; 10,000 take about 1.7 s).
inline constexpr std::uint64_t kMax3mfBuildItems = 10000;

/// Reads a 3MF package: every build item of type model (or solid support) with its transform,
/// components resolved, scaled from the package's unit to millimetres.
/// @throws ParseError  lib3mf cannot read the package (its reason in the message)
void read_3mf(std::string_view data, const std::string& source, MeshFile& mesh);

/// Writes a 3MF package onto `fd` (an empty file): one object, millimetres, metadata and
/// attachments. `xyz` holds 3 floats a point, `ids` 3 point ids a triangle.
/// @throws IoError  lib3mf failed, or the disk did
void write_3mf(int fd, const std::filesystem::path& target, std::span<const float> xyz,
               std::span<const std::uint32_t> ids, const MeshMetadata& metadata);

/// `value` as lib3mf 1.8 writes it and reads it back (CoordinateRounding::ThreeMf).
float three_mf_rounded(float value);

}  // namespace tpmsfill::io
