// The solid spline model file (solid_model.hpp): what is written reads back bit-identically
// and evaluates the same; every truncation, a damaged byte and a later version are refused
// with the byte offset or the version.
#include <gtest/gtest.h>

#include <cmath>
#include <tpmsfill/error.hpp>
#include <tpmsfill/solid/cube_map.hpp>
#include <tpmsfill/solid/solid_model.hpp>

#include "test_util.hpp"

namespace tpmsfill {
namespace {

SolidFit small_fit(int uniform) {
  TetMesh blob = test::make_tet_grid({0, 0, 0}, {20, 10, 10}, {6, 3, 3}, 0.1);
  for (Vec3& p : blob.points) p = Vec3{p.x + std::sin(0.3 * p.y), p.y, p.z * (1 + 0.02 * p.x)};
  for (const Vec3& p : blob.points) blob.material.push_back(0.1 * p.x * p.x);
  const CubeMap map = map_to_cube(blob);
  return fit_solid_spline(
      blob, map,
      {.octree = {.max_per_cell = 2}, .uniform = uniform, .max_iterations = 5, .refinements = 1});
}

TEST(SolidModel, RoundTripsBitIdenticallyAndEvaluatesTheSame) {
  for (int uniform : {0, 6}) {
    SolidModel model{small_fit(uniform), "test: a warped box"};
    const std::string bytes = solid_model_bytes(model);
    const SolidModel back = parse_solid_model(bytes, "model.tsm");
    EXPECT_EQ(solid_model_bytes(back), bytes);
    EXPECT_EQ(back.provenance, model.provenance);
    ASSERT_EQ(back.fit.rounds.size(), model.fit.rounds.size());
    EXPECT_EQ(back.fit.rounds.back().geometry_rs, model.fit.rounds.back().geometry_rs);
    EXPECT_EQ(back.fit.spline.basis.functions.size(), model.fit.spline.basis.functions.size());
    for (const std::array<double, 3> p : {std::array<double, 3>{0.1, 0.2, 0.3}, {0.9, 0.5, 0.01}}) {
      const SolidPoint a = evaluate_solid(model.fit.spline, p),
                       b = evaluate_solid(back.fit.spline, p);
      EXPECT_EQ(a.position, b.position);
      EXPECT_EQ(a.material, b.material);
    }
  }
}

TEST(SolidModel, DamageIsRefusedWithItsByteOffset) {
  const std::string bytes = solid_model_bytes({small_fit(0), "x"});
  for (std::size_t n = 0; n < bytes.size(); n += (n < 64 ? 1 : 97)) {
    try {
      parse_solid_model(bytes.substr(0, n), "cut.tsm");
      FAIL() << "a file cut at byte " << n << " was read";
    } catch (const ParseError& e) {
      EXPECT_TRUE(e.byte_offset().has_value()) << e.what();
      EXPECT_LE(*e.byte_offset(), n);
    }
  }
  std::string damaged = bytes;
  damaged[bytes.size() - 20] ^= 0x10;  // inside the provenance or the report: only the CRC sees it
  EXPECT_THROW(parse_solid_model(damaged, "damaged.tsm"), ParseError);
  std::string later = bytes;
  later[4] = 2;
  try {
    parse_solid_model(later, "later.tsm");
    FAIL() << "version 2 was read";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("version 2"), std::string::npos) << e.what();
  }
  EXPECT_THROW(parse_solid_model("ITDF-not-this", "other.itdf"), ParseError);
  // A uniform basis of 512 per axis announced by a 40-byte file: refused before the basis is
  // built (134 million functions; the fuzzer found it as a 2 GB allocation).
  std::string huge("TSPL\x01\x00\x01\x00\x00\x02\x00\x00", 12);
  huge.append(28, '\0');
  try {
    parse_solid_model(huge, "huge.tsm");
    FAIL() << "a 512³ basis in 40 bytes was read";
  } catch (const ParseError& e) {
    EXPECT_NE(std::string(e.what()).find("512 per axis"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace tpmsfill
