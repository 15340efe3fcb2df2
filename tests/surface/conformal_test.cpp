// Stages "parameterize" and "conformal": surfaces laid flat on the unit square (flips,
// distortion, seams) and lattice layers mapped onto them (validated, within 0..H).
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <functional>
#include <numbers>
#include <tpmsfill/check.hpp>
#include <tpmsfill/conformal.hpp>
#include <tpmsfill/error.hpp>
#include <tpmsfill/io.hpp>
#include <tpmsfill/surface/parameterize.hpp>

#include "test_util.hpp"

using namespace tpmsfill;
using namespace tpmsfill::test;
namespace fs = std::filesystem;

namespace {

constexpr double kPi = std::numbers::pi;

fs::path cgal_mesh(const std::string& name) {
  return fs::path(TPMSFILL_CGAL_MESHES) / name;
}

}  // namespace

TEST(Parameterize, APlaneMapsWithoutDistortion) {
  const SurfaceParameterization p =
      parameterize_surface(make_height_field(12, 30, [](double, double) { return 0.0; }));
  EXPECT_EQ(p.boundary_loops, 1);
  EXPECT_FALSE(p.periodic_u);
  EXPECT_EQ(p.flips, 0u);
  EXPECT_NEAR(p.length_u, 30, 1e-9);
  EXPECT_NEAR(p.length_v, 30, 1e-9);
  EXPECT_NEAR(p.area, 900, 1e-9);
  // Mean-value coordinates reproduce linear functions: the plane maps by a similarity.
  EXPECT_NEAR(p.area_scale.min, 1, 1e-9);
  EXPECT_NEAR(p.area_scale.max, 1, 1e-9);
  EXPECT_NEAR(p.angle_distortion.max, 1, 1e-9);
  // The corner where the boundary turns first goes to (0, 0) and u keeps the orientation.
  for (std::size_t i = 0; i < p.mesh.points.size(); ++i) {
    const Vec3 x = p.mesh.points[i];
    const double u = p.uv[i][0], v = p.uv[i][1];
    // (x, y)/30 up to a symmetry of the square that keeps orientation (a rotation).
    const double a = x.x / 30, b = x.y / 30;
    const bool rotation = (std::fabs(u - a) < 1e-9 && std::fabs(v - b) < 1e-9) ||
                          (std::fabs(u - (1 - b)) < 1e-9 && std::fabs(v - a) < 1e-9) ||
                          (std::fabs(u - (1 - a)) < 1e-9 && std::fabs(v - (1 - b)) < 1e-9) ||
                          (std::fabs(u - b) < 1e-9 && std::fabs(v - (1 - a)) < 1e-9);
    ASSERT_TRUE(rotation) << i << ": (" << x.x << ", " << x.y << ") -> (" << u << ", " << v << ")";
  }
}

TEST(Parameterize, GivenCornersAreTheSquaresCorners) {
  const TriangleSoup plane = make_height_field(6, 12, [](double, double) { return 0.0; });
  // Points 0, 6, 48, 42 are (0,0), (12,0), (12,12), (0,12).
  ParameterizeOptions o;
  o.corners = std::array<std::uint32_t, 4>{6, 48, 42, 0};
  const SurfaceParameterization p = parameterize_surface(plane, o);
  EXPECT_NEAR(p.uv[6][0], 0, 1e-12);
  EXPECT_NEAR(p.uv[6][1], 0, 1e-12);
  EXPECT_NEAR(p.uv[48][0], 1, 1e-12);
  EXPECT_NEAR(p.uv[48][1], 0, 1e-12);
  EXPECT_NEAR(p.uv[0][0], 0, 1e-12);
  EXPECT_NEAR(p.uv[0][1], 1, 1e-12);
  EXPECT_EQ(p.flips, 0u);
  o.corners = std::array<std::uint32_t, 4>{6, 42, 48, 0};  // not in order along the boundary
  EXPECT_THROW(parameterize_surface(plane, o), InputError);
  o.corners = std::array<std::uint32_t, 4>{6, 48, 42, 24};  // 24 is inside
  EXPECT_THROW(parameterize_surface(plane, o), InputError);
}

TEST(Parameterize, CurvedDisksHaveNoFlips) {
  // The square's own properties: mean-value coordinates inside a fixed convex boundary.
  const ParameterizeOptions square{.method = LayoutMethod::Square};
  const SurfaceParameterization hemi =
      parameterize_surface(make_spherical_cap(20, kPi / 2, 16, 48), square);
  EXPECT_EQ(hemi.flips, 0u);
  EXPECT_NEAR(hemi.area, 2 * kPi * 400, 0.01 * 2 * kPi * 400);
  EXPECT_GT(hemi.angle_distortion.p95, 1.0);  // a sphere cannot be laid flat without it
  const SurfaceParameterization wave = parameterize_surface(
      make_height_field(40, 40,
                        [](double x, double y) {
                          return 3 * std::sin(2 * kPi * x / 20) * std::sin(2 * kPi * y / 20);
                        }),
      square);
  EXPECT_EQ(wave.flips, 0u);
  // The waves vanish on the boundary: a square, scaled up to the surface's area.
  EXPECT_GT(wave.area, 1600 * 1.05);
  EXPECT_NEAR(wave.length_u, wave.length_v, 1e-9);
  EXPECT_NEAR(wave.length_u * wave.length_v, wave.area, 1e-6 * wave.area);
  EXPECT_GT(wave.area_scale.p95, 1.05);  // the slopes hold more surface than their share
  EXPECT_LT(wave.area_scale.p5, 0.95);   // the flat tops less
}

TEST(Parameterize, ATubeIsCutAlongASeam) {
  const double R = 5, H = 20;
  const SurfaceParameterization p = parameterize_surface(make_open_cylinder(R, H, 40, 16));
  EXPECT_EQ(p.boundary_loops, 2);
  EXPECT_TRUE(p.periodic_u);
  EXPECT_EQ(p.seam_edges, 16u);  // straight up one column of the cylinder
  EXPECT_EQ(p.flips, 0u);
  const double circumference = 40 * 2 * R * std::sin(kPi / 40);
  EXPECT_NEAR(p.length_u, circumference, 1e-9);
  EXPECT_NEAR(p.length_v, H, 1e-9);
  // A cylinder unrolls isometrically: no distortion at all.
  EXPECT_NEAR(p.angle_distortion.max, 1, 1e-6);
  EXPECT_NEAR(p.area_scale.max, 1, 1e-6);
  EXPECT_EQ(p.mesh.points.size(), 40u * 17u + 17u);  // the seam's 17 points doubled
}

TEST(Parameterize, AFreeLayoutKeepsCellsOnADeepCap) {
  // A bowl three quarters of a sphere deep: the square squeezes its middle into a small share
  // of the unit square, while the free layout keeps each triangle near its own size. Both have
  // no flips; the free one's area scale spreads far less, and auto takes it.
  const TriangleSoup bowl = make_spherical_cap(10, 0.75 * kPi, 32, 96);
  const SurfaceParameterization square =
      parameterize_surface(bowl, {.method = LayoutMethod::Square});
  const SurfaceParameterization free = parameterize_surface(bowl, {.method = LayoutMethod::Free});
  EXPECT_EQ(square.method, LayoutMethod::Square);
  EXPECT_EQ(free.method, LayoutMethod::Free);
  EXPECT_EQ(square.flips, 0u);
  EXPECT_EQ(free.flips, 0u);
  EXPECT_GT(free.free_iterations, 0);
  const auto ratio = [](const Spread& s) { return s.p95 / s.p5; };
  EXPECT_GT(ratio(square.area_scale), 5.0);
  EXPECT_LT(ratio(free.area_scale), 0.5 * ratio(square.area_scale));
  // Centred: the p5 and p95 of the area scale lie equally far from 1.
  EXPECT_NEAR(free.area_scale.p5 * free.area_scale.p95, 1.0, 1e-9);
  // The bounding box is the unit square and the slab holds the layout's own size.
  double lo = 1, hi = 0;
  for (const auto& uv : free.uv)
    for (double c : uv) lo = std::min(lo, c), hi = std::max(hi, c);
  EXPECT_NEAR(lo, 0, 1e-12);
  EXPECT_NEAR(hi, 1, 1e-12);
  const SurfaceParameterization chosen = parameterize_surface(bowl);
  EXPECT_EQ(chosen.method, LayoutMethod::Free);
  ASSERT_TRUE(chosen.other_area_scale.has_value());
  EXPECT_DOUBLE_EQ(chosen.other_area_scale->p95, square.area_scale.p95);
  // Corners belong to the square.
  ParameterizeOptions cornered{.method = LayoutMethod::Free};
  cornered.corners = std::array<std::uint32_t, 4>{0, 1, 2, 3};
  EXPECT_THROW(parameterize_surface(bowl, cornered), InputError);
  EXPECT_EQ(layout_method_from_name("free"), LayoutMethod::Free);
  EXPECT_THROW(layout_method_from_name("round"), InputError);
}

TEST(Parameterize, AFreeTubeStaysClosedAcrossItsSeam) {
  // A cone's frustum (radius 6 at the foot, 9 at the top): the square stretches the foot's
  // circumference to the top's, so its area scale spreads by about 1.5; the free layout may
  // bend and shear but each seam copy stays one period (u + 1) from its original, so a lattice
  // of whole cells along u closes around the tube.
  TriangleSoup frustum = make_open_cylinder(6, 12, 64, 12);
  for (Vec3& p : frustum.points) {
    const double r = 1 + 0.5 * p.z / 12;
    p.x *= r, p.y *= r;
  }
  const SurfaceParameterization square =
      parameterize_surface(frustum, {.method = LayoutMethod::Square});
  const SurfaceParameterization free =
      parameterize_surface(frustum, {.method = LayoutMethod::Free});
  EXPECT_TRUE(free.periodic_u);
  EXPECT_EQ(free.flips, 0u);
  const auto ratio = [](const Spread& s) { return s.p95 / s.p5; };
  EXPECT_GT(ratio(square.area_scale), 1.4);
  EXPECT_LT(ratio(free.area_scale), ratio(square.area_scale));
  // The seam's copies (the last 13 points) sit at u ± 1 of the points they copy, same v.
  const std::size_t n = free.mesh.points.size();
  std::size_t matched = 0;
  for (std::size_t c = n - 13; c < n; ++c)
    for (std::size_t i = 0; i < n - 13; ++i)
      if (free.mesh.points[i] == free.mesh.points[c]) {
        ++matched;
        EXPECT_NEAR(std::fabs(free.uv[c][0] - free.uv[i][0]), 1, 1e-9);
        EXPECT_NEAR(free.uv[c][1], free.uv[i][1], 1e-9);
      }
  EXPECT_EQ(matched, 13u);
  // The period lies between the foot's and the top's circumferences.
  EXPECT_GT(free.length_u, 2 * kPi * 6);
  EXPECT_LT(free.length_u, 2 * kPi * 9);
}

TEST(Parameterize, RefusesWhatIsNotADiskOrATube) {
  EXPECT_THROW(parameterize_surface(make_sphere({0, 0, 0}, 5, 2)), InputError);  // closed
  EXPECT_THROW(parameterize_surface(TriangleSoup{}), InputError);
  TriangleSoup torus = make_torus(10, 3, 24, 12);
  torus = without_triangles(torus, [](const Vec3& c) { return c.x > 12.5; });
  EXPECT_THROW(parameterize_surface(torus), InputError);  // a handle
  TriangleSoup flipped = flip(make_height_field(4, 4, [](double, double) { return 0.0; }), 5);
  EXPECT_THROW(parameterize_surface(flipped), InputError);  // orientation
  TriangleSoup two = concat(make_height_field(2, 1, [](double, double) { return 0.0; }),
                            make_height_field(2, 1, [](double, double) { return 5.0; }));
  EXPECT_THROW(parameterize_surface(two), InputError);  // two pieces
  ParameterizeOptions o;
  o.corners = std::array<std::uint32_t, 4>{0, 1, 2, 3};
  EXPECT_THROW(parameterize_surface(make_open_cylinder(2, 4, 12, 3), o),
               InputError);  // tube corners
}

TEST(Parameterize, DuplicatePointsAreMerged) {
  const TriangleSoup plane = make_height_field(5, 10, [](double x, double) { return 0.1 * x; });
  const SurfaceParameterization a = parameterize_surface(plane);
  const SurfaceParameterization b = parameterize_surface(unshare_points(plane));
  EXPECT_EQ(b.mesh.points.size(), a.mesh.points.size());
  EXPECT_EQ(b.flips, 0u);
  EXPECT_NEAR(b.area, a.area, 1e-9);
}

TEST(Parameterize, CgalDemoFacesHaveNoFlips) {
  for (const char* name : {"nefertiti.off", "lion-head.off", "mushroom.off"}) {
    const fs::path path = cgal_mesh(name);
    if (!fs::exists(path)) GTEST_SKIP() << path << " is missing: install libcgal-demo";
    const SurfaceParameterization p = parameterize_surface(read_mesh(path));
    EXPECT_EQ(p.boundary_loops, 1) << name;
    EXPECT_EQ(p.flips, 0u) << name;
    EXPECT_GE(p.angle_distortion.p5, 1.0) << name;
  }
  const fs::path blade = cgal_mesh("blade.off");
  if (!fs::exists(blade)) GTEST_SKIP() << blade << " is missing";
  const SurfaceParameterization p = parameterize_surface(read_mesh(blade));
  EXPECT_EQ(p.boundary_loops, 2);
  EXPECT_TRUE(p.periodic_u);
  EXPECT_EQ(p.flips, 0u);
}

TEST(Conformal, AGyroidLayerOnAHemisphereIsValidAndWithinItsHeight) {
  ConformalJobOptions o;
  o.layer.height = 2;
  o.design.cell = {4, 4, 4};
  o.grid.voxel_size = 0.25;
  const ConformalResult r = conformal_fill(make_spherical_cap(15, kPi / 2, 24, 64), o);
  const MeshCheck c = check_mesh(r.mesh);
  EXPECT_TRUE(c.valid()) << testing::PrintToString(c.problems());
  EXPECT_GT(r.mesh.triangles.size(), 1000u);
  // Every vertex lies in the layer, 0 <= h <= H, up to marching cubes' placement (a voxel),
  // and the layer reaches its full height.
  EXPECT_GE(r.report.height_min, -0.25);
  EXPECT_LE(r.report.height_max, 2 + 0.25);
  EXPECT_GT(r.report.height_max, 2 - 0.25);
  // Outward on a convex surface nothing folds.
  EXPECT_TRUE(std::isinf(r.report.focal_distance));
  // A vertex's distance from the sphere's centre is R + h.
  for (const Vec3& p : r.mesh.points) {
    ASSERT_GE(norm(p), 15 - 0.3);
    ASSERT_LE(norm(p), 17 + 0.3);
  }
  for (const std::string& w : r.fill.warnings) ADD_FAILURE() << w;
}

TEST(Conformal, ALayerInsideAHemisphereKnowsItsFocalDistance) {
  ConformalJobOptions o;
  o.layer.height = 2;
  o.layer.side = SurfaceSide::In;
  o.design.type = TpmsType::Primitive;
  o.design.cell = {4, 4, 4};
  o.grid.voxel_size = 0.3;
  const ConformalResult r = conformal_fill(make_spherical_cap(15, kPi / 2, 24, 64), o);
  EXPECT_TRUE(check_mesh(r.mesh).valid());
  EXPECT_NEAR(r.report.focal_distance, 15, 0.5);  // the sphere's radius
  for (const Vec3& p : r.mesh.points) {
    ASSERT_GE(norm(p), 13 - 0.35);
    ASSERT_LE(norm(p), 15 + 0.35);
  }
  // Thicker than the radius: warned, with the radius.
  o.layer.height = 16;
  o.grid.voxel_size = 1;
  o.design.cell = {8, 8, 8};
  const ConformalResult folded = conformal_fill(make_spherical_cap(15, kPi / 2, 12, 32), o);
  bool warned = false;
  for (const std::string& w : folded.fill.warnings)
    warned = warned || w.find("folds over itself") != std::string::npos;
  EXPECT_TRUE(warned);
}

TEST(Conformal, SkinsCloseTheLayerIntoAChannel) {
  ConformalJobOptions o;
  o.layer.height = 2;
  o.layer.skin_surface = 0.3;
  o.layer.skin_top = 0.3;
  o.design.cell = {4, 4, 4};
  o.grid.voxel_size = 0.2;
  const TriangleSoup plate = make_height_field(10, 20, [](double, double) { return 0.0; });
  const ConformalResult r = conformal_fill(plate, o);
  const MeshCheck c = check_mesh(r.mesh);
  EXPECT_TRUE(c.valid()) << testing::PrintToString(c.problems());
  // On a flat plate the layer is the box [0, 20]² × [0, 2]: both skins are whole, so every
  // point of the plate's top and of the layer's top is covered.
  EXPECT_NEAR(r.report.height_min, 0, 0.2);
  EXPECT_NEAR(r.report.height_max, 2, 0.2);
  ASSERT_TRUE(c.volume.has_value());
  EXPECT_GT(*c.volume, 2 * 0.3 * 400 * 0.9);  // at least the two skins
  EXPECT_LT(*c.volume, 2 * 400);
}

TEST(Conformal, ALayerAroundATubeClosesAcrossTheSeam) {
  ConformalJobOptions o;
  o.layer.height = 1.5;
  o.design.cell = {3, 3, 3};
  o.grid.voxel_size = 0.25;
  const ConformalResult r = conformal_fill(make_open_cylinder(6, 12, 64, 12), o);
  const MeshCheck c = check_mesh(r.mesh);
  EXPECT_TRUE(c.valid()) << testing::PrintToString(c.problems());
  // Lu is a whole number of 3 mm cells (the circumference is about 37.7 mm: 13 cells).
  EXPECT_NEAR(std::remainder(r.report.length_u, 3.0), 0.0, 1e-9);
  EXPECT_NEAR(r.report.length_u, 39.0, 1e-9);
  for (const Vec3& p : r.mesh.points) {
    const double radius = std::hypot(p.x, p.y);
    ASSERT_GE(radius, 6 - 0.3);
    ASSERT_LE(radius, 7.5 + 0.3);
  }
}

TEST(Conformal, ADeepBowlTakesTheFreeLayoutOrIsRefused) {
  // On the bowl the square would give cells from under half to over twice the size asked:
  // refused with the sizes. Auto lays it out freely and the layer is valid, within its
  // height, and its cells within 0.7-1.4 times the size asked (p5 to p95).
  const TriangleSoup bowl = make_spherical_cap(10, 0.75 * kPi, 24, 72);
  ConformalJobOptions o;
  o.layer.height = 1;
  o.design.cell = {3, 3, 3};
  o.grid.voxel_size = 0.15;
  o.layout.method = LayoutMethod::Square;
  try {
    conformal_fill(bowl, o);
    ADD_FAILURE() << "the square layout's cells were not refused";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("--allow-distortion"), std::string::npos) << e.what();
  }
  o.layout.method = LayoutMethod::Auto;
  const ConformalResult r = conformal_fill(bowl, o);
  EXPECT_EQ(r.report.layout.method, LayoutMethod::Free);
  const MeshCheck c = check_mesh(r.mesh);
  EXPECT_TRUE(c.valid()) << testing::PrintToString(c.problems());
  EXPECT_GE(r.report.height_min, -0.15);
  EXPECT_LE(r.report.height_max, 1 + 0.15);
  EXPECT_GE(r.report.cell_size.p5, 0.7 * 3);
  EXPECT_LE(r.report.cell_size.p95, 1.4 * 3);
  // The layer ends at the bowl's rim (radius 10 sin 135° about the axis, at z = 10 cos 135°):
  // no vertex beyond it by more than a voxel.
  for (const Vec3& p : r.mesh.points)
    ASSERT_GE(p.z, 10 * std::cos(0.75 * kPi) - 1.2) << p.x << " " << p.y << " " << p.z;
  // The vertex map lifts the square's slab: it takes the square (and refuses a free layout).
  o.map = SlabMap::Vertex;
  o.layout.method = LayoutMethod::Free;
  EXPECT_THROW(conformal_fill(bowl, o), InputError);
}

TEST(Conformal, OptionsAreChecked) {
  ConformalOptions o;
  EXPECT_THROW(require_valid(o), InputError);  // no height
  o.height = 1;
  EXPECT_NO_THROW(require_valid(o));
  o.skin_surface = 0.6, o.skin_top = 0.5;
  EXPECT_THROW(require_valid(o), InputError);  // no room left
  o.skin_top = 0, o.normal_scale = 0;
  EXPECT_THROW(require_valid(o), InputError);
  EXPECT_EQ(surface_side_from_name("in"), SurfaceSide::In);
  EXPECT_THROW(surface_side_from_name("up"), InputError);
}

namespace {

int cli(const std::string& args, std::string* out) {
  return run_command(std::string(TPMSFILL_CLI) + " " + args, out);
}

}  // namespace

TEST(ConformalCli, WritesAValidLayerAndItsReport) {
  const fs::path dir = scratch_dir();
  write_mesh(dir / "dome.off", make_spherical_cap(12, kPi / 2, 16, 48));
  std::string out;
  ASSERT_EQ(cli("conformal " + (dir / "dome.off").string() + " " + (dir / "layer.stl").string() +
                    " --height 2 --lattice diamond --cell 4 --voxel 0.3 --report " +
                    (dir / "layer.json").string(),
                &out),
            0)
      << out;
  EXPECT_NE(out.find("layout       a disk, "), std::string::npos) << out;
  EXPECT_NE(out.find(", 0 flips"), std::string::npos) << out;
  const MeshCheck c = check_mesh(read_mesh(dir / "layer.stl"));
  EXPECT_TRUE(c.valid()) << testing::PrintToString(c.problems());
  const std::string report = read_file(dir / "layer.json");
  for (const char* key : {"\"conformal\"", "\"angle_distortion\"", "\"cell_size\"", "\"flips\": 0"})
    EXPECT_NE(report.find(key), std::string::npos) << key;
}

TEST(ConformalCli, RefusesAClosedSurfaceAndBadFlags) {
  {
    const fs::path dir = scratch_dir();
    write_mesh(dir / "dome.off", make_spherical_cap(12, kPi / 2, 8, 24));
    std::string out;
    EXPECT_EQ(cli("conformal " + (dir / "dome.off").string() + " " + (dir / "l.stl").string() +
                      " --height 2 --layout round",
                  &out),
              2)
        << out;
    EXPECT_NE(out.find("unknown layout 'round'"), std::string::npos) << out;
    EXPECT_FALSE(fs::exists(dir / "l.stl"));
  }
  const fs::path dir = scratch_dir();
  write_mesh(dir / "ball.off", make_sphere({0, 0, 0}, 5, 2));
  write_mesh(dir / "dome.off", make_spherical_cap(12, kPi / 2, 8, 24));
  std::string out;
  EXPECT_EQ(cli("conformal " + (dir / "ball.off").string() + " " + (dir / "x.stl").string() +
                    " --height 1",
                &out),
            2);
  EXPECT_NE(out.find("closed"), std::string::npos) << out;
  EXPECT_FALSE(fs::exists(dir / "x.stl"));
  EXPECT_EQ(cli("conformal " + (dir / "dome.off").string() + " " + (dir / "x.stl").string() +
                    " --height 1 --skins 0.6 0.6",
                &out),
            2);
  EXPECT_NE(out.find("leave no room"), std::string::npos) << out;
  EXPECT_EQ(cli("conformal " + (dir / "dome.off").string() + " " + (dir / "x.stl").string() +
                    " --height 1 --side up",
                &out),
            2);
  EXPECT_NE(out.find("use out or in"), std::string::npos) << out;
  // A wrong unit: a 12 m dome under a 1 mm layer is named before the memory estimate refuses.
  EXPECT_EQ(cli("conformal " + (dir / "dome.off").string() + " " + (dir / "x.stl").string() +
                    " --height 1 --units m",
                &out),
            2);
  EXPECT_NE(out.find("implausible in m; if it is in millimetres, add --units mm"),
            std::string::npos)
      << out;
  EXPECT_FALSE(fs::exists(dir / "x.stl"));
}
