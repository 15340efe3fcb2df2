// Every class of malformed input: the right exception type, and a message with the location.
#include <gtest/gtest.h>
#include <sys/stat.h>

#include <chrono>
#include <cstring>
#include <tpmsfill/error.hpp>
#include <tpmsfill/io.hpp>

#include "test_util.hpp"

using namespace tpmsfill;

namespace {

// Parses and expects a ParseError whose message names `location` (e.g. ":3:" or "byte 84").
void expect_parse_error(const std::string& bytes, const std::string& name,
                        const std::string& location, const ReadOptions& options = {}) {
  try {
    parse_mesh(bytes, name, options);
    ADD_FAILURE() << name << ": no exception";
  } catch (const ParseError& e) {
    EXPECT_NE(std::string(e.what()).find(location), std::string::npos)
        << "expected '" << location << "' in: " << e.what();
    EXPECT_EQ(std::string(e.what()).find('\n'), std::string::npos);
  } catch (const std::exception& e) {
    ADD_FAILURE() << name << ": wrong exception: " << e.what();
  }
}

void expect_input_error(const std::string& bytes, const std::string& name,
                        const std::string& words) {
  try {
    parse_mesh(bytes, name);
    ADD_FAILURE() << name << ": no exception";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find(words), std::string::npos) << e.what();
  } catch (const std::exception& e) {
    ADD_FAILURE() << name << ": wrong exception: " << e.what();
  }
}

const std::string kTriangleObj = "v 0 0 0\nv 1 0 0\nv 0 1 0\n";

std::string binary_stl_header(std::uint32_t count) {
  std::string out(80, ' ');
  out.append(reinterpret_cast<const char*>(&count), 4);
  return out;
}

}  // namespace

TEST(IoMalformed, ObjIndexOutOfRangeZeroAndNegative) {
  expect_parse_error(kTriangleObj + "f 1 2 4\n", "a.obj", "a.obj:4:");
  expect_parse_error(kTriangleObj + "f 0 1 2\n", "a.obj", "a.obj:4:");
  expect_parse_error(kTriangleObj + "\nf -1 -2 -4\n", "a.obj", "a.obj:5:");
  expect_parse_error(kTriangleObj + "f 1/1/1 2//3 x/1\n", "a.obj", "a.obj:4:");
}

TEST(IoMalformed, FacesWithFewerThanThreeVertices) {
  expect_parse_error(kTriangleObj + "f 1 2\n", "a.obj", "a.obj:4:");
  expect_parse_error("OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n2 0 1\n", "a.off", "a.off:6:");
  expect_parse_error(
      "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
      "property float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n"
      "0 0 0\n1 0 0\n0 1 0\n2 0 1\n",
      "a.ply", "a.ply:13:");
  expect_parse_error(
      "solid s\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\n"
      "endloop\nendfacet\nendsolid s\n",
      "a.stl", "a.stl:7:");
}

TEST(IoMalformed, PlyIndexOutOfRangeAsciiAndBinary) {
  const std::string header =
      "element vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
      "element face 1\nproperty list uchar int vertex_indices\nend_header\n";
  expect_parse_error("ply\nformat ascii 1.0\n" + header + "0 0 0\n1 0 0\n0 1 0\n3 0 1 3\n", "a.ply",
                     "a.ply:13:");
  expect_parse_error("ply\nformat ascii 1.0\n" + header + "0 0 0\n1 0 0\n0 1 0\n3 0 -1 2\n",
                     "a.ply", "a.ply:13:");
  std::string binary = "ply\nformat binary_little_endian 1.0\n" + header;
  const std::size_t data = binary.size();
  const float xyz[9] = {0, 0, 0, 1, 0, 0, 0, 1, 0};
  binary.append(reinterpret_cast<const char*>(xyz), sizeof xyz);
  binary += '\3';
  const std::int32_t indices[3] = {0, 1, 7};
  binary.append(reinterpret_cast<const char*>(indices), sizeof indices);
  expect_parse_error(binary, "b.ply", "byte " + std::to_string(data + 36 + 1 + 8));
}

TEST(IoMalformed, EmptyWhitespaceAndCommentOnlyFiles) {
  for (const std::string& bytes :
       {std::string(), std::string("  \n\t\r\n"), std::string("# only\n  # comments\n")}) {
    for (const char* name : {"e.stl", "e.obj", "e.ply", "e.off", "e"})
      expect_input_error(bytes, name, "is empty");
  }
  const auto file = test::scratch_dir() / "zero.stl";
  test::write_file(file, "");
  EXPECT_THROW(read_mesh(file), InputError);
  EXPECT_THROW(read_mesh(test::scratch_dir() / "missing.stl"), IoError);
}

TEST(IoMalformed, TextThatIsNoMesh) {
  expect_parse_error("Dear reader,\nthis is a letter.\n", "letter.txt", "letter.txt:1:");
  // Named .obj it is read as OBJ, which has no triangles: a different, InputError, message.
  expect_input_error("Dear reader,\nthis is a letter.\n", "letter.obj", "no triangles");
}

TEST(IoMalformed, NoTrianglesIsDistinctFromEmpty) {
  expect_input_error(kTriangleObj + "l 1 2\np 3\n", "cloud.obj", "contains no triangles");
  expect_input_error(
      "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\n"
      "property float z\nend_header\n0 0 0\n",
      "cloud.ply", "contains no triangles");
  expect_input_error("OFF\n1 0 0\n0 0 0\n", "cloud.off", "contains no triangles");
  expect_input_error("solid empty\nendsolid empty\n", "e.stl", "contains no triangles");
  expect_input_error(binary_stl_header(0), "zero.stl", "contains no triangles");
}

TEST(IoMalformed, BinaryStlCountTooHighIsTruncated) {
  std::string bytes = binary_stl_header(3) + std::string(100, '\0');
  expect_parse_error(bytes, "t.stl", "byte 184");
  // A header claiming 4 billion triangles fails at once, without allocating for them.
  expect_parse_error(binary_stl_header(0xFFFFFFFFu) + std::string(50, '\0'), "huge.stl",
                     "truncated");
  // An excess that is neither < 50 bytes nor whole triangles is refused.
  expect_parse_error(binary_stl_header(1) + std::string(50 + 70, '\0'), "odd.stl", "byte 134");
}

TEST(IoMalformed, NonFiniteCoordinatesInEveryFormat) {
  for (const char* bad : {"nan", "inf", "-Infinity", "+NaN"}) {
    const std::string b(bad);
    expect_parse_error("v 0 0 0\nv 1 " + b + " 0\nv 0 1 0\nf 1 2 3\n", "n.obj", "n.obj:2:");
    expect_parse_error("OFF\n3 1 0\n0 0 0\n1 0 " + b + "\n0 1 0\n3 0 1 2\n", "n.off", "n.off:4:");
    expect_parse_error("solid s\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex " + b +
                           " 0 0\nvertex 0 1 0\nendloop\nendfacet\nendsolid s\n",
                       "n.stl", "n.stl:5:");
    expect_parse_error(
        "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
        "property float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n"
        "0 0 0\n" +
            b + " 0 0\n0 1 0\n3 0 1 2\n",
        "n.ply", "n.ply:11:");
  }
  // Binary: a float NaN in a binary STL and a double infinity in a binary PLY.
  std::string stl = binary_stl_header(1);
  const float tri[12] = {0, 0, 1, 0, 0, 0, 1, std::numeric_limits<float>::quiet_NaN(), 0, 0, 1, 0};
  stl.append(reinterpret_cast<const char*>(tri), sizeof tri);
  stl.append(2, '\0');
  expect_parse_error(stl, "n.stl", "byte 108");
  std::string ply =
      "ply\nformat binary_little_endian 1.0\nelement vertex 3\nproperty double x\n"
      "property double y\nproperty double z\nelement face 1\n"
      "property list uchar int vertex_indices\nend_header\n";
  const std::size_t at = ply.size() + 8 * 5;
  const double xyz[9] = {0, 0, 0, 1, 0, std::numeric_limits<double>::infinity(), 0, 1, 0};
  ply.append(reinterpret_cast<const char*>(xyz), sizeof xyz);
  ply += '\3';
  const std::int32_t idx[3] = {0, 1, 2};
  ply.append(reinterpret_cast<const char*>(idx), sizeof idx);
  expect_parse_error(ply, "n.ply", "byte " + std::to_string(at));
}

TEST(IoMalformed, MalformedNumbersNameTokenAndLine) {
  expect_parse_error("v 0 0 0\nv 1 0 3.1+e2\nv 0 1 0\nf 1 2 3\n", "m.obj", "'3.1+e2'");
  expect_parse_error("v 0 0 0\nv 1 0 3.1+e2\nv 0 1 0\nf 1 2 3\n", "m.obj", "m.obj:2:");
  expect_parse_error("v 0 0 0\nv 1 0 1e999\nv 0 1 0\nf 1 2 3\n", "m.obj", "m.obj:2:");
  expect_parse_error("v 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n", "m.obj", "m.obj:1:");
  expect_parse_error("OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2x\n", "m.off", "m.off:6:");
  // A leading '+' is fine (from_chars alone would refuse it).
  EXPECT_EQ(parse_mesh("v +1e2 0 0\nv 1 0 0\nv 0 1 0\nf +1 2 3\n", "p.obj").soup.points[0].x,
            100.0);
}

TEST(IoMalformed, HugeDeclaredCountsFailFast) {
  expect_parse_error(
      "ply\nformat binary_little_endian 1.0\nelement vertex 1000000000000\n"
      "property float x\nproperty float y\nproperty float z\nend_header\n" +
          std::string(64, '\0'),
      "h.ply", "h.ply:3:");
  expect_parse_error(
      "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\n"
      "property float y\nproperty float z\nelement face 999999999999\n"
      "property list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n",
      "h.ply", "h.ply:7:");
  expect_parse_error("OFF 1000000000000 1 0\n0 0 0\n", "h.off", "h.off:1:");
  // A glued count is still checked, and anything but digits glued on is no keyword.
  expect_parse_error("OFF1000000000000 1 0\n0 0 0\n", "g.off", "g.off:1:");
  expect_parse_error("OFF8 1\n0 0 0\n", "g.off", "g.off:1:");
  expect_parse_error("OFFx 1 0\n", "g.off", "g.off:1:");
  expect_parse_error("OFF\n3 1000000000000\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n", "h.off", "h.off:2:");
  // A binary list claiming more items than bytes remain.
  std::string ply =
      "ply\nformat binary_little_endian 1.0\nelement vertex 3\nproperty uchar x\n"
      "property uchar y\nproperty uchar z\nelement face 1\n"
      "property list uint int vertex_indices\nend_header\n";
  ply += std::string(9, '\0');
  ply += std::string("\xff\xff\xff\x7f", 4) + std::string(12, '\0');
  expect_parse_error(ply, "l.ply", "byte");
}

TEST(IoMalformed, OffVariantsNotSupported) {
  expect_parse_error("4OFF\n1 0 0\n0 0 0 0\n", "a.off", "not supported");
  expect_parse_error("nOFF 4\n1 0 0\n0 0 0 0\n", "a.off", "a.off:1:");
  expect_parse_error("OFF BINARY\n", "a.off", "not supported");
  // Too few faces: refused at the counts line when the bytes cannot hold them, else at the end.
  expect_parse_error("OFF\n3 2 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n", "a.off", "a.off:2:");
  expect_parse_error("OFF\n3 2 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n\n\n\n\n\n\n\n\n\n\n", "a.off",
                     "1 of 2 faces");
}

TEST(IoMalformed, Utf16WithNonAsciiIsRefused) {
  std::string utf16 = "\xFF\xFE";
  for (const char c : std::string("v 0 0 0\n# x\n")) utf16 += std::string{c, '\0'};
  utf16 += std::string("\xE9\x00", 2);  // U+00E9 on line 3
  expect_parse_error(utf16, "u.obj", "u.obj:3:");
  expect_parse_error(std::string("\xFE\xFF\x00", 3), "odd.obj", "byte");
}

TEST(IoMalformed, ForcedFormatOnOtherContent) {
  const std::string obj = kTriangleObj + "f 1 2 3\n";
  expect_parse_error(obj, "x", "x:1:", {.format = MeshFormat::Ply});
  expect_parse_error(obj, "x", "x:1:", {.format = MeshFormat::Off});
  expect_parse_error(obj, "x", "byte", {.format = MeshFormat::StlBinary});
  EXPECT_EQ(parse_mesh(obj, "x", {.format = MeshFormat::Obj}).soup.triangles.size(), 1u);
}

TEST(IoMalformed, SizeLimit) {
  EXPECT_THROW(parse_mesh(kTriangleObj + "f 1 2 3\n", "big.obj", {.max_bytes = 10}), InputError);
  const auto file = test::scratch_dir() / "big.obj";
  test::write_file(file, kTriangleObj + "f 1 2 3\n");
  EXPECT_THROW(read_mesh(file, {.max_bytes = 10}), InputError);
}

// A file of another kind under a mesh's name is named for what it is, not read as a broken
// STL ("header declares 4124962155 triangles" was what a PNG named .stl got).
TEST(IoMalformed, OtherKindsOfFileAreNamed) {
  std::string png("\x89PNG\r\n\x1a\n\0\0\0\rIHDR", 16);
  png.resize(300, '\x01');
  expect_parse_error(png, "picture.stl", "this is a PNG image, not a mesh");
  expect_parse_error(png, "picture.stl", "byte 0");
  std::string jpeg("\xFF\xD8\xFF\xE0", 4);
  jpeg.resize(200, '\x02');
  expect_parse_error(jpeg, "photo.obj", "a JPEG image");
  expect_parse_error("%PDF-1.7\n%\xE2\xE3\xCF\xD3\n", "drawing.ply", "a PDF document");
  // A binary STL whose 80-byte header happens to start with the PNG signature is still an STL.
  std::string stl = png.substr(0, 8);
  stl.resize(80, ' ');
  const std::uint32_t one = 1;
  stl.append(reinterpret_cast<const char*>(&one), 4);
  const float facet[12] = {0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1, 0};
  stl.append(reinterpret_cast<const char*>(facet), sizeof facet);
  stl.append(2, '\0');
  EXPECT_EQ(parse_mesh(stl, "odd-header.stl").soup.triangles.size(), 1u);
}

// Issue 37: a gzipped STL of zeros declares 0 triangles in its first 84 bytes: inflating stops
// there (1 GiB of zeros peaked at 2.1 GB before the reader said a word). A text STL declares
// nothing and is read as before.
TEST(IoMalformed, GzippedStlStopsAtTheSizeItsHeaderDeclares) {
  const auto gz = [](const std::string& in) { return test::gzip(in, 1); };
  const std::string packed = gz(std::string(std::size_t{64} << 20, '\0'));
  ASSERT_LT(packed.size(), 1u << 20);
  const auto start = std::chrono::steady_clock::now();
  expect_input_error(packed, "bomb.stl.gz", "more than 84 bytes, the size its header declares");
  EXPECT_LT(std::chrono::steady_clock::now() - start, std::chrono::seconds(2));
  // A binary STL of one triangle followed by junk is refused the same way; the triangle alone
  // reads.
  std::string stl = binary_stl_header(1);
  const float facet[12] = {0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1, 0};
  stl.append(reinterpret_cast<const char*>(facet), sizeof facet);
  stl.append(2, '\0');
  EXPECT_EQ(parse_mesh(gz(stl), "one.stl.gz").soup.triangles.size(), 1u);
  expect_input_error(gz(stl + std::string(1000, 'x')), "one.stl.gz", "more than 134 bytes");
  const std::string text =
      "solid t\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\n"
      "vertex 0 1 0\nendloop\nendfacet\nendsolid t\n";
  EXPECT_EQ(parse_mesh(gz(text), "t.stl.gz").soup.triangles.size(), 1u);
}

// Issue 37: `mkfifo p.stl; tpmsfill check p.stl` waited forever for a writer.
TEST(IoMalformed, FifosAndOtherNonRegularFilesAreRefused) {
  const auto dir = test::scratch_dir();
  ASSERT_EQ(mkfifo((dir / "p.stl").c_str(), 0600), 0);
  try {
    read_mesh(dir / "p.stl");
    ADD_FAILURE() << "read";
  } catch (const IoError& e) {
    EXPECT_NE(std::string(e.what()).find("it is a FIFO, and only regular files are read"),
              std::string::npos)
        << e.what();
  }
  EXPECT_THROW(read_mesh("/dev/zero"), IoError);
}
