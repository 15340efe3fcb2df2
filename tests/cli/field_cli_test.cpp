// `tpmsfill field fit|info|mesh` and `fill --field` (issue 13), end to end through the program.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <string>
#include <tpmsfill/io.hpp>
#include <tpmsfill/io/volume.hpp>
#include <tpmsfill/mesh/validate.hpp>
#include <tpmsfill/scan/itdf.hpp>

#include "test_util.hpp"

using namespace tpmsfill;

namespace {

int run(const std::string& args, std::string* out = nullptr) {
  return test::run_command(std::string(TPMSFILL_CLI) + " " + args + " 2>&1", out);
}

// A signed sponge field on 24³ cells of a 12 mm cube: distance to the nearest of a few pore
// centres minus 2 mm (negative in the pores), written in the seed's binary form.
std::filesystem::path sponge_field(const std::filesystem::path& dir) {
  ScalarVolume v;
  v.dims = {24, 24, 24};
  v.spacing = {0.5, 0.5, 0.5};
  v.origin = {0.25, 0.25, 0.25};
  v.sign = FieldSign::Signed;
  const double c[5][3] = {{3, 3, 3}, {9, 4, 6}, {5, 9, 9}, {2, 10, 3}, {10, 10, 11}};
  for (int k = 0; k < 24; ++k)
    for (int j = 0; j < 24; ++j)
      for (int i = 0; i < 24; ++i) {
        double best = 1e9;
        for (const auto& p : c)
          best = std::min(best, std::hypot(0.5 * i + 0.25 - p[0], 0.5 * j + 0.25 - p[1],
                                           0.5 * k + 0.25 - p[2]));
        v.values.push_back(best - 2);
      }
  write_volume(dir / "sponge.tdfb", v);
  return dir / "sponge.tdfb";
}

}  // namespace

TEST(FieldCli, FitInfoMeshAndFill) {
  const auto dir = test::scratch_dir();
  const auto field = sponge_field(dir);
  std::string out;
  // The pores are where C < 0: the solid is C >= 0 (--solid 0 inf).
  ASSERT_EQ(run("field fit " + field.string() + " " + (dir / "s.itdf").string() +
                    " --coefficients 16 --solid 0 inf",
                &out),
            0)
      << out;
  EXPECT_NE(out.find("16 x 16 x 16 coefficients"), std::string::npos) << out;
  const ItdfFile f = read_itdf(dir / "s.itdf");
  ASSERT_TRUE(f.fit);
  EXPECT_LT(f.fit->rms, 0.05);
  EXPECT_EQ(f.structure.size, (std::array<double, 3>{12, 12, 12}));
  ASSERT_EQ(run("field info " + (dir / "s.itdf").string(), &out), 0) << out;
  EXPECT_NE(out.find("12 x 12 x 12 mm"), std::string::npos) << out;

  // Meshed over its own box at a porosity of 0.6: closed, valid, porosity within one point.
  ASSERT_EQ(run("field mesh " + (dir / "s.itdf").string() + " " + (dir / "s.stl").string() +
                    " --voxel 0.2 --porosity 0.6",
                &out),
            0)
      << out;
  const TriangleSoup solid = read_mesh(dir / "s.stl");
  const double volume = test::signed_volume(solid);
  EXPECT_NEAR(1 - volume / (12.0 * 12 * 12), 0.6, 0.01) << out;
  EXPECT_NE(out.find("smaller"), std::string::npos) << out;
  // The storage line says which file is the larger, whichever it is (a coarse mesh is smaller
  // than its ITDF; it once printed "1x smaller" for an ITDF 1.8 times the STL).
  for (const char* voxel : {"0.2", "2"}) {
    ASSERT_EQ(run("field mesh " + (dir / "s.itdf").string() + " " + (dir / "c.stl").string() +
                      " --voxel " + voxel + " --porosity 0.6",
                  &out),
              0)
        << out;
    const bool itdf_larger =
        std::filesystem::file_size(dir / "s.itdf") > std::filesystem::file_size(dir / "c.stl");
    EXPECT_NE(out.find(itdf_larger ? "x larger" : "x smaller"), std::string::npos) << out;
  }
  // fit writes ITDF only: a mesh's name for it is refused before any work.
  EXPECT_EQ(run("field fit " + field.string() + " " + (dir / "fit.stl").string(), &out), 2);
  EXPECT_NE(out.find("named .itdf"), std::string::npos) << out;
  EXPECT_FALSE(std::filesystem::exists(dir / "fit.stl"));

  // To 3MF: validated as lib3mf's micrometres hold it, so the package reads back valid.
  ASSERT_EQ(run("field mesh " + (dir / "s.itdf").string() + " " + (dir / "s.3mf").string() +
                    " --voxel 0.4 --porosity 0.6",
                &out),
            0)
      << out;
  EXPECT_EQ(run("check " + (dir / "s.3mf").string(), &out), 0) << out;

  // The surface type without thickness: an open 2-manifold with a boundary on the box.
  ASSERT_EQ(run("field mesh " + (dir / "s.itdf").string() + " " + (dir / "open.ply").string() +
                    " --voxel 0.3 --surface 0",
                &out),
            0)
      << out;
  const MeshValidity open = validate_mesh(read_mesh(dir / "open.ply"));
  EXPECT_TRUE(open.manifold());
  EXPECT_GT(open.border_edges, 0u);
  EXPECT_EQ(open.inconsistent_edges, 0u);

  // fill --field: a sphere filled with the tiled sponge; TPMS flags are refused with it.
  write_mesh(dir / "ball.stl", test::make_sphere({0, 0, 0}, 10, 3));
  ASSERT_EQ(run("fill " + (dir / "ball.stl").string() + " " + (dir / "ball-out.ply").string() +
                    " --field " + (dir / "s.itdf").string() + " --cell 6 --voxel 0.25 --quiet",
                &out),
            0)
      << out;
  EXPECT_TRUE(validate_mesh(read_mesh(dir / "ball-out.ply")).valid());
  EXPECT_EQ(run("fill " + (dir / "ball.stl").string() + " " + (dir / "x.stl").string() +
                    " --field " + (dir / "s.itdf").string() + " --lattice diamond",
                &out),
            2);
  EXPECT_NE(out.find("--lattice describes a TPMS"), std::string::npos) << out;
}

// OpenVDB both ways through the program: fill writes its lattice as a level set (--field-out),
// which field info reads as signed, field mesh meshes and fill --field fills with (fitted on
// reading), each output a valid mesh; a wrong name is refused before any work.
TEST(FieldCli, AVdbFromFillFeedsFieldMeshAndFill) {
  if (!vdb_available()) GTEST_SKIP() << "built without OpenVDB";
  const auto dir = test::scratch_dir();
  write_mesh(dir / "box.stl", test::make_box({0, 0, 0}, {12, 12, 12}));
  std::string out;
  const std::string box = (dir / "box.stl").string(), phi = (dir / "phi.vdb").string();
  ASSERT_EQ(run("fill --quiet " + box + " " + (dir / "g.stl").string() +
                    " --cell 6 --voxel 0.3 --field-out " + phi,
                &out),
            0)
      << out;
  ASSERT_EQ(run("field info " + phi, &out), 0) << out;
  EXPECT_NE(out.find("signed"), std::string::npos) << out;
  ASSERT_EQ(
      run("field mesh --quiet " + phi + " " + (dir / "m.ply").string() + " --voxel 0.3", &out), 0)
      << out;
  EXPECT_TRUE(validate_mesh(read_mesh(dir / "m.ply")).valid());
  ASSERT_EQ(run("fill --quiet " + box + " " + (dir / "f.ply").string() + " --field " + phi +
                    " --voxel 0.3",
                &out),
            0)
      << out;
  EXPECT_TRUE(validate_mesh(read_mesh(dir / "f.ply")).valid());

  std::filesystem::remove(dir / "x.stl");
  EXPECT_EQ(run("fill " + box + " " + (dir / "x.stl").string() +
                    " --cell 6 --voxel 0.3 --field-out " + (dir / "phi.nrrd").string(),
                &out),
            2);
  EXPECT_NE(out.find("named .vdb"), std::string::npos) << out;
  EXPECT_FALSE(std::filesystem::exists(dir / "x.stl"));
}

TEST(FieldCli, BadInputsSayWhatAndWhere) {
  const auto dir = test::scratch_dir();
  test::write_file(dir / "bad.tdf", "4 4 4\n1 2 3\n");
  std::string out;
  EXPECT_EQ(run("field fit " + (dir / "bad.tdf").string() + " " + (dir / "o.itdf").string() +
                    " --solid 0 1",
                &out),
            2);
  EXPECT_NE(out.find("bad.tdf:1: 64 values declared, more than the file holds"), std::string::npos)
      << out;
  EXPECT_FALSE(std::filesystem::exists(dir / "o.itdf"));
  // Two counts are neither one nor three: a sentence before any work, not a crash.
  EXPECT_EQ(run("field fit " + (dir / "bad.tdf").string() + " " + (dir / "o.itdf").string() +
                    " --coefficients 8 9 --solid 0 1",
                &out),
            2);
  EXPECT_NE(out.find("--coefficients takes one count, or three"), std::string::npos) << out;
  // An unsigned field needs a structure; an ITDF without a size needs --size to be meshed.
  test::write_file(dir / "u.tdf",
                   "sign unsigned\n4 4 4\n" + std::string(64 * 2, ' ').replace(0, 0, [] {
                     std::string s;
                     for (int n = 0; n < 64; ++n) s += std::to_string(n % 5) + " ";
                     return s;
                   }()));
  EXPECT_EQ(run("field fit " + (dir / "u.tdf").string() + " " + (dir / "u.itdf").string(), &out),
            2);
  EXPECT_NE(out.find("needs a structure"), std::string::npos) << out;
  ASSERT_EQ(run("field fit " + (dir / "u.tdf").string() + " " + (dir / "u.itdf").string() +
                    " --solid 0 1 --quiet",
                &out),
            0)
      << out;
  EXPECT_EQ(run("field mesh " + (dir / "u.itdf").string() + " " + (dir / "u.stl").string() +
                    " --voxel 0.1",
                &out),
            2);
  EXPECT_NE(out.find("--size"), std::string::npos) << out;
  test::write_file(dir / "cut.itdf", test::read_file(dir / "u.itdf").substr(0, 60));
  EXPECT_EQ(run("field info " + (dir / "cut.itdf").string(), &out), 2);
  EXPECT_NE(out.find("byte"), std::string::npos) << out;
}

TEST(FieldCli, FromMeshPointsAndCtFeedTheFit) {
  // A sphere of radius 5 mm: from-mesh writes its signed distance; fitted, the stored
  // structure C <= 0 is the ball again (volume within 3 %).
  const auto dir = test::scratch_dir();
  write_mesh(dir / "ball.off", test::make_sphere({0, 0, 0}, 5, 4));
  std::string out;
  ASSERT_EQ(run("field from-mesh " + (dir / "ball.off").string() + " " +
                    (dir / "ball.tdfb").string() + " --voxel 0.5",
                &out),
            0)
      << out;
  EXPECT_NE(out.find("signed"), std::string::npos) << out;
  ASSERT_EQ(run("field fit " + (dir / "ball.tdfb").string() + " " + (dir / "ball.itdf").string() +
                    " --quiet",
                &out),
            0)
      << out;
  ASSERT_EQ(run("field mesh " + (dir / "ball.itdf").string() + " " + (dir / "ball.ply").string() +
                    " --voxel 0.2 --quiet",
                &out),
            0)
      << out;
  const TriangleSoup ball = read_mesh(dir / "ball.ply");
  EXPECT_TRUE(validate_mesh(ball).valid());
  const double sphere = 4.0 / 3 * M_PI * 125;
  EXPECT_NEAR(test::signed_volume(ball), sphere, 0.03 * sphere);
  // from-points and from-ct write fields that read back with their sign.
  test::write_file(dir / "p.xyz", "0 0 0\n1 0 0\n0 1 0\n0 0 1\n");
  ASSERT_EQ(run("field from-points " + (dir / "p.xyz").string() + " " + (dir / "p.nrrd").string() +
                    " --voxel 0.25 --quiet",
                &out),
            0)
      << out;
  EXPECT_EQ(read_volume_file(dir / "p.nrrd").volume.sign, FieldSign::Unsigned);
  ASSERT_EQ(run("field from-ct " + (dir / "ball.tdfb").string() + " " + (dir / "ct.tdf").string() +
                    " --iso 0 --below --quiet",
                &out),
            0)
      << out;
  EXPECT_EQ(read_volume_file(dir / "ct.tdf").volume.sign, FieldSign::Signed);
  EXPECT_EQ(
      run("field from-ct " + (dir / "ball.tdfb").string() + " " + (dir / "ct2.tdf").string(), &out),
      2);
  EXPECT_NE(out.find("--iso"), std::string::npos) << out;
}

TEST(FieldCli, EditChangesTheStructureWithoutRefitting) {
  // Issue 41 (seed 003: "edit further, then print"): field edit moves the thresholds to a
  // porosity, tiles, re-encodes C, and keeps the fitted C: the edited file meshes with the
  // porosity asked, its C is the fit's (to float32, or int16's quantum), the provenance says
  // what changed, and bad edits write nothing.
  const auto dir = test::scratch_dir();
  const auto field = sponge_field(dir);
  const std::string s = (dir / "s.itdf").string();
  std::string out;
  ASSERT_EQ(run("field fit " + field.string() + " " + s + " --coefficients 16 --solid 0 inf", &out),
            0)
      << out;
  const ItdfFile fitted = read_itdf(s);
  const std::string e = (dir / "e.itdf").string();
  ASSERT_EQ(run("field edit " + s + " " + e + " --porosity 0.7 --size 6 6 6 --tile", &out), 0)
      << out;
  EXPECT_NE(out.find("porosity"), std::string::npos) << out;
  const ItdfFile edited = read_itdf(e);
  EXPECT_EQ(edited.structure.field.coefficients, fitted.structure.field.coefficients);
  EXPECT_EQ(edited.structure.placement, Placement::Tile);
  EXPECT_EQ(edited.structure.size, (std::array<double, 3>{6, 6, 6}));
  ASSERT_TRUE(edited.fit);
  EXPECT_EQ(edited.fit->rms, fitted.fit->rms);
  EXPECT_NEAR(1 - porous_solid_share(edited.structure, edited.structure.size), 0.7, 0.01);
  EXPECT_EQ(edited.provenance.rfind(fitted.provenance, 0), 0u);
  EXPECT_NE(edited.provenance.find("field edit: structure"), std::string::npos)
      << edited.provenance;
  EXPECT_NE(edited.provenance.find("placement tile"), std::string::npos) << edited.provenance;
  // Meshed as stored, no flags: its 6 mm box at the edited porosity.
  ASSERT_EQ(run("field mesh " + e + " " + (dir / "e.stl").string() + " --voxel 0.1", &out), 0)
      << out;
  const double volume = test::signed_volume(read_mesh(dir / "e.stl"));
  EXPECT_NEAR(1 - volume / (6.0 * 6 * 6), 0.7, 0.015) << out;
  // In place, to int16: C within half a quantum of the fit's, the file smaller.
  ASSERT_EQ(run("field edit " + e + " --coefficient-type int16 --stretch --quiet", &out), 0) << out;
  EXPECT_TRUE(out.empty()) << out;
  const ItdfFile small = read_itdf(e);
  EXPECT_EQ(small.encoding[0].type, CoefficientType::Int16);
  EXPECT_EQ(small.structure.placement, Placement::Stretch);
  const auto& c0 = fitted.structure.field.coefficients;
  const auto& c1 = small.structure.field.coefficients;
  ASSERT_EQ(c0.size(), c1.size());
  const auto [lo, hi] = std::minmax_element(c0.begin(), c0.end());
  for (std::size_t i = 0; i < c0.size(); ++i)
    ASSERT_NEAR(c1[i], c0[i], 0.5 * (*hi - *lo) / 32767 * 1.01);
  EXPECT_LT(std::filesystem::file_size(e), std::filesystem::file_size(s));
  // Nothing to change, contradicting flags, a mesh name: refused, nothing written.
  const auto bytes = test::read_file(e);
  EXPECT_EQ(run("field edit " + e, &out), 2);
  EXPECT_NE(out.find("nothing to change"), std::string::npos) << out;
  EXPECT_EQ(run("field edit " + e + " --tile --stretch", &out), 2);
  EXPECT_NE(out.find("--tile or --stretch"), std::string::npos) << out;
  EXPECT_EQ(run("field edit " + e + " " + (dir / "x.stl").string() + " --porosity 0.5", &out), 2);
  EXPECT_NE(out.find("named .itdf"), std::string::npos) << out;
  EXPECT_FALSE(std::filesystem::exists(dir / "x.stl"));
  EXPECT_EQ(test::read_file(e), bytes);
  // The same value again: written, with a warning that nothing changed.
  ASSERT_EQ(run("field edit " + e + " --stretch", &out), 0) << out;
  EXPECT_NE(out.find("leave"), std::string::npos) << out;
}
