// Seed 001's model of a solid with a material through it: a closed genus-0 surface filled with
// tets, a material (the distance to the surface's lowest corner, the seed's duck rule), the
// cube map, then G and M fitted as cubic THB splines, written as a model, the material asked
// at points in mm through G^-1, and a gyroid filling the surface graded by that material.
//
//   07_solid_spline SURFACE [OUT.tsm]
#include <algorithm>
#include <cstdio>
#include <memory>
#include <tpmsfill/error.hpp>
#include <tpmsfill/fill.hpp>
#include <tpmsfill/io.hpp>
#include <tpmsfill/material.hpp>
#include <tpmsfill/solid/cube_map.hpp>
#include <tpmsfill/solid/material_volume.hpp>
#include <tpmsfill/solid/solid_inverse.hpp>
#include <tpmsfill/solid/solid_model.hpp>
#include <tpmsfill/solid/tetrahedralize.hpp>

using namespace tpmsfill;

int main(int argc, char** argv) {
  if (argc < 2) {
    std::fprintf(stderr, "usage: 07_solid_spline SURFACE [OUT.tsm]\n");
    return 2;
  }
  try {
    TetMesh tets = with_chords_split(tetrahedralize(read_mesh(argv[1])));
    const TetMeshReport report = check_tet_mesh(tets);
    if (const auto problem = ball_problem(report)) {
      std::fprintf(stderr, "cannot map onto the cube: %s\n", problem->c_str());
      return 1;
    }
    const Box3 box = report.bounds;
    tets.material = distance_material(tets, box.min);
    const CubeMap map = map_to_cube(tets);
    const SolidFit fit = fit_solid_spline(tets, map);
    for (const FitRound& r : fit.rounds)
      std::printf("%zu control points: G %d steps, RS %.1f %%; M %d steps, RS %.1f %%\n",
                  r.control_points, r.geometry_iterations, r.geometry_rs, r.material_iterations,
                  r.material_rs);
    if (argc > 2) write_solid_model(argv[2], {fit, "examples/07_solid_spline"});
    // The material at points along the box's diagonal, through G^-1 (nothing outside).
    const SolidLocator locator = build_solid_locator(fit.spline);
    for (double t : {0.25, 0.5, 0.75, 1.5}) {
      const Vec3 p = box.min + t * (box.max - box.min);
      const std::optional<double> m = material_at(fit.spline, locator, p);
      if (m)
        std::printf("(%.3g, %.3g, %.3g) mm: material %.4g (the distance is %.4g)\n", p.x, p.y, p.z,
                    *m, norm(p - box.min));
      else
        std::printf("(%.3g, %.3g, %.3g) mm: outside the solid\n", p.x, p.y, p.z);
    }
    // A gyroid whose porosity follows the material: 0.5 near the corner, 0.8 far from it. The
    // material is sampled once onto a volume (M(G^-1) on a coarse grid), then read trilinearly.
    const auto material = std::make_shared<const ScalarVolume>(material_volume(fit.spline).volume);
    const Vec3 size = box.max - box.min;
    const double cell = std::min({size.x, size.y, size.z}) / 3;
    FillOptions job;
    job.design.cell = {cell, cell, cell};
    job.design.grading.push_back(
        {Graded::Porosity,
         {.shape = RampShape::Volume, .start = 0.5, .end = 0.8, .volume = material}});
    job.grid.voxel_size = cell / 16;
    const FillResult graded = fill(read_mesh(argv[1]), job);
    std::printf("graded gyroid: %zu triangles, porosity %.1f %% (%s)\n",
                graded.mesh.triangles.size(), 100 * graded.report.porosity(),
                grading_label(graded.resolved.design.grading[0]).c_str());
    return 0;
  } catch (const Error& e) {
    std::fprintf(stderr, "error: %s\n", e.what());
    return 1;
  }
}
