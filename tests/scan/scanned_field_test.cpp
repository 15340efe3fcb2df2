// Stage "scanned field" (issue 13): distance fields from a mesh, a point cloud and a CT, each
// against the analytic distance of the shape it came from.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <numbers>
#include <tpmsfill/error.hpp>
#include <tpmsfill/io.hpp>
#include <tpmsfill/scan/scanned_field.hpp>

#include "test_util.hpp"

using namespace tpmsfill;

namespace {

Vec3 centre_of(const ScalarVolume& v, int i, int j, int k) {
  return {v.origin.x + i * v.spacing[0], v.origin.y + j * v.spacing[1],
          v.origin.z + k * v.spacing[2]};
}

// The largest |value − expected(p)| over the cells.
template <class F>
double worst(const ScalarVolume& v, F expected) {
  double e = 0;
  for (int k = 0; k < v.dims[2]; ++k)
    for (int j = 0; j < v.dims[1]; ++j)
      for (int i = 0; i < v.dims[0]; ++i)
        e = std::max(e, std::fabs(v.at(i, j, k) - expected(centre_of(v, i, j, k))));
  return e;
}

}  // namespace

TEST(ScannedField, MeshGivesItsExactSignedDistance) {
  // An icosphere of radius 5: inside negative; off by at most its chordal error (the flat
  // faces lie inside the sphere by up to r (1 − cos θ)) plus nothing from the grid.
  const double r = 5;
  const TriangleSoup sphere = test::make_sphere({0, 0, 0}, r, 4);
  const ScalarVolume v = field_from_mesh(sphere, {.voxel = 0.4});
  EXPECT_EQ(v.sign, FieldSign::Signed);
  EXPECT_LT(worst(v, [&](Vec3 p) { return norm(p) - r; }), 0.05);
  EXPECT_LT(v.at(v.dims[0] / 2, v.dims[1] / 2, v.dims[2] / 2), -4.5);  // the centre is inside
  // A messy mesh: holes and flipped faces, still signed by the winding number.
  // A cap of the sphere cut away (a hole of about 2 mm) and one face flipped.
  TriangleSoup messy =
      test::flip(test::without_triangles(sphere, [](const Vec3& c) { return c.z > 4.8; }), 7);
  const ScalarVolume m = field_from_mesh(messy, {.voxel = 0.4});
  EXPECT_LT(m.at(m.dims[0] / 2, m.dims[1] / 2, m.dims[2] / 2), -4);
  EXPECT_THROW(field_from_mesh(sphere, {.voxel = 0.001, .max_cells = 1000000}), ResourceError);
}

TEST(ScannedField, PointsGiveTheExactDistanceToTheNearest) {
  // Points on a sphere (a Fibonacci lattice): the field is the distance to the nearest point,
  // checked against brute force; it is near | |p| − r | up to the gap between points.
  std::vector<Vec3> points;
  const int n = 2000;
  for (int i = 0; i < n; ++i) {
    const double z = 1 - (2 * i + 1.0) / n, rho = std::sqrt(1 - z * z);
    const double phi = i * std::numbers::pi * (3 - std::sqrt(5.0));
    points.push_back({4 * rho * std::cos(phi), 4 * rho * std::sin(phi), 4 * z});
  }
  const ScalarVolume v = field_from_points(points, {.voxel = 0.5});
  EXPECT_EQ(v.sign, FieldSign::Unsigned);
  const double brute = worst(v, [&](Vec3 p) {
    double best = INFINITY;
    for (const Vec3& q : points) best = std::min(best, norm(p - q));
    return best;
  });
  EXPECT_LT(brute, 1e-9);
  EXPECT_LT(worst(v, [](Vec3 p) { return std::fabs(norm(p) - 4); }), 0.2);
  EXPECT_THROW(field_from_points({}, {.voxel = 1}), InputError);
}

TEST(ScannedField, FlatAndCollinearCloudsAreExactToo) {
  // A plate scanned from one side (every z = 0) and points along a line: boxes without volume,
  // on which a search in growing shells of buckets never stopped.
  std::vector<Vec3> plate, line;
  for (int i = 0; i < 30; ++i) {
    for (int j = 0; j < 30; ++j) plate.push_back({i / 3.0, j / 3.0, 0});
    line.push_back({0.5 * i, 0, 0});
  }
  for (const std::vector<Vec3>* cloud : {&plate, &line}) {
    const ScalarVolume v = field_from_points(*cloud, {.voxel = 0.5});
    EXPECT_LT(worst(v,
                    [&](Vec3 p) {
                      double best = INFINITY;
                      for (const Vec3& q : *cloud) best = std::min(best, norm(p - q));
                      return best;
                    }),
              1e-9);
  }
}

TEST(ScannedField, CtGivesASignedDistanceWithinAVoxel) {
  // A ball of radius 6 mm in a CT with anisotropic voxels (0.5 × 0.5 × 0.8 mm).
  ScalarVolume ct;
  ct.dims = {40, 40, 25};
  ct.spacing = {0.5, 0.5, 0.8};
  ct.origin = {-9.75, -9.75, -9.6};
  for (int k = 0; k < 25; ++k)
    for (int j = 0; j < 40; ++j)
      for (int i = 0; i < 40; ++i) ct.values.push_back(norm(centre_of(ct, i, j, k)) < 6 ? 1000 : 0);
  const ScalarVolume v = field_from_ct(ct, 500);
  EXPECT_EQ(v.sign, FieldSign::Signed);
  EXPECT_LT(worst(v, [](Vec3 p) { return norm(p) - 6; }), 0.8);
  EXPECT_THROW(field_from_ct(ct, 5000), InputError);  // nothing is solid
}

TEST(ScannedField, PointFilesReadWithLineNumbers) {
  const auto dir = test::scratch_dir();
  test::write_file(dir / "a.xyz", "# scan\n0 0 0 0 0 1\n1,2,3\n\n4 5 6\n");
  const std::vector<Vec3> p = read_points(dir / "a.xyz");
  ASSERT_EQ(p.size(), 3u);
  EXPECT_EQ(p[1].y, 2);
  test::write_file(dir / "b.xyz", "0 0 0\n1 2\n");
  try {
    read_points(dir / "b.xyz");
    ADD_FAILURE();
  } catch (const ParseError& e) {
    EXPECT_EQ(e.line(), 2u);
  }
  // A PLY of vertices only (no faces): the points.
  test::write_file(dir / "c.ply",
                   "ply\nformat ascii 1.0\nelement vertex 2\nproperty float x\nproperty float "
                   "y\nproperty float z\nend_header\n1 2 3\n4 5 6\n");
  EXPECT_EQ(read_points(dir / "c.ply").size(), 2u);
}
