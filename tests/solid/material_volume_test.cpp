// A fitted solid's material sampled onto a volume (material_volume.hpp) and a lattice graded by
// it (design.hpp's volume ramps): a box with a linear material is sampled exactly, and grading
// by that material gives the field a linear ramp along the same direction gives.
#include <gtest/gtest.h>

#include <cmath>
#include <memory>
#include <tpmsfill/error.hpp>
#include <tpmsfill/lattice/design.hpp>
#include <tpmsfill/solid/cube_map.hpp>
#include <tpmsfill/solid/material_volume.hpp>

#include "test_util.hpp"

namespace tpmsfill {
namespace {

double linear(Vec3 p) {
  return 1 + 0.1 * p.x + 0.2 * p.y + 0.3 * p.z;
}

// A 20 × 10 × 10 mm box whose material is linear: G and M are exact from the start.
SolidSpline linear_box(double (*material)(Vec3)) {
  TetMesh box = test::make_tet_grid({0, 0, 0}, {20, 10, 10}, {4, 2, 2});
  for (const Vec3& p : box.points) box.material.push_back(material(p));
  return fit_solid_spline(box, map_to_cube(box)).spline;
}

TEST(MaterialVolume, BoxWithLinearMaterialIsSampledExactly) {
  const MaterialVolume mv = material_volume(linear_box(linear), {.cells = 20});
  const ScalarVolume& v = mv.volume;
  // 1 mm samples centred on the box, two beyond it on every side: none on its faces.
  ASSERT_EQ(v.dims, (std::array<int, 3>{24, 14, 14}));
  EXPECT_DOUBLE_EQ(v.spacing[0], 1);
  EXPECT_EQ(mv.inside, 20u * 10 * 10);
  EXPECT_NEAR(mv.min, linear({0.5, 0.5, 0.5}), 1e-9);
  EXPECT_NEAR(mv.max, linear({19.5, 9.5, 9.5}), 1e-9);
  for (int k = 0; k < v.dims[2]; ++k)
    for (int j = 0; j < v.dims[1]; ++j)
      for (int i = 0; i < v.dims[0]; ++i) {
        const Vec3 p = v.origin + Vec3{double(i), double(j), double(k)};
        const double value = v.at(i, j, k);
        const bool inside = p.x > 0 && p.x < 20 && p.y > 0 && p.y < 10 && p.z > 0 && p.z < 10;
        if (inside)
          ASSERT_NEAR(value, linear(p), 1e-7) << i << " " << j << " " << k;
        else  // extended outwards: within the solid's own range, never beyond it
          ASSERT_TRUE(value >= mv.min - 1e-12 && value <= mv.max + 1e-12) << value;
      }
  // Read back trilinearly anywhere between the inside samples: the material itself.
  for (int n = 0; n < 50; ++n) {
    const Vec3 p{0.5 + 19 * std::fmod(0.618 * n, 1.0), 0.5 + 9 * std::fmod(0.414 * n, 1.0),
                 0.5 + 9 * std::fmod(0.732 * n, 1.0)};
    EXPECT_NEAR(sample_volume(v, p), linear(p), 1e-7);
  }
}

TEST(MaterialVolume, GradingByTheMaterialIsTheRampItFollows) {
  // Material = z: grading porosity by the material from 2 to 8 is grading it along z from 2 to
  // 8 mm, node for node, wherever the volume's samples are inside the box.
  auto height = [](Vec3 p) { return p.z; };
  const auto volume = std::make_shared<const ScalarVolume>(
      material_volume(linear_box(+height), {.cells = 40}).volume);
  LatticeDesign by_material{{.type = TpmsType::Gyroid, .cell = {2.5, 2.5, 2.5}}};
  LatticeDesign along_z = by_material;
  by_material.grading.push_back({Graded::Porosity,
                                 {.shape = RampShape::Volume,
                                  .from = 2,
                                  .to = 8,
                                  .start = 0.4,
                                  .end = 0.8,
                                  .volume = volume}});
  along_z.grading.push_back({Graded::Porosity,
                             {.shape = RampShape::Linear,
                              .point = Vec3{},
                              .from = 2,
                              .to = 8,
                              .start = 0.4,
                              .end = 0.8}});
  const Grid grid{.origin = {1, 1, 1}, .spacing = 0.25, .dims = {73, 33, 33}};  // to 19, 9, 9
  const Field a = sample_field(design_source(by_material), grid);
  const Field b = sample_field(design_source(along_z), grid);
  for (std::size_t n = 0; n < a.values.size(); ++n)
    ASSERT_NEAR(a.values[n], b.values[n], 1e-5) << n;
  // A grading of the porosity really varies: the field differs from an ungraded one.
  const Field plain = sample_field(
      design_source(
          LatticeDesign{{.type = TpmsType::Gyroid, .cell = {2.5, 2.5, 2.5}, .porosity = 0.6}}),
      grid);
  double largest = 0;
  for (std::size_t n = 0; n < a.values.size(); ++n)
    largest = std::max(largest, double(std::fabs(a.values[n] - plain.values[n])));
  EXPECT_GT(largest, 0.1);
}

TEST(MaterialVolume, RefusalsSayWhy) {
  TetMesh box = test::make_tet_grid({0, 0, 0}, {4, 4, 4}, {1, 1, 1});
  const SolidSpline shape_only = fit_solid_spline(box, map_to_cube(box)).spline;
  EXPECT_THROW(material_volume(shape_only), InputError);  // no material to grade by
  EXPECT_THROW(material_volume(linear_box(linear), {.cells = 2}), InputError);
  LatticeDesign d;
  d.grading.push_back({Graded::Porosity, {.shape = RampShape::Volume, .start = 0.5, .end = 0.7}});
  EXPECT_THROW(require_valid(d), InputError);  // a volume ramp without its volume
  ScalarVolume unplaced{.dims = {2, 2, 2}, .values = std::vector<double>(8, 1.0)};
  d.grading[0].ramp.volume = std::make_shared<const ScalarVolume>(unplaced);
  EXPECT_THROW(require_valid(d), InputError);  // no spacing: not in mm
  unplaced.spacing = {1, 1, 1};
  d.grading[0].ramp.volume = std::make_shared<const ScalarVolume>(unplaced);
  EXPECT_NO_THROW(require_valid(d));
}

}  // namespace
}  // namespace tpmsfill
