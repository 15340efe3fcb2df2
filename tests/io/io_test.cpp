// Readers and writers on meshes made in code and on real files from Debian packages.
#include <gtest/gtest.h>
#include <unistd.h>
#include <zlib.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <span>
#include <string>
#include <tpmsfill/error.hpp>
#include <tpmsfill/io.hpp>
#include <tuple>
#include <vector>

#include "io/inflate.hpp"
#include "test_util.hpp"

using namespace tpmsfill;
namespace fs = std::filesystem;

namespace {

std::vector<TriangleSoup> test_meshes() {
  return {test::make_box({-1.5, 0.25, 2}, {3.1, 4.7, 9.3}), test::make_sphere({1, 2, 3}, 2.7, 2),
          test::make_torus(5, 1.3, 24, 12)};
}

Vec3 to_float(Vec3 p) {
  return {static_cast<float>(p.x), static_cast<float>(p.y), static_cast<float>(p.z)};
}

// The positions of every triangle's corners, in order: equal for two soups that describe the
// same triangles whether or not they share points.
std::vector<Vec3> corner_positions(const TriangleSoup& soup, bool as_float = false) {
  std::vector<Vec3> out;
  for (const Triangle& t : soup.triangles)
    for (std::uint32_t v : t) out.push_back(as_float ? to_float(soup.points[v]) : soup.points[v]);
  return out;
}

std::string binary_stl(const std::vector<std::array<float, 9>>& triangles, std::uint32_t count,
                       const std::string& header = std::string(80, ' ')) {
  std::string out = header;
  out.resize(80, ' ');
  out.append(reinterpret_cast<const char*>(&count), 4);
  for (const auto& t : triangles) {
    out.append(12, '\0');
    out.append(reinterpret_cast<const char*>(t.data()), 36);
    out.append(2, '\0');
  }
  return out;
}

const std::vector<std::array<float, 9>> kTwoTriangles = {{0, 0, 0, 1, 0, 0, 0, 1, 0},
                                                         {0, 0, 1, 1, 0, 1, 0, 1, 1}};

MeshFile parse(const std::string& bytes, const std::string& name) {
  return parse_mesh(bytes, name);
}

}  // namespace

// ---- writers round trip -----------------------------------------------------------------

TEST(IoRoundTrip, ObjPlyOffAreExact) {
  const fs::path dir = test::scratch_dir();
  for (const char* ext : {".obj", ".ply", ".off", ".OBJ"}) {
    for (const TriangleSoup& mesh : test_meshes()) {
      const fs::path file = dir / (std::string("mesh") + ext);
      write_mesh(file, mesh);
      const MeshFile back = read_mesh_file(file);
      EXPECT_EQ(back.soup.points, mesh.points) << ext;
      EXPECT_EQ(back.soup.triangles, mesh.triangles) << ext;
      EXPECT_EQ(back.faces_in_file, mesh.triangles.size());
      EXPECT_TRUE(back.warnings.empty());
    }
  }
}

TEST(IoRoundTrip, StlBinaryAndAsciiKeepFloatCoordinates) {
  const fs::path dir = test::scratch_dir();
  for (const MeshFormat format : {MeshFormat::StlBinary, MeshFormat::StlAscii}) {
    for (const TriangleSoup& mesh : test_meshes()) {
      const fs::path file = dir / "mesh.stl";
      write_mesh(file, mesh, {.format = format});
      const MeshFile back = read_mesh_file(file);
      EXPECT_EQ(back.format, format);
      // STL stores three points per facet: compare as unshared soups, coordinates as floats.
      const TriangleSoup expected = test::unshare_points(mesh);
      EXPECT_EQ(back.soup.triangles, expected.triangles);
      // ASCII reads the printed float as a double: equal once both are rounded to float.
      EXPECT_EQ(corner_positions(back.soup, true), corner_positions(expected, true));
      EXPECT_NEAR(test::signed_volume(back.soup), test::signed_volume(mesh),
                  1e-5 * std::fabs(test::signed_volume(mesh)));
    }
  }
}

TEST(IoRoundTrip, ShortestTextFormReadsBackBitIdentical) {
  TriangleSoup soup{{{0.1, 1.0 / 3.0, -2e-300}, {1e300, 5e-324, 123456789.123456789}, {-0.0, 1, 2}},
                    {{0, 1, 2}}};
  const fs::path dir = test::scratch_dir();
  for (const char* name : {"a.obj", "a.off", "a.ply"}) {
    write_mesh(dir / name, soup);
    const TriangleSoup back = read_mesh(dir / name);
    ASSERT_EQ(back.points.size(), 3u);
    for (int i = 0; i < 3; ++i)
      for (int axis = 0; axis < 3; ++axis)
        EXPECT_EQ(std::signbit(back.points[i][axis]), std::signbit(soup.points[i][axis]));
    EXPECT_EQ(back.points, soup.points) << name;
  }
}

TEST(IoWrite, BinaryStlHeaderDoesNotStartWithSolidAndHasNormals) {
  const fs::path file = test::scratch_dir() / "box.STL";
  write_mesh(file, test::make_box({0, 0, 0}, {1, 2, 3}));
  const std::string bytes = test::read_file(file);
  ASSERT_EQ(bytes.size(), 84u + 50u * 12u);
  EXPECT_NE(bytes.substr(0, 5), "solid");
  // First facet's normal is a unit vector perpendicular to its edges.
  float n[3];
  std::memcpy(n, bytes.data() + 84, 12);
  EXPECT_FLOAT_EQ(n[0] * n[0] + n[1] * n[1] + n[2] * n[2], 1.0f);
}

TEST(IoWrite, UnknownExtensionIsInputError) {
  const fs::path dir = test::scratch_dir();
  EXPECT_THROW(write_mesh(dir / "mesh.xyz", test::make_box({0, 0, 0}, {1, 1, 1})), InputError);
  EXPECT_THROW(write_mesh(dir / "mesh", test::make_box({0, 0, 0}, {1, 1, 1})), InputError);
  EXPECT_TRUE(fs::is_empty(dir));
}

TEST(IoWrite, IndexOutOfRangeIsInputErrorAndWritesNothing) {
  const fs::path dir = test::scratch_dir();
  TriangleSoup bad = test::make_box({0, 0, 0}, {1, 1, 1});
  bad.triangles[3][1] = 8;
  EXPECT_THROW(write_mesh(dir / "bad.obj", bad), InputError);
  EXPECT_TRUE(fs::is_empty(dir));
}

TEST(IoWrite, MissingFolderIsIoErrorNamingThePath) {
  const fs::path file = test::scratch_dir() / "no" / "such" / "mesh.stl";
  try {
    write_mesh(file, test::make_box({0, 0, 0}, {1, 1, 1}));
    FAIL() << "no exception";
  } catch (const IoError& e) {
    EXPECT_NE(std::string(e.what()).find(file.string()), std::string::npos) << e.what();
  }
}

TEST(IoWrite, ReplacesTargetAtomicallyAndLeavesNoTemporary) {
  const fs::path dir = test::scratch_dir();
  const fs::path file = dir / "m.off";
  test::write_file(file, "old content");
  write_mesh(file, test::make_box({0, 0, 0}, {1, 1, 1}));
  EXPECT_EQ(read_mesh(file).triangles.size(), 12u);
  EXPECT_EQ(std::distance(fs::directory_iterator(dir), fs::directory_iterator()), 1);
}

TEST(IoWrite, FailedRenameRemovesTemporary) {
  // The target is a folder: the rename fails after the data was written.
  const fs::path dir = test::scratch_dir();
  fs::create_directory(dir / "taken.obj");
  EXPECT_THROW(write_mesh(dir / "taken.obj", test::make_box({0, 0, 0}, {1, 1, 1})), IoError);
  EXPECT_EQ(std::distance(fs::directory_iterator(dir), fs::directory_iterator()), 1);
  EXPECT_TRUE(fs::is_directory(dir / "taken.obj"));
}

TEST(IoWrite, FailedWriteLeavesOldFileAndNoTemporary) {
  if (::geteuid() == 0) GTEST_SKIP() << "root ignores folder permissions";
  const fs::path dir = test::scratch_dir();
  const fs::path file = dir / "m.off";
  test::write_file(file, "old content");
  fs::permissions(dir, fs::perms::owner_read | fs::perms::owner_exec);
  EXPECT_THROW(write_mesh(file, test::make_box({0, 0, 0}, {1, 1, 1})), IoError);
  fs::permissions(dir, fs::perms::owner_all);
  EXPECT_EQ(test::read_file(file), "old content");
  EXPECT_EQ(std::distance(fs::directory_iterator(dir), fs::directory_iterator()), 1);
}

// ---- MeshWriter: piece by piece ----------------------------------------------------------

namespace {

// Every name in `dir`, sorted: temporaries included (they start with a dot).
std::vector<std::string> listing(const fs::path& dir) {
  std::vector<std::string> names;
  for (const auto& entry : fs::directory_iterator(dir))
    names.push_back(entry.path().filename().string());
  std::sort(names.begin(), names.end());
  return names;
}

// Points [begin, end), or triangles [begin, end), as one call.
struct Piece {
  bool points;
  std::size_t begin, end;
};

// Points in 3 pieces and triangles in 4, in the given order of the 7 (P0..P2, T0..T3).
std::vector<Piece> pieces(const TriangleSoup& mesh, const std::string& order) {
  const std::size_t np = mesh.points.size(), nt = mesh.triangles.size();
  const std::size_t p[] = {0, np / 3, 2 * np / 3, np};
  const std::size_t t[] = {0, nt / 5, nt / 2, 3 * nt / 4, nt};
  std::vector<Piece> out;
  for (std::size_t i = 0; i + 1 < order.size(); i += 2) {
    const int k = order[i + 1] - '0';
    out.push_back(order[i] == 'P' ? Piece{true, p[k], p[k + 1]} : Piece{false, t[k], t[k + 1]});
  }
  return out;
}

// The orders tried: triangles before, among and after their points.
const char* const kOrders[] = {"T0P0T1P1T2P2T3", "P0P1P2T0T1T2T3", "T0T1T2T3P0P1P2",
                               "P0T0T1P1P2T2T3"};

// Triangles [begin, end), with a window of just the ids they use.
void add_triangle_piece(MeshWriter& writer, const TriangleSoup& mesh, std::size_t begin,
                        std::size_t end) {
  const std::span<const Triangle> triangles(mesh.triangles.data() + begin, end - begin);
  std::uint32_t lo = UINT32_MAX, hi = 0;
  for (const Triangle& t : triangles)
    for (std::uint32_t v : t) {
      lo = std::min(lo, v);
      hi = std::max(hi, v);
    }
  if (triangles.empty()) lo = hi = 0;
  writer.add_triangles(triangles, std::span(mesh.points).subspan(lo, hi - lo + 1), lo);
}

void write_in_pieces(const fs::path& file, const TriangleSoup& mesh,
                     const std::vector<Piece>& order, const WriteOptions& options) {
  MeshWriter writer(file, mesh.points.size(), mesh.triangles.size(), options);
  for (const Piece& piece : order) {
    if (piece.points)
      writer.add_points(std::span(mesh.points).subspan(piece.begin, piece.end - piece.begin));
    else
      add_triangle_piece(writer, mesh, piece.begin, piece.end);
  }
  writer.commit();
}

struct FormatCase {
  const char* name;
  WriteOptions options;
};
const FormatCase kFormats[] = {{"m.stl", {}},
                               {"m.stl", {.format = MeshFormat::StlAscii}},
                               {"m.obj", {}},
                               {"m.off", {}},
                               {"m.ply", {}}};

}  // namespace

TEST(IoMeshWriter, PiecesGiveTheBytesOfWriteMeshInEveryFormat) {
  const fs::path dir = test::scratch_dir();
  for (const TriangleSoup& mesh :
       {test::make_torus(5, 1.3, 24, 12), test::make_sphere({1, 2, 3}, 2.7, 2)}) {
    for (const FormatCase& format : kFormats) {
      const std::string label = std::string(format_name(format.options.format)) + " " + format.name;
      const fs::path whole = dir / "whole" / format.name;
      fs::create_directories(whole.parent_path());
      write_mesh(whole, mesh, format.options);
      const std::string expected = test::read_file(whole);
      for (const char* order : kOrders) {
        const fs::path file = dir / "pieces" / format.name;
        fs::remove_all(file.parent_path());
        fs::create_directories(file.parent_path());
        write_in_pieces(file, mesh, pieces(mesh, order), format.options);
        EXPECT_TRUE(test::read_file(file) == expected) << label << " " << order;
        // Nothing but the file: the temporary was renamed, the faces' one never had a name.
        EXPECT_EQ(listing(file.parent_path()), std::vector<std::string>{format.name});
        const TriangleSoup back = read_mesh(file);
        if (format_from_extension(file) == MeshFormat::StlBinary) {
          // STL stores three float points per facet.
          const TriangleSoup unshared = test::unshare_points(mesh);
          EXPECT_EQ(back.triangles, unshared.triangles) << label;
          EXPECT_EQ(corner_positions(back, true), corner_positions(unshared, true)) << label;
        } else {
          EXPECT_EQ(back.points, mesh.points) << label;
          EXPECT_EQ(back.triangles, mesh.triangles) << label;
        }
      }
    }
  }
}

TEST(IoMeshWriter, PiecesLongerThanOneBufferGiveTheSameBytes) {
  // 360,000 triangles: pieces are formatted a buffer of 2^18 at a time.
  const fs::path dir = test::scratch_dir();
  const TriangleSoup mesh = test::make_torus(5, 1.3, 600, 300);
  fs::create_directories(dir / "whole");
  for (const char* name : {"m.stl", "m.obj", "m.ply"}) {
    write_mesh(dir / "whole" / name, mesh);
    write_in_pieces(dir / name, mesh, pieces(mesh, "T0T1P0T2P1P2T3"), {});
    EXPECT_TRUE(test::read_file(dir / name) == test::read_file(dir / "whole" / name)) << name;
  }
  // A bad corner in the second buffer is named by its index in the whole mesh.
  TriangleSoup bad = mesh;
  bad.triangles[300000][2] = static_cast<std::uint32_t>(mesh.points.size());
  MeshWriter writer(dir / "bad.obj", mesh.points.size(), mesh.triangles.size());
  writer.add_points(mesh.points);
  try {
    writer.add_triangles(bad.triangles, mesh.points, 0);
    ADD_FAILURE() << "no exception";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("triangle 300000 refers to point 180000,"),
              std::string::npos)
        << e.what();
  }
  EXPECT_FALSE(fs::exists(dir / "bad.obj"));
}

TEST(IoMeshWriter, EmptyPiecesAndAnEmptyMeshChangeNothing) {
  const fs::path dir = test::scratch_dir();
  const TriangleSoup box = test::make_box({0, 0, 0}, {1, 2, 3});
  for (const FormatCase& format : kFormats) {
    fs::create_directories(dir / "whole");
    fs::create_directories(dir / "pieces");
    write_mesh(dir / "whole" / format.name, TriangleSoup{}, format.options);
    {
      MeshWriter writer(dir / "pieces" / format.name, 0, 0, format.options);
      writer.add_points({});
      writer.add_triangles({}, {}, 0);
      writer.commit();
    }
    EXPECT_EQ(test::read_file(dir / "pieces" / format.name),
              test::read_file(dir / "whole" / format.name));
    MeshWriter writer(dir / "pieces" / format.name, box.points.size(), box.triangles.size(),
                      format.options);
    writer.add_triangles({}, {}, 0);
    writer.add_points(box.points);
    writer.add_points({});
    writer.add_triangles(box.triangles, box.points, 0);
    writer.add_triangles({}, {}, 0);
    writer.commit();
    write_mesh(dir / "whole" / format.name, box, format.options);
    EXPECT_EQ(test::read_file(dir / "pieces" / format.name),
              test::read_file(dir / "whole" / format.name));
  }
}

TEST(IoMeshWriter, WrongCountsThrowAndLeaveNoFile) {
  const fs::path dir = test::scratch_dir();
  const TriangleSoup mesh = test::make_torus(5, 1.3, 12, 6);
  const std::size_t np = mesh.points.size(), nt = mesh.triangles.size();
  for (const FormatCase& format : kFormats) {
    const fs::path file = dir / format.name;
    // Fewer than declared, found at commit (with faces waiting for their points, too).
    for (const auto& [points, triangles, order] :
         {std::tuple{np + 1, nt, "T0P0T1P1T2P2T3"}, std::tuple{np, nt + 1, "P0P1P2T0T1T2T3"},
          std::tuple{np + 1, nt + 1, "T0T1T2T3P0P1P2"}}) {
      MeshWriter writer(file, points, triangles, format.options);
      for (const Piece& piece : pieces(mesh, order)) {
        if (piece.points)
          writer.add_points(std::span(mesh.points).subspan(piece.begin, piece.end - piece.begin));
        else
          add_triangle_piece(writer, mesh, piece.begin, piece.end);
      }
      try {
        writer.commit();
        ADD_FAILURE() << "no exception";
      } catch (const InputError& e) {
        const std::string what = e.what();
        EXPECT_EQ(what.rfind("cannot write " + file.string() + ": only ", 0), 0u) << what;
        EXPECT_NE(what.find("declared"), std::string::npos) << what;
      }
      EXPECT_TRUE(fs::is_empty(dir)) << format.name << " " << order;
      // Dead: every later call is refused, and nothing appears.
      EXPECT_THROW(writer.commit(), InputError);
      EXPECT_THROW(writer.add_points({}), InputError);
      EXPECT_TRUE(fs::is_empty(dir));
    }
    // More than declared, found when added.
    {
      MeshWriter writer(file, np - 1, nt, format.options);
      EXPECT_THROW(writer.add_points(mesh.points), InputError);
      EXPECT_TRUE(fs::is_empty(dir)) << format.name;
      EXPECT_THROW(writer.add_triangles(mesh.triangles, mesh.points, 0), InputError);
    }
    {
      MeshWriter writer(file, np, nt - 1, format.options);
      writer.add_points(mesh.points);
      EXPECT_THROW(writer.add_triangles(mesh.triangles, mesh.points, 0), InputError);
      EXPECT_TRUE(fs::is_empty(dir)) << format.name;
    }
    EXPECT_TRUE(fs::is_empty(dir));
  }
}

TEST(IoMeshWriter, CornerOutsideTheWindowOrThePointsThrows) {
  const fs::path dir = test::scratch_dir();
  const TriangleSoup box = test::make_box({0, 0, 0}, {1, 2, 3});
  const std::span<const Vec3> points(box.points);
  for (const FormatCase& format : kFormats) {
    const fs::path file = dir / format.name;
    {
      // The window starts one id too late for some corner.
      MeshWriter writer(file, 8, 12, format.options);
      writer.add_points(points);
      try {
        writer.add_triangles(box.triangles, points.subspan(1), 1);
        ADD_FAILURE() << "no exception";
      } catch (const InputError& e) {
        EXPECT_NE(std::string(e.what()).find("outside the window of points [1, 8)"),
                  std::string::npos)
            << e.what();
      }
      EXPECT_TRUE(fs::is_empty(dir)) << format.name;
      EXPECT_THROW(writer.add_triangles(box.triangles, points, 0), InputError);
      EXPECT_THROW(writer.commit(), InputError);
    }
    {
      // A window too short at the end, before any point was added.
      MeshWriter writer(file, 8, 12, format.options);
      EXPECT_THROW(writer.add_triangles(box.triangles, points.first(7), 0), InputError);
      EXPECT_TRUE(fs::is_empty(dir)) << format.name;
    }
    {
      // A corner past the declared points, however wide the window: write_mesh's message.
      TriangleSoup bad = box;
      bad.triangles[3][1] = 8;
      bad.points.push_back({9, 9, 9});
      MeshWriter writer(file, 8, 12, format.options);
      try {
        writer.add_triangles(bad.triangles, bad.points, 0);
        ADD_FAILURE() << "no exception";
      } catch (const InputError& e) {
        EXPECT_EQ(std::string(e.what()), "cannot write " + file.string() +
                                             ": triangle 3 refers to point 8, but there are "
                                             "only 8 points");
      }
      EXPECT_TRUE(fs::is_empty(dir)) << format.name;
    }
  }
}

TEST(IoMeshWriter, GzipTargetsHoldTheSameBytesDeflated) {
  // "m.stl.gz" and the others: gzip's magic, and inflated the very bytes of the uncompressed
  // file, whether written whole or in pieces with faces before the points (the sidecar path).
  const fs::path dir = test::scratch_dir();
  const TriangleSoup mesh = test::make_sphere({0.25, -0.5, 1}, 2, 3);
  for (const FormatCase& format : kFormats) {
    const fs::path plain = dir / format.name;
    const fs::path packed = dir / (std::string(format.name) + ".gz");
    write_mesh(plain, mesh, format.options);
    const std::string expected = test::read_file(plain);
    write_mesh(packed, mesh, format.options);
    std::string bytes = test::read_file(packed);
    ASSERT_GE(bytes.size(), 2u);
    EXPECT_EQ(bytes.substr(0, 2), "\x1f\x8b") << format.name;
    EXPECT_LT(bytes.size(), expected.size()) << format.name;
    EXPECT_TRUE(detail::inflate_bytes(bytes, packed.string(), UINT64_MAX) == expected)
        << format.name;
    {
      MeshWriter writer(packed, mesh.points.size(), mesh.triangles.size(), format.options);
      add_triangle_piece(writer, mesh, 0, 100);  // before the points: raw in the sidecar
      writer.add_points(mesh.points);
      add_triangle_piece(writer, mesh, 100, mesh.triangles.size());
      writer.commit();
    }
    bytes = test::read_file(packed);
    EXPECT_TRUE(detail::inflate_bytes(bytes, packed.string(), UINT64_MAX) == expected)
        << format.name;
    // The readers take it back by content, its name's inner extension breaking ties.
    const MeshFile back = read_mesh_file(packed);
    EXPECT_TRUE(back.gzip);
    EXPECT_EQ(back.soup.triangles.size(), mesh.triangles.size()) << format.name;
    fs::remove(plain);
    fs::remove(packed);
  }
  // The name decides unless the options do; write_options_for reads a name for a staged path.
  EXPECT_EQ(format_from_extension("x.PLY.GZ"), MeshFormat::Ply);
  EXPECT_EQ(format_from_extension("x.gz"), MeshFormat::Auto);
  EXPECT_TRUE(is_gzip_name("x.stl.Gz"));
  EXPECT_EQ(write_options_for("a/x.obj.gz").compression, Compression::Gzip);
  EXPECT_EQ(write_options_for("a/x.obj.gz").format, MeshFormat::Obj);
  EXPECT_EQ(write_options_for("x.stl").compression, Compression::None);
  const fs::path staged = dir / ".x.staged";
  write_mesh(staged, mesh, write_options_for("x.off.gz"));
  EXPECT_EQ(read_mesh_file(staged).format, MeshFormat::Off);
  EXPECT_TRUE(read_mesh_file(staged).gzip);
}

TEST(IoMeshWriter, TargetUntouchedUntilCommitAndWhenNeverCommitted) {
  const fs::path dir = test::scratch_dir();
  const TriangleSoup mesh = test::make_sphere({0, 0, 0}, 1, 1);
  for (const FormatCase& format : kFormats) {
    const fs::path file = dir / format.name;
    test::write_file(file, "old content");
    {
      // Everything added, never committed: the folder is as it was.
      MeshWriter writer(file, mesh.points.size(), mesh.triangles.size(), format.options);
      add_triangle_piece(writer, mesh, 0, 10);  // the faces wait in an unnamed temporary
      writer.add_points(mesh.points);
      add_triangle_piece(writer, mesh, 10, mesh.triangles.size());
      EXPECT_EQ(test::read_file(file), "old content");
      EXPECT_EQ(listing(dir).size(), 2u);  // the target and the temporary beside it
    }
    EXPECT_EQ(listing(dir), std::vector<std::string>{format.name});
    EXPECT_EQ(test::read_file(file), "old content");
    {
      MeshWriter writer(file, mesh.points.size(), mesh.triangles.size(), format.options);
      add_triangle_piece(writer, mesh, 0, 10);
      writer.add_points(mesh.points);
      add_triangle_piece(writer, mesh, 10, mesh.triangles.size());
      EXPECT_EQ(test::read_file(file), "old content");
      writer.commit();
      EXPECT_EQ(listing(dir), std::vector<std::string>{format.name});
      // Committed: later calls are refused and change nothing.
      EXPECT_THROW(writer.add_points({}), InputError);
      EXPECT_THROW(writer.commit(), InputError);
    }
    const std::string written = test::read_file(file);
    write_mesh(file, mesh, format.options);
    EXPECT_TRUE(written == test::read_file(file)) << format.name;
    fs::remove(file);
  }
}

TEST(IoMeshWriter, BadFormatOrCountsAreInputErrorsAndMissingFolderIoError) {
  const fs::path dir = test::scratch_dir();
  const std::uint64_t too_many = std::uint64_t{1} << 32;
  try {
    MeshWriter writer(dir / "m.xyz", 8, 12);
    ADD_FAILURE() << "no exception";
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()), "cannot write " + (dir / "m.xyz").string() +
                                         ": unknown extension (use .stl, .obj, .ply, .off or "
                                         ".3mf; the first four may end in .gz too)");
  }
  EXPECT_THROW(MeshWriter(dir / "m.stl", 3, too_many), InputError);
  EXPECT_THROW(MeshWriter(dir / "m.ply", too_many, 1), InputError);
  EXPECT_TRUE(fs::is_empty(dir));
  // The same counts fit the other formats (the writers are dropped uncommitted).
  MeshWriter(dir / "m.stl", too_many, too_many, {.format = MeshFormat::StlAscii});
  MeshWriter(dir / "m.ply", 3, too_many);
  MeshWriter(dir / "m.obj", too_many, too_many);
  EXPECT_TRUE(fs::is_empty(dir));
  const fs::path missing = dir / "no" / "such" / "m.obj";
  try {
    MeshWriter writer(missing, 8, 12);
    ADD_FAILURE() << "no exception";
  } catch (const IoError& e) {
    EXPECT_NE(std::string(e.what()).find(missing.string()), std::string::npos) << e.what();
  }
}

TEST(IoFormat, NamesAndExtensions) {
  EXPECT_EQ(format_name(MeshFormat::StlBinary), "stl-binary");
  EXPECT_EQ(format_name(MeshFormat::StlAscii), "stl-ascii");
  EXPECT_EQ(format_name(MeshFormat::Obj), "obj");
  EXPECT_EQ(format_name(MeshFormat::Ply), "ply");
  EXPECT_EQ(format_name(MeshFormat::Off), "off");
  EXPECT_EQ(format_name(MeshFormat::Auto), "auto");
  EXPECT_EQ(format_from_extension("a/b.STL"), MeshFormat::StlBinary);
  EXPECT_EQ(format_from_extension("b.Obj"), MeshFormat::Obj);
  EXPECT_EQ(format_from_extension("b.ply"), MeshFormat::Ply);
  EXPECT_EQ(format_from_extension("b.OFF"), MeshFormat::Off);
  EXPECT_EQ(format_from_extension("b.txt"), MeshFormat::Auto);
}

// ---- readers: accepted variants ----------------------------------------------------------

TEST(IoStl, AsciiSeveralSolidsEmptySolidsTabAndBom) {
  const std::string facet =
      "  FACET Normal 0 0 1\n OUTER loop\n  vertex 0 0 0\n  Vertex +1e0 0 0\n  vertex 0 1 0\n"
      " endloop\nendfacet\n";
  const std::string text = "\xEF\xBB\xBFsolid\tpart  with   spaces  \n" + facet +
                           "endsolid part\nsolid empty\nendsolid\nSOLID second\n" + facet + facet +
                           "ENDSOLID second\n";
  const MeshFile mesh = parse(text, "multi.stl");
  EXPECT_EQ(mesh.format, MeshFormat::StlAscii);
  EXPECT_EQ(mesh.soup.triangles.size(), 3u);
  EXPECT_EQ(mesh.soup.points.size(), 9u);  // STL facets never share points
  EXPECT_EQ(mesh.soup.points[1], (Vec3{1, 0, 0}));
}

TEST(IoStl, AsciiQuadFacetIsSplit) {
  const std::string text =
      "solid q\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nvertex 1 1 0\n"
      "vertex 0 1 0\nendloop\nendfacet\nendsolid q\n";
  const MeshFile mesh = parse(text, "q.stl");
  EXPECT_EQ(mesh.soup.triangles.size(), 2u);
  EXPECT_EQ(mesh.polygons_triangulated, 1u);
}

TEST(IoStl, BinaryHeaderStartingWithSolidIsBinary) {
  const std::string bytes = binary_stl(kTwoTriangles, 2, "solid looks like ascii");
  const MeshFile mesh = parse(bytes, "x.stl");
  EXPECT_EQ(mesh.format, MeshFormat::StlBinary);
  EXPECT_EQ(mesh.soup.triangles.size(), 2u);
  EXPECT_EQ(mesh.soup.points[4], (Vec3{1, 0, 1}));
}

TEST(IoStl, BinaryHeaderOfBinaryGarbageIsRead) {
  std::string header(80, '\0');
  for (int i = 0; i < 80; ++i) header[i] = static_cast<char>(255 - 3 * i);
  header[0] = '\xFF';  // even a UTF-16 byte-order mark
  header[1] = '\xFE';
  EXPECT_EQ(parse(binary_stl(kTwoTriangles, 2, header), "noext").soup.triangles.size(), 2u);
  header[0] = '\x1f';  // or the gzip magic
  header[1] = '\x8b';
  EXPECT_EQ(parse(binary_stl(kTwoTriangles, 2, header), "noext").soup.triangles.size(), 2u);
}

TEST(IoStl, BinaryCountTooLowReadsAllWithWarning) {
  const MeshFile mesh = parse(binary_stl(kTwoTriangles, 1), "low.stl");
  EXPECT_EQ(mesh.soup.triangles.size(), 2u);
  ASSERT_EQ(mesh.warnings.size(), 1u);
  EXPECT_NE(mesh.warnings[0].find("declares 1"), std::string::npos);
}

TEST(IoStl, BinaryTrailingBytesAreWarnedAbout) {
  const MeshFile mesh = parse(binary_stl(kTwoTriangles, 2) + "xyz", "trail.stl");
  EXPECT_EQ(mesh.soup.triangles.size(), 2u);
  ASSERT_EQ(mesh.warnings.size(), 1u);
  EXPECT_NE(mesh.warnings[0].find("trailing"), std::string::npos);
}

TEST(IoGzip, CompressedStlNamedStlReads) {
  const fs::path dir = test::scratch_dir();
  write_mesh(dir / "plain.stl", test::make_sphere({0, 0, 0}, 1, 2));
  const std::string plain = test::read_file(dir / "plain.stl");
  const fs::path packed = dir / "packed.stl";
  gzFile gz = gzopen(packed.c_str(), "wb9");
  ASSERT_NE(gz, nullptr);
  ASSERT_EQ(gzwrite(gz, plain.data(), static_cast<unsigned>(plain.size())),
            static_cast<int>(plain.size()));
  ASSERT_EQ(gzclose(gz), Z_OK);
  const MeshFile a = read_mesh_file(dir / "plain.stl"), b = read_mesh_file(packed);
  EXPECT_TRUE(b.gzip);
  EXPECT_FALSE(a.gzip);
  EXPECT_EQ(b.format, MeshFormat::StlBinary);
  EXPECT_EQ(a.soup.points, b.soup.points);
  EXPECT_EQ(a.soup.triangles, b.soup.triangles);
}

TEST(IoGzip, DecompressedSizeIsCapped) {
  std::string zeros(1 << 20, ' ');
  zeros = "solid a\n" + zeros;
  uLongf size = compressBound(zeros.size());
  std::string packed(size, '\0');
  // compress() writes zlib, not gzip: wrap by hand with gzip's header via deflateInit2.
  z_stream z{};
  ASSERT_EQ(deflateInit2(&z, 9, Z_DEFLATED, 15 + 16, 8, Z_DEFAULT_STRATEGY), Z_OK);
  z.next_in = reinterpret_cast<Bytef*>(zeros.data());
  z.avail_in = static_cast<uInt>(zeros.size());
  z.next_out = reinterpret_cast<Bytef*>(packed.data());
  z.avail_out = static_cast<uInt>(packed.size());
  ASSERT_EQ(deflate(&z, Z_FINISH), Z_STREAM_END);
  packed.resize(z.total_out);
  deflateEnd(&z);
  EXPECT_THROW(parse_mesh(packed, "bomb.stl", {.max_bytes = 1000}), InputError);
  // Truncated gzip data is a ParseError with a byte offset.
  try {
    parse_mesh(packed.substr(0, packed.size() / 2), "cut.stl.gz");
    FAIL();
  } catch (const ParseError& e) {
    EXPECT_TRUE(e.byte_offset().has_value()) << e.what();
  }
}

TEST(IoObj, Utf16WithByteOrderMarkReads) {
  const std::string ascii = "v 0 0 0\r\nv 1 0 0\r\nv 0 1 0\r\nf 1 2 3\r\n";
  for (const bool big : {true, false}) {
    std::string utf16 = big ? "\xFE\xFF" : "\xFF\xFE";
    for (const char c : ascii) {
      utf16 += big ? '\0' : c;
      utf16 += big ? c : '\0';
    }
    const MeshFile mesh = parse(utf16, "u.obj");
    EXPECT_EQ(mesh.format, MeshFormat::Obj);
    EXPECT_EQ(mesh.soup.triangles.size(), 1u);
  }
}

TEST(IoObj, CrlfContinuationPolygonsNegativeIndicesAndSlashForms) {
  std::string text = "# polygons\r\nmtllib none.mtl\r\no thing\r\ng a b\r\ns off\r\n";
  // A regular 11-gon and a hexagon, as fans of points on circles.
  for (int i = 0; i < 11; ++i)
    text += "v " + std::to_string(std::cos(2 * M_PI * i / 11)) + " " +
            std::to_string(std::sin(2 * M_PI * i / 11)) + " 0 1.0 0.5 0.5 0.5\r\n";
  text +=
      "vt 0 0\r\nvn 0 0 1\r\nusemtl x\r\nf 1/1/1 2/1/1 3/1/1 4/1/1 5/1/1 6/1/1 \\\r\n"
      "  7/1/1 8/1/1 9//1 10/1 11\r\n";
  for (int i = 0; i < 6; ++i)
    text += "v " + std::to_string(std::cos(2 * M_PI * i / 6)) + " " +
            std::to_string(std::sin(2 * M_PI * i / 6)) + " +1e0\r\n";
  text += "f -6 -5 -4 -3 -2 -1\r\nl 1 2\r\np 3\r\nunknown keyword\r\nf -3/1 -2/1 -1/1";
  const MeshFile mesh = parse(text, "poly.obj");
  EXPECT_EQ(mesh.soup.points.size(), 17u);
  EXPECT_EQ(mesh.faces_in_file, 3u);
  EXPECT_EQ(mesh.polygons_triangulated, 2u);
  EXPECT_EQ(mesh.soup.triangles.size(), 9u + 4u + 1u);
  EXPECT_EQ(mesh.soup.points[11].z, 1.0);
  EXPECT_EQ(mesh.soup.triangles.back(), (Triangle{14, 15, 16}));
  for (std::size_t t = 0; t < 9; ++t)
    for (std::uint32_t v : mesh.soup.triangles[t]) EXPECT_LT(v, 11u);
}

TEST(IoOff, LeadingWhitespaceCountsOnKeywordLineAndComments) {
  const std::string text =
      "  \n\t OFF 4 2 0 # counts here\n# a comment\n0 0 0\n1 0 0 # trailing\n\n1 1 0\n0 1 0\n"
      "3 0 1 2\n3 0 2 3 255 0 0\n";
  const MeshFile mesh = parse(text, "a.off");
  EXPECT_EQ(mesh.format, MeshFormat::Off);
  EXPECT_EQ(mesh.soup.triangles.size(), 2u);
  EXPECT_EQ(mesh.soup.triangles[1], (Triangle{0, 2, 3}));
}

TEST(IoOff, KeywordGluedToTheVertexCount) {
  // "OFF8 6 12": a cube's header with the space after OFF lost, as a real file had it. Read
  // as OFF with 8 vertices, 6 quads and 12 edges: a closed box of volume 1.
  std::string text = "OFF8 6 12\n";
  for (int v = 0; v < 8; ++v)
    text += std::to_string(v & 1) + " " + std::to_string(v >> 1 & 1) + " " +
            std::to_string(v >> 2 & 1) + "\n";
  text += "4 0 2 3 1\n4 4 5 7 6\n4 0 1 5 4\n4 2 6 7 3\n4 0 4 6 2\n4 1 3 7 5\n";
  const MeshFile mesh = parse(text, "cube.off");
  EXPECT_EQ(mesh.format, MeshFormat::Off);
  EXPECT_EQ(mesh.soup.points.size(), 8u);
  EXPECT_EQ(mesh.faces_in_file, 6u);
  EXPECT_NEAR(test::signed_volume(mesh.soup), 1.0, 1e-12);
  // Found by content too, whatever the name says.
  EXPECT_EQ(parse(text, "cube.txt").soup.triangles.size(), 12u);
  EXPECT_EQ(parse("COFF3 1\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n", "c.off").soup.triangles.size(), 1u);
}

TEST(IoOff, CoffWithColoursAndCountsOnNextLine) {
  const std::string text =
      "COFF\n# c\n4 1 0\n0 0 0 255 0 0 255\n1 0 0 0 255 0 255\n1 1 0 0 0 255 255\n"
      "0 1 0 1 1 1 1\n4 0 1 2 3 0.5 0.5 0.5\n";
  const MeshFile mesh = parse(text, "c.off");
  EXPECT_EQ(mesh.soup.points.size(), 4u);
  EXPECT_EQ(mesh.soup.points[2], (Vec3{1, 1, 0}));
  EXPECT_EQ(mesh.soup.triangles.size(), 2u);
  EXPECT_EQ(mesh.polygons_triangulated, 1u);
  for (const char* keyword : {"NOFF", "CNOFF", "STOFF"}) {
    EXPECT_EQ(parse(std::string(keyword) + "\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n", "k.off")
                  .soup.triangles.size(),
              1u)
        << keyword;
  }
}

namespace {
std::string ply_header(const std::string& format, const std::string& body) {
  return "ply\r\nformat " + format + " 1.0\r\ncomment c\r\nobj_info o\r\n" + body + "end_header\n";
}
template <typename T>
void put_be(std::string& out, T value) {
  char b[sizeof(T)];
  std::memcpy(b, &value, sizeof(T));
  std::reverse(b, b + sizeof(T));
  out.append(b, sizeof(T));
}
template <typename T>
void put_le(std::string& out, T value) {
  out.append(reinterpret_cast<const char*>(&value), sizeof(T));
}
}  // namespace

TEST(IoPly, AsciiWithExtraElementsAndProperties) {
  const std::string text = ply_header("ascii",
                                      "element material 1\nproperty list uchar int ids\n"
                                      "element face 1\nproperty uchar flags\n"
                                      "property list uchar int vertex_index\n"
                                      "element vertex 4\nproperty uchar red\nproperty float x\n"
                                      "property double y\nproperty list int float extra\n"
                                      "property int z\n") +
                           "3 7 8 9\n1 4 0 1 2 3\n"
                           "10 0 0 2 0.5 0.5 0\n10 1 0 0 0\n10 +1 1 1 9 0\n10 0 1 0 0\n";
  const MeshFile mesh = parse(text, "a.ply");
  EXPECT_EQ(mesh.soup.points, (std::vector<Vec3>{{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}}));
  EXPECT_EQ(mesh.soup.triangles.size(), 2u);
}

TEST(IoPly, BigEndianAndLittleEndianWithEveryScalarType) {
  for (const bool big : {true, false}) {
    std::string data = ply_header(big ? "binary_big_endian" : "binary_little_endian",
                                  "element vertex 3\nproperty char x\nproperty ushort y\n"
                                  "property float64 z\nproperty list uint16 int8 junk\n"
                                  "element face 1\nproperty list int uint32 vertex_indices\n"
                                  "property short s\n");
    auto put = [&](auto v) { big ? put_be(data, v) : put_le(data, v); };
    const std::int8_t xs[3] = {-1, 2, 3};
    for (int i = 0; i < 3; ++i) {
      put(xs[i]);
      put(static_cast<std::uint16_t>(1000 + i));
      put(0.25 * i);
      put(static_cast<std::uint16_t>(2));  // two junk items
      put(std::int8_t{7});
      put(std::int8_t{8});
    }
    put(std::int32_t{3});
    for (std::uint32_t v : {0u, 1u, 2u}) put(v);
    put(std::int16_t{-5});
    const MeshFile mesh = parse(data, "b.ply");
    EXPECT_EQ(mesh.soup.points,
              (std::vector<Vec3>{{-1, 1000, 0}, {2, 1001, 0.25}, {3, 1002, 0.5}}));
    EXPECT_EQ(mesh.soup.triangles, (std::vector<Triangle>{{0, 1, 2}}));
  }
}

// ---- real files --------------------------------------------------------------------------

namespace {
fs::path assimp(const std::string& relative) {
  return fs::path(TPMSFILL_ASSIMP_MODELS) / relative;
}
}  // namespace

TEST(IoRealFiles, EveryAssimpModelReadsOrThrowsOurError) {
  if (!fs::is_directory(TPMSFILL_ASSIMP_MODELS)) GTEST_SKIP() << "assimp-testmodels missing";
  int read = 0, refused = 0;
  for (const auto& entry : fs::recursive_directory_iterator(TPMSFILL_ASSIMP_MODELS)) {
    std::string ext = entry.path().extension().string();
    std::transform(ext.begin(), ext.end(), ext.begin(), ::tolower);
    if (!entry.is_regular_file() ||
        (ext != ".stl" && ext != ".obj" && ext != ".ply" && ext != ".off"))
      continue;
    try {
      EXPECT_GE(read_mesh(entry.path()).triangles.size(), 1u);
      ++read;
    } catch (const Error&) {
      ++refused;
    }
  }
  EXPECT_GT(read, 20);
  RecordProperty("read", read);
  RecordProperty("refused", refused);
}

TEST(IoRealFiles, SpiderInThreeFormats) {
  if (!fs::exists(assimp("STL/Spider_ascii.stl"))) GTEST_SKIP() << "assimp-testmodels missing";
  const MeshFile ascii = read_mesh_file(assimp("STL/Spider_ascii.stl"));
  const MeshFile binary = read_mesh_file(assimp("STL/Spider_binary.stl"));
  EXPECT_EQ(ascii.format, MeshFormat::StlAscii);
  EXPECT_EQ(binary.format, MeshFormat::StlBinary);
  ASSERT_EQ(ascii.soup.triangles.size(), 1368u);
  ASSERT_EQ(binary.soup.triangles.size(), 1368u);
  EXPECT_EQ(ascii.soup.triangles, binary.soup.triangles);
  // The ASCII file prints 6 decimals: equal to float precision, not bit for bit.
  const std::vector<Vec3> a = corner_positions(ascii.soup), b = corner_positions(binary.soup);
  for (std::size_t i = 0; i < a.size(); ++i)
    for (int axis = 0; axis < 3; ++axis)
      ASSERT_NEAR(a[i][axis], b[i][axis], 1e-6 * std::max(1.0, std::fabs(b[i][axis]))) << i;
  EXPECT_EQ(read_mesh(assimp("OBJ/spider.obj")).triangles.size(), 1368u);
}

TEST(IoRealFiles, AssimpPlyAndUtf16Obj) {
  if (!fs::exists(assimp("PLY/cube.ply"))) GTEST_SKIP() << "assimp-testmodels missing";
  EXPECT_EQ(read_mesh(assimp("PLY/cube.ply")).triangles.size(), 12u);
  EXPECT_EQ(read_mesh(assimp("PLY/cube_binary.ply")).triangles.size(), 12u);
  EXPECT_EQ(read_mesh(assimp("OBJ/box_UTF16BE.obj")).triangles.size(), 12u);
}

TEST(IoRealFiles, PointCloudsHaveNoTriangles) {
  if (!fs::exists(assimp("PLY/points.ply"))) GTEST_SKIP() << "assimp-testmodels missing";
  for (const char* file : {"OBJ/point_cloud.obj", "OBJ/testpoints.obj", "PLY/points.ply"}) {
    try {
      read_mesh(assimp(file));
      ADD_FAILURE() << file;
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find("no triangles"), std::string::npos) << e.what();
    }
  }
}

TEST(IoRealFiles, CgalFemur) {
  const fs::path femur = fs::path(TPMSFILL_CGAL_MESHES) / "femur.off";
  if (!fs::exists(femur)) GTEST_SKIP() << "libcgal-demo meshes missing";
  const MeshFile mesh = read_mesh_file(femur);
  EXPECT_EQ(mesh.soup.triangles.size(), 7798u);
  EXPECT_EQ(mesh.soup.points.size(), 3897u);
  EXPECT_GT(test::signed_volume(mesh.soup), 0);
}
