// Point clouds (scanned_field.hpp's parse_points, read_points): PLY vertices or XYZ text.
#include <cmath>
#include <cstdio>
#include <string>

#include "io/file_bytes.hpp"
#include "io/formats.hpp"
#include "io/inflate.hpp"
#include "io/parse_errors.hpp"
#include "tpmsfill/error.hpp"
#include "tpmsfill/scan/scanned_field.hpp"

namespace tpmsfill {
namespace {

std::vector<Vec3> parse_xyz(std::string_view data, const std::string& source) {
  std::vector<Vec3> points;
  std::uint64_t line = 0;
  for (std::size_t at = 0; at < data.size();) {
    const std::size_t eol = std::min(data.find('\n', at), data.size());
    std::string text(data.substr(at, eol - at));
    at = eol + 1;
    ++line;
    if (const std::size_t hash = text.find('#'); hash != std::string::npos) text.resize(hash);
    for (char& ch : text)
      if (ch == ',' || ch == ';' || ch == '\t' || ch == '\r') ch = ' ';
    if (text.find_first_not_of(' ') == std::string::npos) continue;
    double xyz[3];
    int used = 0;
    if (std::sscanf(text.c_str(), "%lf %lf %lf%n", &xyz[0], &xyz[1], &xyz[2], &used) != 3)
      detail::fail_at_line(source, line, "expected three coordinates x y z");
    if (!std::isfinite(xyz[0]) || !std::isfinite(xyz[1]) || !std::isfinite(xyz[2]))
      detail::fail_at_line(source, line, "a coordinate is not finite");
    points.push_back({xyz[0], xyz[1], xyz[2]});
  }
  return points;
}

}  // namespace

std::vector<Vec3> parse_points(std::string_view data, const std::string& name) {
  std::string inflated;
  if (data.size() >= 2 && static_cast<unsigned char>(data[0]) == 0x1f &&
      static_cast<unsigned char>(data[1]) == 0x8b) {
    inflated = detail::inflate_bytes(data, name, std::uint64_t{4} << 30);
    data = inflated;
  }
  std::vector<Vec3> points;
  if (data.rfind("ply", 0) == 0) {
    MeshFile mesh;
    io::read_ply(data, name, mesh);
    points = std::move(mesh.soup.points);
  } else {
    points = parse_xyz(data, name);
  }
  if (points.empty()) throw InputError(name + " holds no points");
  return points;
}

std::vector<Vec3> read_points(const std::filesystem::path& path) {
  return parse_points(detail::read_file_bytes(path, std::uint64_t{4} << 30), path.string());
}

}  // namespace tpmsfill
