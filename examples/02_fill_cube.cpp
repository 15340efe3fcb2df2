// Fill a mesh made in code with a gyroid lattice, in one call, and write it as STL.
//
//   02_fill_cube [OUT.stl]
//
// The model is a 10 mm cube with a 4 mm square hole through it (a closed mesh of genus 1,
// built below). fill() runs the whole pipeline and validates the result; the report says
// how it went.
#include <cstdio>
#include <tpmsfill/error.hpp>
#include <tpmsfill/fill.hpp>
#include <tpmsfill/io.hpp>

using namespace tpmsfill;

namespace {

// A square frame: the cube [0,10]³ minus the column [3,7]² × [0,10], as 16 outward quads.
TriangleSoup make_frame() {
  TriangleSoup m;
  const double o[4] = {0, 3, 7, 10};  // the four x (and y) levels of the outline
  // Points: the outline rings at z = 0 and z = 10; ring index r = 0 outer, 1 inner.
  auto add = [&](double x, double y, double z) {
    m.points.push_back({x, y, z});
    return static_cast<std::uint32_t>(m.points.size() - 1);
  };
  std::uint32_t ring[2][2][4];  // [outer/inner][bottom/top][corner, counter-clockwise]
  for (int r = 0; r < 2; ++r)
    for (int t = 0; t < 2; ++t) {
      const double lo = o[r], hi = o[3 - r], z = 10.0 * t;
      ring[r][t][0] = add(lo, lo, z);
      ring[r][t][1] = add(hi, lo, z);
      ring[r][t][2] = add(hi, hi, z);
      ring[r][t][3] = add(lo, hi, z);
    }
  auto quad = [&](std::uint32_t a, std::uint32_t b, std::uint32_t c, std::uint32_t d) {
    m.triangles.push_back({a, b, c});
    m.triangles.push_back({a, c, d});
  };
  for (int c = 0; c < 4; ++c) {
    const int n = (c + 1) % 4;
    quad(ring[0][0][c], ring[0][0][n], ring[0][1][n], ring[0][1][c]);  // outer wall, outward
    quad(ring[1][0][n], ring[1][0][c], ring[1][1][c], ring[1][1][n]);  // hole wall, inward
    quad(ring[0][1][c], ring[0][1][n], ring[1][1][n], ring[1][1][c]);  // top, +z
    quad(ring[0][0][n], ring[0][0][c], ring[1][0][c], ring[1][0][n]);  // bottom, -z
  }
  return m;
}

}  // namespace

int main(int argc, char** argv) {
  const char* out = argc > 1 ? argv[1] : "frame-gyroid.stl";
  FillOptions options;
  options.design.type = TpmsType::Gyroid;
  options.design.cell = {2.5, 2.5, 2.5};
  options.grid.voxel_size = 0.2;
  try {
    const FillResult result = fill(make_frame(), options);
    write_mesh(out, result.mesh);
    std::printf("%s\nwritten to %s\n", to_text(result.report).c_str(), out);
    return result.report.validation.valid() ? 0 : 1;
  } catch (const Error& e) {
    std::fprintf(stderr, "error: %s\n", e.what());
    return 1;
  }
}
