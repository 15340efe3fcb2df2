// The tet-mesh readers and writer (tet_mesh.hpp): round trips in every format, small
// hand-written files of each, and malformed files (the documented exception, at the right line
// or byte).
// GCC 12 at -O3 warns falsely (-Wrestrict, GCC bug 105651) inside <string> on `"literal" +
// std::string` once inlined; it can only be silenced before the first include.
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC diagnostic ignored "-Wrestrict"
#endif

#include <gtest/gtest.h>

#include <bit>
#include <charconv>
#include <cmath>
#include <cstring>
#include <functional>
#include <limits>
#include <string>
#include <tpmsfill/error.hpp>
#include <tpmsfill/solid/tet_mesh.hpp>

#include "test_util.hpp"

using namespace tpmsfill;

namespace {

// Two tets sharing a face, with coordinates and material that only a shortest round-trip
// text keeps bit-identical.
TetMesh two_tets(bool material) {
  TetMesh mesh;
  mesh.points = {
      {0.1, 0.2, 1.0 / 3.0}, {1.0, -0.0, 1e-300}, {0, 1, 2.5e17}, {0, 0, 1}, {0.7, 0.7, -0.7}};
  mesh.tets = {{0, 1, 2, 3}, {1, 2, 3, 4}};
  if (material) mesh.material = {0.5, 1.0 / 7.0, -2.25, 1e-12, 3.0};
  return mesh;
}

void expect_same(const TetMesh& a, const TetMesh& b) {
  ASSERT_EQ(a.points.size(), b.points.size());
  for (std::size_t i = 0; i < a.points.size(); ++i) {
    EXPECT_EQ(std::bit_cast<std::uint64_t>(a.points[i].x),
              std::bit_cast<std::uint64_t>(b.points[i].x));
    EXPECT_EQ(std::bit_cast<std::uint64_t>(a.points[i].y),
              std::bit_cast<std::uint64_t>(b.points[i].y));
    EXPECT_EQ(std::bit_cast<std::uint64_t>(a.points[i].z),
              std::bit_cast<std::uint64_t>(b.points[i].z));
  }
  EXPECT_EQ(a.tets, b.tets);
  ASSERT_EQ(a.material.size(), b.material.size());
  for (std::size_t i = 0; i < a.material.size(); ++i)
    EXPECT_EQ(std::bit_cast<std::uint64_t>(a.material[i]),
              std::bit_cast<std::uint64_t>(b.material[i]));
}

std::string num(double v) {
  char buf[32];
  const auto r = std::to_chars(buf, buf + sizeof buf, v);
  return std::string(buf, r.ptr);
}

// Expects `f` to throw a ParseError at `line` (text) or `byte` (binary) of `source`.
void expect_parse_error(const std::function<void()>& f, const std::string& source,
                        std::optional<std::uint64_t> line, std::optional<std::uint64_t> byte = {}) {
  try {
    f();
    ADD_FAILURE() << source << ": no exception";
  } catch (const ParseError& e) {
    EXPECT_EQ(e.source(), source) << e.what();
    EXPECT_EQ(e.line(), line) << e.what();
    EXPECT_EQ(e.byte_offset(), byte) << e.what();
    EXPECT_EQ(std::string(e.what()).find('\n'), std::string::npos);
  } catch (const std::exception& e) {
    ADD_FAILURE() << source << ": wrong exception: " << e.what();
  }
}

template <typename E>
void expect_error(const std::function<void()>& f, const std::string& words) {
  try {
    f();
    ADD_FAILURE() << "no exception, expected: " << words;
  } catch (const E& e) {
    EXPECT_NE(std::string(e.what()).find(words), std::string::npos) << e.what();
  } catch (const std::exception& e) {
    ADD_FAILURE() << "wrong exception: " << e.what();
  }
}

TetMesh medit(const std::string& mesh, const std::string& sol = {}) {
  return parse_tet_mesh(TetFormat::Medit, mesh, "a.mesh", sol, "a.sol");
}
TetMesh tetgen(const std::string& node, const std::string& ele) {
  return parse_tet_mesh(TetFormat::TetGen, node, "a.node", ele, "a.ele");
}
TetMesh vtk(const std::string& bytes, const std::string& material = {}) {
  TetReadOptions options;
  options.material_name = material;
  return parse_tet_mesh(TetFormat::Vtk, bytes, "a.vtk", {}, {}, options);
}

// Big-endian binary values, as legacy VTK stores them.
std::string be32(std::uint32_t v) {
  std::string out(4, '\0');
  for (int i = 0; i < 4; ++i) out[3 - i] = static_cast<char>(v >> (8 * i) & 0xff);
  return out;
}
std::string be64(std::uint64_t v) {
  std::string out(8, '\0');
  for (int i = 0; i < 8; ++i) out[7 - i] = static_cast<char>(v >> (8 * i) & 0xff);
  return out;
}
std::string be_float(float v) {
  return be32(std::bit_cast<std::uint32_t>(v));
}
std::string be_double(double v) {
  return be64(std::bit_cast<std::uint64_t>(v));
}

const std::string kUnitTetNode = "4 3 0 0\n0 0 0 0\n1 1 0 0\n2 0 1 0\n3 0 0 1\n";
const std::string kUnitTetMedit =
    "MeshVersionFormatted 2\nDimension 3\nVertices\n4\n0 0 0 0\n1 0 0 0\n0 1 0 0\n0 0 1 0\n"
    "Tetrahedra\n1\n1 2 3 4 0\nEnd\n";
const std::string kVtkHead =
    "# vtk DataFile Version 3.0\ntitle\nASCII\nDATASET UNSTRUCTURED_GRID\n";
const std::string kVtkUnitTet =
    kVtkHead + "POINTS 4 float\n0 0 0 1 0 0\n0 1 0 0 0 1\nCELLS 1 5\n4 0 1 2 3\nCELL_TYPES 1\n10\n";

}  // namespace

TEST(TetIo, FormatNames) {
  EXPECT_EQ(tet_format_name(TetFormat::Auto), "auto");
  EXPECT_EQ(tet_format_name(TetFormat::Medit), "MEDIT");
  EXPECT_EQ(tet_format_name(TetFormat::TetGen), "TetGen");
  EXPECT_EQ(tet_format_name(TetFormat::Vtk), "VTK");
}

TEST(TetIo, RoundTripMeditWithSol) {
  const auto dir = test::scratch_dir();
  const TetMesh mesh = two_tets(true);
  write_tet_mesh(dir / "m.mesh", mesh);
  ASSERT_TRUE(std::filesystem::exists(dir / "m.sol"));
  expect_same(read_tet_mesh(dir / "m.mesh"), mesh);
  // The .sol named explicitly, and the format forced.
  std::filesystem::rename(dir / "m.sol", dir / "other.sol");
  TetReadOptions options;
  options.format = TetFormat::Medit;
  options.material_file = dir / "other.sol";
  expect_same(read_tet_mesh(dir / "m.mesh", options), mesh);
  EXPECT_TRUE(read_tet_mesh(dir / "m.mesh").material.empty());
}

TEST(TetIo, RoundTripMeditWithoutMaterialWritesNoSol) {
  const auto dir = test::scratch_dir();
  const TetMesh mesh = two_tets(false);
  write_tet_mesh(dir / "m.mesh", two_tets(true));  // an old material beside it goes
  ASSERT_TRUE(std::filesystem::exists(dir / "m.sol"));
  write_tet_mesh(dir / "m.mesh", mesh);
  EXPECT_FALSE(std::filesystem::exists(dir / "m.sol"));
  expect_same(read_tet_mesh(dir / "m.mesh"), mesh);
}

TEST(TetIo, RoundTripVtk) {
  const auto dir = test::scratch_dir();
  for (const bool material : {true, false}) {
    const TetMesh mesh = two_tets(material);
    write_tet_mesh(dir / "m.vtk", mesh);
    expect_same(read_tet_mesh(dir / "m.vtk"), mesh);
    TetReadOptions options;
    options.material_name = "material";
    if (material) expect_same(read_tet_mesh(dir / "m.vtk", options), mesh);
  }
}

TEST(TetIo, RoundTripTetGenWrittenByTheTest) {
  // No TetGen writer: the test writes the pair, 1-based, with the material as attribute.
  const TetMesh mesh = two_tets(true);
  std::string node = "# made by the test\n5 3 1 1\n";
  for (std::size_t i = 0; i < mesh.points.size(); ++i) {
    const Vec3& p = mesh.points[i];
    node += std::to_string(i + 1) + " " + num(p.x) + " " + num(p.y) + " " + num(p.z) + " " +
            num(mesh.material[i]) + " 0\n";
  }
  std::string ele = "2 4 0\n";
  for (std::size_t i = 0; i < mesh.tets.size(); ++i) {
    ele += std::to_string(i + 1);
    for (const std::uint32_t v : mesh.tets[i]) ele += " " + std::to_string(v + 1);
    ele += "\n";
  }
  const auto dir = test::scratch_dir();
  test::write_file(dir / "t.node", node);
  test::write_file(dir / "t.ele", ele);
  expect_same(read_tet_mesh(dir / "t.node"), mesh);
  expect_same(read_tet_mesh(dir / "t.ele"), mesh);
}

TEST(TetIo, MeditHandWritten) {
  // CRLF, comments, any case, skipped sections, counts on the keyword's line or the next.
  const std::string mesh =
      "# from a mesher\r\nMeshVersionFormatted 1\r\ndimension\r\n3\r\n"
      "Vertices 5\r\n0 0 0 1\r\n1 0 0 1\r\n0 1 0 1 # comment\r\n0 0 1 2\r\n9 9 9 0\r\n"
      "Edges\r\n1\r\n1 2 0\r\nTriangles\r\n2\r\n1 2 3 0\r\n1 2 4 0\r\n"
      "Corners 1 1\r\nRidges 1 1\r\nRequiredVertices 2 1 2\r\n"
      "Normals 1 0 0 1\r\nNormalAtVertices 1 1 1\r\nTangents 1 1 0 0\r\n"
      "TangentAtVertices 1 1 1\r\n"
      "TETRAHEDRA\r\n1\r\n1 2 3 4 7\r\nHexahedra 1\r\n1 2 3 4 1 2 3 4 0\r\nEnd\r\n";
  const std::string sol =
      "MeshVersionFormatted 2\r\nDimension 3\r\n# a vector, then two scalars\r\n"
      "SolAtVertices\r\n5\r\n3 2 1 1\r\n0 0 0 10 -1\r\n0 0 0 11 -1\r\n0 0 0 12 -1\r\n"
      "0 0 0 13 -1\r\n0 0 0 14 -1\r\nEnd\r\n";
  const TetMesh m = medit(mesh, sol);
  ASSERT_EQ(m.points.size(), 5u);
  EXPECT_EQ(m.points[3].z, 1.0);
  ASSERT_EQ(m.tets.size(), 1u);
  EXPECT_EQ(m.tets[0], (Tet{0, 1, 2, 3}));
  EXPECT_EQ(m.material, (std::vector<double>{10, 11, 12, 13, 14}));
  EXPECT_TRUE(medit(mesh).material.empty());
}

TEST(TetIo, MeditSecondOrderTetsKeepTheirCorners) {
  const std::string mesh =
      "MeshVersionFormatted 2\nDimension 3\nVertices\n4\n0 0 0 0\n1 0 0 0\n0 1 0 0\n0 0 1 0\n"
      "TetrahedraP2\n1\n1 2 3 4 1 2 3 4 1 2 0\nEnd\n";
  EXPECT_EQ(medit(mesh).tets, (std::vector<Tet>{{0, 1, 2, 3}}));
  // Tetrahedra before their Vertices are checked once the Vertices are read.
  EXPECT_EQ(medit("Tetrahedra 1 1 2 3 4 0 Vertices 4 0 0 0 0 1 0 0 0 0 1 0 0 0 0 1 0").tets,
            (std::vector<Tet>{{0, 1, 2, 3}}));
  expect_parse_error(
      [] { medit("Tetrahedra 1\n1 2 3 5 0\nVertices 4 0 0 0 0 1 0 0 0 0 1 0 0 0 0 1 0"); },
      "a.mesh", 1);
}

TEST(TetIo, TetGenZeroAndOneBasedTenNodeCrlf) {
  const TetMesh zero = tetgen(kUnitTetNode, "1 4 0\n0 0 1 2 3\n");
  EXPECT_EQ(zero.tets, (std::vector<Tet>{{0, 1, 2, 3}}));
  EXPECT_TRUE(zero.material.empty());
  const std::string node =
      "# header\r\n4  3  2  1\r\n\r\n1 0 0 0 5.5 7 1\r\n2 1 0 0 6.5 7 0\r\n# a comment line\r\n"
      "3 0 1 0 7.5 7 0\r\n4 0 0 1 8.5 7 1 # trailing\r\n";
  const std::string ele = "1 10 1\r\n1 1 2 3 4 1 2 3 4 1 2 -3\r\n";
  const TetMesh one = tetgen(node, ele);
  EXPECT_EQ(one.tets, (std::vector<Tet>{{0, 1, 2, 3}}));
  EXPECT_EQ(one.material, (std::vector<double>{5.5, 6.5, 7.5, 8.5}));
  EXPECT_EQ(one.points[1].x, 1.0);
  // Without the optional marker count and ele attribute count.
  EXPECT_EQ(tetgen("4 3 0\n0 0 0 0\n1 1 0 0\n2 0 1 0\n3 0 0 1\n", "1 4\n0 3 2 1 0\n").tets,
            (std::vector<Tet>{{3, 2, 1, 0}}));
}

TEST(TetIo, VtkLegacyAsciiMixedCellsAndArrays) {
  std::string tensors;
  for (int i = 0; i < 45; ++i) tensors += "0 ";
  const std::string f =
      "# vtk DataFile Version 4.2\nmixed\nascii\nDATASET UNSTRUCTURED_GRID\n"
      "FIELD FieldData 1\nTIME 1 1 double\n0.5\n"
      "POINTS 5 double\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n1 1 1\n"
      "CELLS 4 17\n3 0 1 2\n4 0 1 2 3\n2 3 4\n4 1 2 3 4\n"
      "CELL_TYPES 4\n5\n10\n3\n10\n"
      "CELL_DATA 4\nSCALARS region int 1\nLOOKUP_TABLE default\n1 2 3 4\n"
      "VECTORS flow float\n0 0 0 1 1 1 2 2 2 3 3 3\n"
      "POINT_DATA 5\nVECTORS velocity double\n0 0 0 0 0 0 0 0 0 0 0 0 0 0 0\n"
      "METADATA\nINFORMATION 0\n\n"
      "SCALARS rgb float 3\nLOOKUP_TABLE default\n0 0 0 0 0 0 0 0 0 0 0 0 0 0 0\n"
      "SCALARS density float\nLOOKUP_TABLE my_table\n1 2 3 4 5\n"
      "LOOKUP_TABLE my_table 2\n0 0 0 1 1 1 1 1\n"
      "NORMALS n float\n0 0 1 0 0 1 0 0 1 0 0 1 0 0 1\n"
      "TEXTURE_COORDINATES uv 2 float\n0 0 1 0 0 1 1 1 0.5 0.5\n"
      "TENSORS t float\n" +
      tensors +
      "\nFIELD more 2\nporosity 1 5 double\n0.1 0.2 0.3 0.4 0.5\n"
      "grad 3 5 float\n0 0 0 0 0 0 0 0 0 0 0 0 0 0 0\n";
  const TetMesh m = vtk(f);
  EXPECT_EQ(m.points.size(), 5u);
  EXPECT_EQ(m.tets, (std::vector<Tet>{{0, 1, 2, 3}, {1, 2, 3, 4}}));
  EXPECT_EQ(m.material, (std::vector<double>{1, 2, 3, 4, 5}));  // the first 1-component one
  EXPECT_EQ(vtk(f, "porosity").material, (std::vector<double>{0.1, 0.2, 0.3, 0.4, 0.5}));
  EXPECT_EQ(vtk(f, "density").material, (std::vector<double>{1, 2, 3, 4, 5}));
  try {
    vtk(f, "stiffness");
    ADD_FAILURE() << "no exception";
  } catch (const ParseError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("'stiffness'"), std::string::npos) << what;
    EXPECT_NE(what.find("'density'"), std::string::npos) << what;
    EXPECT_NE(what.find("'porosity'"), std::string::npos) << what;
    EXPECT_EQ(e.line(), 30u) << what;  // the POINT_DATA line
  }
  expect_parse_error([&] { vtk(f, "rgb"); }, "a.vtk", 36);  // 3 components
}

TEST(TetIo, VtkOtherAttributesAreTheMaterialOnlyWhenNamed) {
  const std::string f = kVtkUnitTet +
                        "POINT_DATA 4\nTEXTURE_COORDINATES t 1 float\n1 2 3 4\n"
                        "GLOBAL_IDS ids int\n5 6 7 8\nSCALARS s float\n9 10 11 12\n";
  EXPECT_EQ(vtk(f).material, (std::vector<double>{9, 10, 11, 12}));  // no LOOKUP_TABLE: fine
  EXPECT_EQ(vtk(f, "t").material, (std::vector<double>{1, 2, 3, 4}));
  EXPECT_EQ(vtk(f, "ids").material, (std::vector<double>{5, 6, 7, 8}));
}

TEST(TetIo, Vtk51OffsetsAndConnectivity) {
  const std::string file =
      "# vtk DataFile Version 5.1\nvtk output\nASCII\nDATASET UNSTRUCTURED_GRID\n"
      "POINTS 5 float\n0 0 0 1 0 0 0 1 0\n0 0 1 1 1 1\n"
      "METADATA\nINFORMATION 2\nNAME L2_NORM_RANGE LOCATION vtkDataArray\nDATA 2 0 1.73\n"
      "NAME L2_NORM_FINITE_RANGE LOCATION vtkDataArray\nDATA 2 0 1.73\n\n"
      "CELLS 4 11\nOFFSETS vtktypeint64\n0 4 7 11\nCONNECTIVITY vtktypeint64\n"
      "0 1 2 3\n0 1 2\n1 2 3 4\n"
      "CELL_TYPES 3\n10\n5\n10\n"
      "POINT_DATA 5\nFIELD FieldData 1\nE 1 5 double\n1 2 3 4 5\n"
      "METADATA\nINFORMATION 0\n\n";
  const TetMesh m = vtk(file);
  EXPECT_EQ(m.tets, (std::vector<Tet>{{0, 1, 2, 3}, {1, 2, 3, 4}}));
  EXPECT_EQ(m.material, (std::vector<double>{1, 2, 3, 4, 5}));
}

TEST(TetIo, VtkBinaryBigEndianClassicAnd51) {
  std::string classic = "# vtk DataFile Version 3.0\nbin\nBINARY\nDATASET UNSTRUCTURED_GRID\n";
  classic += "POINTS 5 float\n";
  const float xyz[] = {0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1, 1, 1, 1};
  for (const float v : xyz) classic += be_float(v);
  classic += "\nCELLS 2 9\n";
  for (const std::uint32_t v : {4u, 0u, 1u, 2u, 3u, 3u, 2u, 3u, 4u}) classic += be32(v);
  classic += "\nCELL_TYPES 2\n" + be32(10) + be32(5);
  classic += "\nPOINT_DATA 5\nSCALARS m double 1\nLOOKUP_TABLE default\n";
  for (const double v : {0.5, 1.5, 2.5, 3.5, 10.0}) classic += be_double(v);
  classic += "\n";
  const TetMesh a = vtk(classic);
  EXPECT_EQ(a.points[4].z, 1.0f);
  EXPECT_EQ(a.tets, (std::vector<Tet>{{0, 1, 2, 3}}));
  EXPECT_EQ(a.material, (std::vector<double>{0.5, 1.5, 2.5, 3.5, 10.0}));

  std::string v51 = "# vtk DataFile Version 5.1\nbin\nBINARY\nDATASET UNSTRUCTURED_GRID\n";
  v51 += "POINTS 4 double\n";
  for (const double v : {0., 0., 0., 1., 0., 0., 0., 1., 0., 0., 0., 1.}) v51 += be_double(v);
  v51 += "\nCELLS 2 4\nOFFSETS vtktypeint64\n" + be64(0) + be64(4);
  v51 += "\nCONNECTIVITY vtktypeint64\n" + be64(3) + be64(2) + be64(1) + be64(0);
  v51 += "\nCELL_TYPES 1\n" + be32(10) + "\n";
  EXPECT_EQ(vtk(v51).tets, (std::vector<Tet>{{3, 2, 1, 0}}));
}

TEST(TetIo, ReadTetMeshFilesAndLimits) {
  const auto dir = test::scratch_dir();
  test::write_file(dir / "u.node", kUnitTetNode);
  expect_error<IoError>([&] { read_tet_mesh(dir / "u.node"); }, "u.ele");
  test::write_file(dir / "u.ele", "1 4 0\n0 0 1 2 3\n");
  EXPECT_EQ(read_tet_mesh(dir / "u.ele").tets.size(), 1u);
  TetReadOptions tetgen_base;  // TetGen's base name: u.node and u.ele
  tetgen_base.format = TetFormat::TetGen;
  EXPECT_EQ(read_tet_mesh(dir / "u", tetgen_base).tets.size(), 1u);
  expect_error<InputError>([&] { read_tet_mesh(dir / "u.off"); }, "unknown extension");
  TetReadOptions small;
  small.max_bytes = 10;
  expect_error<InputError>([&] { read_tet_mesh(dir / "u.node", small); }, "limit");
  test::write_file(dir / "e.vtk", " \n\n");
  expect_error<InputError>([&] { read_tet_mesh(dir / "e.vtk"); }, "empty");
  TetReadOptions missing;
  missing.material_file = dir / "none.sol";
  test::write_file(dir / "u.mesh", kUnitTetMedit);
  expect_error<IoError>([&] { read_tet_mesh(dir / "u.mesh", missing); }, "none.sol");
  expect_error<InputError>([] { parse_tet_mesh(TetFormat::Auto, kUnitTetMedit, "x"); }, "format");
  expect_error<InputError>([] { medit("MeshVersionFormatted 2\nDimension 3\nEnd\n"); },
                           "no tetrahedra");
}

TEST(TetIo, WriterRefusesWhatReadersWouldRefuse) {
  const auto dir = test::scratch_dir();
  TetMesh mesh = two_tets(true);
  expect_error<InputError>([&] { write_tet_mesh(dir / "m.ply", mesh); }, "unknown extension");
  mesh.tets[1][2] = 5;
  expect_error<InputError>([&] { write_tet_mesh(dir / "m.mesh", mesh); }, "tetrahedron 1");
  mesh = two_tets(true);
  mesh.material.pop_back();
  expect_error<InputError>([&] { write_tet_mesh(dir / "m.vtk", mesh); }, "4 material values");
  mesh = two_tets(true);
  mesh.material[2] = std::numeric_limits<double>::quiet_NaN();
  expect_error<InputError>([&] { write_tet_mesh(dir / "m.vtk", mesh); }, "point 2");
  EXPECT_TRUE(test::files_in(dir, 1 << 20).empty());
}

// ---- malformed -----------------------------------------------------------------------------

TEST(TetIoMalformed, Medit) {
  expect_parse_error([] { medit("MeshVersionFormatted 2\nDimension 3\nBogus 3\n"); }, "a.mesh", 3);
  expect_parse_error([] { medit("MeshVersionFormatted 2\n\nDimension 2\n"); }, "a.mesh", 3);
  expect_parse_error([] { medit("Vertices\n2\n0 0 0 0\n0 0 inf 0\n"); }, "a.mesh", 4);
  expect_parse_error([] { medit("Vertices\n2\n0 0 0 0\n0 0 nan 0\n"); }, "a.mesh", 4);
  expect_parse_error([] { medit("Vertices\n99999999999\n0 0 0 0\n"); }, "a.mesh", 2);
  // The end of the file is reported on the line after the last line break.
  expect_parse_error([] { medit("Vertices\n2\n0 0 0 0\n0 0 0\n"); }, "a.mesh", 5);
  std::string zero = kUnitTetMedit;
  zero.replace(zero.find("1 2 3 4 0"), 9, "0 2 3 4 0");
  expect_parse_error([&] { medit(zero); }, "a.mesh", 11);
  std::string five = kUnitTetMedit;
  five.replace(five.find("1 2 3 4 0"), 9, "1 2 3 5 0");
  expect_parse_error([&] { medit(five); }, "a.mesh", 11);
  expect_parse_error(
      [] { medit(kUnitTetMedit.substr(0, kUnitTetMedit.size() - 4) + "Vertices 0\n"); }, "a.mesh",
      12);
  expect_parse_error([] { medit(std::string("\x01\0\0\0\x02\0\0\0", 8)); }, "a.mesh", {}, 0);
  expect_parse_error([] { medit(std::string("\0\0\0\x01\0\0\0\x02", 8)); }, "a.mesh", {}, 0);
  expect_parse_error([] { medit("Edges 3\n1 2 0\n"); }, "a.mesh", 1);
}

TEST(TetIoMalformed, MeditSol) {
  const std::string head = "MeshVersionFormatted 2\nDimension 3\nSolAtVertices\n";
  expect_parse_error([&] { medit(kUnitTetMedit, head + "3\n1 1\n0\n1\n2\n"); }, "a.sol", 4);
  expect_parse_error([&] { medit(kUnitTetMedit, head + "4\n1 1\n0\n1\nnan\n2\n"); }, "a.sol", 8);
  expect_parse_error([&] { medit(kUnitTetMedit, head + "4\n1 7\n0\n1\n1\n2\n"); }, "a.sol", 5);
  expect_parse_error([&] { medit(kUnitTetMedit, head + "4\n1 1\n0\n1\n"); }, "a.sol", 4);
  expect_parse_error([&] { medit(kUnitTetMedit, "MeshVersionFormatted 2\nDimension 3\nEnd\n"); },
                     "a.sol", 3);
  std::string vectors = head + "4\n1 2\n";
  for (int i = 0; i < 4; ++i) vectors += "0 0 0\n";
  expect_parse_error([&] { medit(kUnitTetMedit, vectors); }, "a.sol", 4);
  // SolAtTetrahedra is skipped by its count.
  EXPECT_EQ(
      medit(kUnitTetMedit, "SolAtTetrahedra 1 1 1 9\nSolAtVertices 4 1 1 1 2 3 4\nEnd\n").material,
      (std::vector<double>{1, 2, 3, 4}));
  expect_parse_error([&] { medit(kUnitTetMedit, std::string("\x01\0\0\0", 4)); }, "a.sol", {}, 0);
}

TEST(TetIoMalformed, TetGen) {
  const std::string ele = "1 4 0\n0 0 1 2 3\n";
  expect_parse_error([&] { tetgen("4 2 0 0\n", ele); }, "a.node", 1);
  expect_parse_error([&] { tetgen("# c\n4 3 0 0\n2 0 0 0\n3 1 0 0\n4 0 1 0\n5 0 0 1\n", ele); },
                     "a.node", 3);
  expect_parse_error([&] { tetgen("4 3 0 0\n0 0 0 0\n1 1 0 0\n3 0 1 0\n2 0 0 1\n", ele); },
                     "a.node", 4);
  // Rows the bytes left cannot hold are refused at the header, a short row at its line.
  expect_parse_error([&] { tetgen("4 3 0 0\n0 0 0 0\n1 1 0 0\n2 0 1 0\n3 0 0\n", ele); }, "a.node",
                     1);
  expect_parse_error([&] { tetgen("4 3 0 0\n0 0 0 0\n1 1 0 0\n2 0 1 0\n3 0 0  \n", ele); },
                     "a.node", 5);
  expect_parse_error(
      [&] { tetgen("4 3 1 0\n0 0 0 0 1\n1 1 0 0 nan\n2 0 1 0 1\n3 0 0 1 1\n", ele); }, "a.node", 3);
  expect_parse_error([&] { tetgen("4000000000 3 0 0\n0 0 0 0\n", ele); }, "a.node", 1);
  expect_parse_error([&] { tetgen("4 3 999999999 0\n0 0 0 0\n", ele); }, "a.node", 1);
  expect_parse_error([&] { tetgen(kUnitTetNode, "1 8 0\n0 0 1 2 3 0 1 2 3\n"); }, "a.ele", 1);
  expect_parse_error([&] { tetgen(kUnitTetNode, "# c\n\n1 4 0\n0 0 1 2 4\n"); }, "a.ele", 4);
  expect_parse_error([&] { tetgen(kUnitTetNode, "1 4 0\n0 -1 1 2 3\n"); }, "a.ele", 2);
  expect_parse_error([&] { tetgen(kUnitTetNode, "2 4 0\n0 0 1 2 3\n"); }, "a.ele", 1);
  expect_parse_error([&] { tetgen(kUnitTetNode, "1 4 0\n0 0 1 2\n"); }, "a.ele", 1);
  expect_parse_error([&] { tetgen(kUnitTetNode, "1 4 0\n0 0 1 2    \n"); }, "a.ele", 2);
  // 1-based nodes: corner 0 is out of range.
  expect_parse_error(
      [&] { tetgen("4 3 0 0\n1 0 0 0\n2 1 0 0\n3 0 1 0\n4 0 0 1\n", "1 4 0\n1 0 1 2 3\n"); },
      "a.ele", 2);
  expect_error<InputError>([&] { tetgen(kUnitTetNode, "\n"); }, "a.ele is empty");
}

TEST(TetIoMalformed, VtkAscii) {
  expect_parse_error([] { vtk("# vtk DataFile\nx\nASCII\n"); }, "a.vtk", 1);
  expect_parse_error([] { vtk("# vtk DataFile Version 2.0\nx\nXML\n"); }, "a.vtk", 3);
  expect_parse_error([] { vtk("# vtk DataFile Version 2.0\nx\nASCII\nDATASET POLYDATA\n"); },
                     "a.vtk", 4);
  expect_parse_error([] { vtk(kVtkHead + "POINTS 99999999 float\n0 0 0\n"); }, "a.vtk", 5);
  expect_parse_error([] { vtk(kVtkHead + "POINTS 2 float\n0 0 0\n0 nan 0\n"); }, "a.vtk", 7);
  expect_parse_error([] { vtk(kVtkHead + "POINTS 2 quaternion\n"); }, "a.vtk", 5);
  expect_parse_error([] { vtk(kVtkUnitTet + "POLYGONS 1 4\n"); }, "a.vtk", 12);
  expect_parse_error([] { vtk(kVtkUnitTet + "POINT_DATA 3\n"); }, "a.vtk", 12);
  expect_parse_error(
      [] {
        vtk(kVtkUnitTet + "POINT_DATA 4\nSCALARS m float\nLOOKUP_TABLE default\n0 1\ninf 3\n");
      },
      "a.vtk", 16);
  expect_parse_error([] { vtk(kVtkUnitTet + "SCALARS m float\n"); }, "a.vtk", 12);
  std::string three = kVtkUnitTet;
  three.replace(three.find("CELLS 1 5\n4 0 1 2 3"), 19, "CELLS 1 4\n3 0 1 2");
  expect_parse_error([&] { vtk(three); }, "a.vtk", 8);
  std::string far = kVtkUnitTet;
  far.replace(far.find("4 0 1 2 3"), 9, "4 0 1 2 4");
  expect_parse_error([&] { vtk(far); }, "a.vtk", 8);
  std::string types = kVtkUnitTet;
  types.replace(types.find("CELL_TYPES 1"), 12, "CELL_TYPES 2");
  expect_parse_error([&] { vtk(types); }, "a.vtk", 10);
  std::string counts = kVtkUnitTet;
  counts.replace(counts.find("CELLS 1 5\n4"), 11, "CELLS 1 5\n7");
  expect_parse_error([&] { vtk(counts); }, "a.vtk", 9);
  expect_parse_error(
      [] { vtk(kVtkHead + "POINTS 4 float\n0 0 0 1 0 0\n0 1 0 0 0 1\nCELLS 1 5\n4 0 1 2 3\n"); },
      "a.vtk", 8);
  expect_error<InputError>(
      [] {
        vtk(kVtkHead +
            "POINTS 3 float\n0 0 0 1 0 0 0 1 0\nCELLS 3 8\n3 0 1 2\n1 0\n1 1\n"
            "CELL_TYPES 3\n5\n1\n1\n");
      },
      "2 of type 1 (vertex), 1 of type 5 (triangle)");
}

TEST(TetIoMalformed, VtkBinaryOffsets) {
  const std::string head = "# vtk DataFile Version 3.0\nbin\nBINARY\nDATASET UNSTRUCTURED_GRID\n";
  // 4 points of float declared, 3 given: refused at the first data byte.
  std::string truncated = head + "POINTS 4 float\n";
  const std::uint64_t data_at = truncated.size();
  for (int i = 0; i < 9; ++i) truncated += be_float(0);
  expect_parse_error([&] { vtk(truncated); }, "a.vtk", {}, data_at);
  // A NaN coordinate: refused at its own byte.
  std::string nan = head + "POINTS 4 float\n";
  const std::uint64_t at = nan.size() + 5 * 4;
  for (int i = 0; i < 12; ++i)
    nan += be_float(i == 5 ? std::numeric_limits<float>::quiet_NaN() : 0.0f);
  expect_parse_error([&] { vtk(nan + "\n"); }, "a.vtk", {}, at);
  // A cell with a negative point count, in binary.
  std::string cells =
      head + "POINTS 1 float\n" + be_float(0) + be_float(0) + be_float(0) + "\nCELLS 1 2\n";
  const std::uint64_t cells_at = cells.size();
  cells += be32(static_cast<std::uint32_t>(-1)) + be32(0) + "\n";
  expect_parse_error([&] { vtk(cells); }, "a.vtk", {}, cells_at);
  // Offsets that decrease (5.1).
  std::string offsets =
      "# vtk DataFile Version 5.1\nbin\nBINARY\nDATASET UNSTRUCTURED_GRID\n"
      "POINTS 1 float\n" +
      be_float(0) + be_float(0) + be_float(0) + "\nCELLS 3 4\nOFFSETS vtktypeint64\n";
  const std::uint64_t offsets_at = offsets.size() + 8;
  offsets += be64(0) + be64(5) + be64(4);
  expect_parse_error([&] { vtk(offsets); }, "a.vtk", {}, offsets_at);
  // Lines keep counting after binary data (its line breaks included).
  std::string after =
      head + "POINTS 1 float\n" + be_float(0) + be_float(0) + be_float(0) + "\nBOGUS\n";
  expect_parse_error([&] { vtk(after); }, "a.vtk", 7);
}
