// Seed 001's direct slicing against the input surface's own cross-sections (docs/benchmarks.md
// §22): a fitted model (.tsm) sliced at heights across its box with several tau, each section's
// area compared with the closed surface's section at the same height (each triangle's crossing
// segment, oriented by its normal, summed by the shoelace rule: exact for a closed surface).
//
//   bench_solid_slice MODEL.tsm SURFACE TETS|- TAU...
//
// TETS (the tets the model was fitted to, as `material info --tets` writes them) adds their own
// section's area (each tet's section polygon), which the fit saw. TAU 0 is the default τ.
// Cracks counts the section's border edges with an end off the cube's faces, and edges used by
// more than two triangles: both must be 0. Unfolded counts the turned-over triangles where G
// does not fold at any of their corners (det of G's Jacobian > 0 there).
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <map>
#include <string>
#include <tpmsfill/io.hpp>
#include <tpmsfill/solid/solid_model.hpp>
#include <tpmsfill/solid/solid_slice.hpp>
#include <tpmsfill/solid/tet_mesh.hpp>

#include <vector>
#include "../test_util.hpp"

using namespace tpmsfill;

// Border edges inside the parameter cube, and edges of more than two triangles.
std::size_t cracks(const SolidLevelSet& mesh) {
  std::map<std::pair<std::uint32_t, std::uint32_t>, int> uses;
  for (const auto& t : mesh.triangles)
    for (int e = 0; e < 3; ++e)
      ++uses[{std::min(t[e], t[(e + 1) % 3]), std::max(t[e], t[(e + 1) % 3])}];
  auto on_face = [&](std::uint32_t v) {
    for (double x : mesh.uvw[v])
      if (x == 0 || x == 1) return true;
    return false;
  };
  std::size_t count = 0;
  for (const auto& [edge, n] : uses)
    count += n > 2 || (n == 1 && !(on_face(edge.first) && on_face(edge.second)));
  return count;
}

// Turned-over triangles of a section with det J_G > 0 at all three corners.
std::size_t unfolded(const SolidSpline& spline, const SolidSection& s) {
  std::size_t count = 0;
  for (const auto& t : s.mesh.triangles) {
    const Vec3 a = s.mesh.points[t[0]], b = s.mesh.points[t[1]], c = s.mesh.points[t[2]];
    if (!((b.x - a.x) * (c.y - a.y) - (c.x - a.x) * (b.y - a.y) < 0)) continue;
    bool folds = false;
    for (std::uint32_t v : t) {
      const auto j = evaluate_solid(spline, s.mesh.uvw[v]).jacobian;
      folds |= !(dot(j[0], cross(j[1], j[2])) > 0);
    }
    count += !folds;
  }
  return count;
}

int main(int argc, char** argv) {
  if (argc < 5) {
    std::fprintf(stderr, "usage: bench_solid_slice MODEL.tsm SURFACE TETS|- TAU...\n");
    return 2;
  }
  const SolidModel model = read_solid_model(argv[1]);
  const TriangleSoup surface = read_mesh(argv[2]);
  const bool with_tets = std::string(argv[3]) != "-";
  const TetMesh tets = with_tets ? read_tet_mesh(argv[3]) : TetMesh{};
  const Box3 box = solid_box(model.fit.spline);
  Box3 controls{model.fit.spline.geometry[0], model.fit.spline.geometry[0]};  // as slice_solid's τ
  for (const Vec3& p : model.fit.spline.geometry)
    controls = {{std::min(controls.min.x, p.x), std::min(controls.min.y, p.y),
                 std::min(controls.min.z, p.z)},
                {std::max(controls.max.x, p.x), std::max(controls.max.y, p.y),
                 std::max(controls.max.z, p.z)}};
  std::printf(
      "| height (share of the box) | tau | level | triangles | area | surface's area | "
      "difference | tets' area | difference | flipped | unfolded | cracks | seconds |\n"
      "|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n");
  for (double share : {0.2, 0.4, 0.6, 0.8}) {
    const double z = box.min.z + share * (box.max.z - box.min.z);
    const double expected = test::section_area(surface, z);
    const double tet_area = with_tets ? test::tet_section_area(tets, z) : std::nan("");
    for (int k = 4; k < argc; ++k) {
      const double tau = std::atof(argv[k]);
      const auto t0 = std::chrono::steady_clock::now();
      const SolidSection s = slice_solid(model.fit.spline, z, {.tau = tau});
      const double seconds =
          std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
      std::printf(
          "| %.4g (%.1f) | %.3g | %d | %zu | %.5g | %.5g | %+.2f %% | %.5g | %+.2f %% | %zu | %zu "
          "| %zu | %.3f |\n",
          z, share, tau > 0 ? tau : default_slice_tau(controls), s.mesh.level,
          s.mesh.triangles.size(), s.area, expected, 100 * (s.area / expected - 1), tet_area,
          100 * (s.area / tet_area - 1), s.flipped, unfolded(model.fit.spline, s), cracks(s.mesh),
          seconds);
    }
  }
  return 0;
}
