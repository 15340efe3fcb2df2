/// @file problem_text.hpp
/// @brief The sentences MeshCheck::problems() (stage "check") and
/// MeshValidity::problems() (stage "validate") write, each written once here. Where the
/// two stages know different facts (holes, why a mesh is not outward) the sentence takes
/// what its caller knows; the words are part of the CLI's output and of the reports.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <optional>
#include <string>

namespace tpmsfill::detail {

/// "1 border edge", "3 border edges".
inline std::string plural(std::uint64_t n, const char* one, const char* many) {
  return std::to_string(n) + " " + (n == 1 ? one : many);
}

/// Three significant digits, never in exponent notation for everyday magnitudes.
inline std::string short_number(double v) {
  if (!std::isfinite(v) || v == 0) return v == 0 ? "0" : std::to_string(v);
  double magnitude = std::floor(std::log10(std::fabs(v)));
  if (magnitude < -6 || magnitude > 15) {
    char buffer[32];
    std::snprintf(buffer, sizeof buffer, "%.3g", v);
    return buffer;
  }
  int decimals = std::max(0, 2 - static_cast<int>(magnitude));
  char buffer[64];
  std::snprintf(buffer, sizeof buffer, "%.*f", decimals, v);
  return buffer;
}

/// One sentence per failed condition, in the words both stages print.
namespace sentence {

inline std::string no_triangles() {
  return "the mesh has no triangles";
}

/// With the holes counted (check): "3 border edges in 1 hole: the mesh is open" ("and" when
/// splitting non-manifold edges made more holes than border edges); without (validate):
/// "3 border edges: the mesh is not closed".
inline std::string border_edges(std::uint64_t border_edges, std::optional<std::uint64_t> holes) {
  const std::string edges = plural(border_edges, "border edge", "border edges");
  if (!holes) return edges + ": the mesh is not closed";
  const char* joint = *holes <= border_edges ? " in " : " and ";
  return edges + joint + plural(*holes, "hole", "holes") + ": the mesh is open";
}

inline std::string non_manifold_edges(std::uint64_t n) {
  return plural(n, "non-manifold edge", "non-manifold edges") +
         " (shared by three or more triangles)";
}

inline std::string non_manifold_vertices(std::uint64_t n) {
  return plural(n, "non-manifold vertex", "non-manifold vertices") +
         " (where separate sheets touch at a point)";
}

inline std::string inconsistent_edges(std::uint64_t n) {
  return plural(n, "inconsistently oriented edge", "inconsistently oriented edges") +
         ": neighbouring triangles disagree on which side is outside";
}

/// A closed, oriented mesh whose shells do not all face out (check): inside out when its
/// volume is negative, else some shell faces into the solid; the volume when known.
inline std::string shells_not_outward(std::optional<double> volume) {
  const std::string v = volume ? " (volume " + short_number(*volume) + ")" : "";
  if (volume && *volume < 0) return "the mesh is inside out: its normals point inward" + v;
  return "a shell is oriented the wrong way: its normals point into the solid" + v;
}

/// A mesh that is not outward (validate): inside out unless its signed volume is positive,
/// else some component encloses no volume.
inline std::string components_not_outward(double volume) {
  if (volume <= 0) return "the mesh is inside out: its signed volume is " + short_number(volume);
  return "a component encloses no volume (its signed volume is zero)";
}

inline std::string degenerate_triangles(std::uint64_t n) {
  return plural(n, "degenerate triangle", "degenerate triangles") +
         " (repeated or collinear corners)";
}

inline std::string duplicate_triangles(std::uint64_t n) {
  return plural(n, "duplicate triangle", "duplicate triangles");
}

inline std::string duplicate_points(std::uint64_t n) {
  return plural(n, "duplicate point", "duplicate points") +
         ": separate vertices at the same position";
}

inline std::string self_intersections(std::uint64_t pairs) {
  return plural(pairs, "self-intersecting triangle pair", "self-intersecting triangle pairs");
}

}  // namespace sentence
}  // namespace tpmsfill::detail
