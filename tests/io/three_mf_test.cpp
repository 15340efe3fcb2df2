// 3MF in and out (src/io/three_mf.cpp): what tpmsfill writes, lib3mf reads back as the same mesh
// with its metadata; what lib3mf writes (transforms, components, units, supports), tpmsfill
// reads as a slicer would; broken packages are refused with a sentence.
#include <Model/COM/NMR_DLLInterfaces.h>
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/resource.h>
#include <zip.h>

#include <chrono>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <limits>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include "io/inflate.hpp"
#include "io/three_mf.hpp"
#include "test_util.hpp"
#include "tpmsfill/check.hpp"
#include "tpmsfill/error.hpp"
#include "tpmsfill/fill.hpp"
#include "tpmsfill/io.hpp"
#include "tpmsfill/mesh/validate.hpp"
#include "tpmsfill/repair.hpp"

namespace tpmsfill {
namespace {

namespace fs = std::filesystem;

// ---- lib3mf, as a slicer would use it ------------------------------------------------------

struct Release {
  void operator()(NMR::PLib3MFBase* p) const { NMR::lib3mf_release(p); }
};
using Handle = std::unique_ptr<NMR::PLib3MFBase, Release>;

Handle read_model(const fs::path& path) {
  NMR::PLib3MFModel* model = nullptr;
  EXPECT_EQ(NMR::lib3mf_createmodel(&model), LIB3MF_OK);
  Handle owned(model);
  NMR::PLib3MFModelReader* reader = nullptr;
  EXPECT_EQ(NMR::lib3mf_model_queryreader(model, "3mf", &reader), LIB3MF_OK);
  const Handle owned_reader(reader);
  // tpmsfill's attachments (its recipe and report) are read when their relationship is named.
  EXPECT_EQ(NMR::lib3mf_reader_addrelationtoreadutf8(reader,
                                                     "http://schemas.tpmsfill.org/3mf/attachment"),
            LIB3MF_OK);
  EXPECT_EQ(NMR::lib3mf_reader_readfromfileutf8(reader, path.c_str()), LIB3MF_OK) << path;
  return owned;
}

std::string metadata_value(NMR::PLib3MFModel* model, const std::string& key) {
  DWORD count = 0;
  NMR::lib3mf_model_getmetadatacount(model, &count);
  for (DWORD i = 0; i < count; ++i) {
    ULONG needed = 0;
    std::string k(256, '\0');
    NMR::lib3mf_model_getmetadatakeyutf8(model, i, k.data(), k.size(), &needed);
    k.resize(std::strlen(k.c_str()));
    if (k != key) continue;
    NMR::lib3mf_model_getmetadatavalueutf8(model, i, nullptr, 0, &needed);
    std::string v(needed + 1, '\0');
    NMR::lib3mf_model_getmetadatavalueutf8(model, i, v.data(), v.size(), &needed);
    v.resize(std::strlen(v.c_str()));
    return v;
  }
  return "(absent)";
}

// A unit tetrahedron object (outward), for packages made here.
NMR::PLib3MFModelMeshObject* add_tetrahedron(NMR::PLib3MFModel* model, DWORD type) {
  NMR::PLib3MFModelMeshObject* object = nullptr;
  EXPECT_EQ(NMR::lib3mf_model_addmeshobject(model, &object), LIB3MF_OK);
  NMR::MODELMESHVERTEX v[4] = {{{0, 0, 0}}, {{1, 0, 0}}, {{0, 1, 0}}, {{0, 0, 1}}};
  NMR::MODELMESHTRIANGLE t[4] = {{{0, 2, 1}}, {{0, 1, 3}}, {{1, 2, 3}}, {{0, 3, 2}}};
  EXPECT_EQ(NMR::lib3mf_meshobject_setgeometry(object, v, 4, t, 4), LIB3MF_OK);
  EXPECT_EQ(NMR::lib3mf_object_settype(object, type), LIB3MF_OK);
  return object;
}

NMR::MODELTRANSFORM transform(double scale, Vec3 shift) {
  NMR::MODELTRANSFORM m{};
  for (int i = 0; i < 3; ++i) m.m_fFields[i][i] = static_cast<float>(scale);
  m.m_fFields[0][3] = static_cast<float>(shift.x);
  m.m_fFields[1][3] = static_cast<float>(shift.y);
  m.m_fFields[2][3] = static_cast<float>(shift.z);
  return m;
}

void write_model(NMR::PLib3MFModel* model, const fs::path& path) {
  NMR::PLib3MFModelWriter* writer = nullptr;
  ASSERT_EQ(NMR::lib3mf_model_querywriter(model, "3mf", &writer), LIB3MF_OK);
  const Handle owned(writer);
  ASSERT_EQ(NMR::lib3mf_writer_writetofileutf8(writer, path.c_str()), LIB3MF_OK);
}

TriangleSoup rounded(TriangleSoup soup) {
  round_coordinates(CoordinateRounding::ThreeMf, soup);
  return soup;
}

// ---- what we write --------------------------------------------------------------------------

TEST(ThreeMf, RoundedMeshReadsBackBitIdentical) {
  // A sphere off the origin, its points rounded as lib3mf writes them: written and read back
  // through lib3mf, every coordinate and every triangle is the same, and so is a second write.
  const fs::path dir = test::scratch_dir();
  const TriangleSoup mesh = rounded(test::make_sphere({12.345678, -0.000321, 101.5}, 7.25, 4));
  write_mesh(dir / "s.3mf", mesh);
  const MeshFile back = read_mesh_file(dir / "s.3mf");
  EXPECT_EQ(back.format, MeshFormat::ThreeMf);
  EXPECT_TRUE(back.warnings.empty());
  ASSERT_EQ(back.soup.points.size(), mesh.points.size());
  ASSERT_EQ(back.soup.triangles, mesh.triangles);
  for (std::size_t i = 0; i < mesh.points.size(); ++i) {
    EXPECT_EQ(back.soup.points[i].x, mesh.points[i].x) << i;
    EXPECT_EQ(back.soup.points[i].y, mesh.points[i].y) << i;
    EXPECT_EQ(back.soup.points[i].z, mesh.points[i].z) << i;
  }
  fs::create_directory(dir / "again");
  write_mesh(dir / "again" / "s.3mf", back.soup);
  EXPECT_EQ(test::read_file(dir / "again" / "s.3mf"), test::read_file(dir / "s.3mf"))
      << "the same mesh must give the same bytes (UUIDs from the content, not drawn)";
}

TEST(ThreeMf, RoundingIsWhatLib3mfWritesAtEveryMagnitude) {
  // Random coordinates from 1e-7 mm to 1e5 mm, both signs: rounded, they are fixed points of
  // the rounding, within 6 µm (runs of micrometres that do not stand, below 10 mm) plus two
  // steps of lib3mf's float arithmetic (the float product's ulp, in micrometres: 8 µm at
  // 100 mm, 64 µm at 1000 mm), and lib3mf writes them as they are.
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> mantissa(1, 10);
  TriangleSoup soup;
  for (int i = 0; i < 30000; ++i) {
    Vec3 p;
    for (double* c : {&p.x, &p.y, &p.z})
      *c = (rng() % 2 ? 1 : -1) * mantissa(rng) * std::pow(10.0, static_cast<int>(rng() % 13) - 7);
    const Vec3 q = round_coordinates(CoordinateRounding::ThreeMf, p);
    const Vec3 qq = round_coordinates(CoordinateRounding::ThreeMf, q);
    ASSERT_TRUE(q.x == qq.x && q.y == qq.y && q.z == qq.z) << p.x << " " << p.y << " " << p.z;
    for (const auto& [a, b] : {std::pair{p.x, q.x}, {p.y, q.y}, {p.z, q.z}}) {
      const float product = static_cast<float>(std::fabs(a)) * 1e6f;
      const double step = (std::nextafter(product, INFINITY) - product) / 1e6;
      ASSERT_LE(std::fabs(a - b), 6e-6 + 2 * step) << a << " -> " << b;
    }
    soup.points.push_back(q);
  }
  for (std::uint32_t i = 0; i + 2 < soup.points.size(); i += 3)
    soup.triangles.push_back({i, i + 1, i + 2});
  const fs::path path = test::scratch_dir() / "magnitudes.3mf";
  write_mesh(path, soup);
  const TriangleSoup back = read_mesh(path);
  ASSERT_EQ(back.points.size(), soup.points.size());
  for (std::size_t i = 0; i < soup.points.size(); ++i)
    ASSERT_TRUE(back.points[i].x == soup.points[i].x && back.points[i].y == soup.points[i].y &&
                back.points[i].z == soup.points[i].z)
        << i;
}

TEST(ThreeMf, FilledLatticeIsOneValidObjectWithItsMetadata) {
  // fill_to_file into a 3MF: lib3mf reads one object in millimetres whose mesh is what fill
  // validated (closed, 2-manifold, outward, no self-intersections, the report's triangles and
  // volume), with a title, the tool as Application, a description naming the porosity, and the
  // report attached.
  const fs::path dir = test::scratch_dir();
  const FillResult r = fill_to_file(test::make_sphere({0.3, 0.1, -0.2}, 5, 4),
                                    test::gyroid_options(2.5, 0.2), dir / "ball.3mf");
  const Handle model = read_model(dir / "ball.3mf");
  DWORD unit = 99;
  NMR::lib3mf_model_getunit(model.get(), &unit);
  EXPECT_EQ(unit, static_cast<DWORD>(NMR::MODELUNIT_MILLIMETER));
  EXPECT_EQ(metadata_value(model.get(), "Title"), "ball");
  EXPECT_EQ(metadata_value(model.get(), "Application"), "tpmsfill " + std::string("0.1.0"));
  const std::string description = metadata_value(model.get(), "Description");
  EXPECT_NE(description.find("gyroid"), std::string::npos) << description;
  EXPECT_NE(description.find("porosity"), std::string::npos) << description;
  DWORD attachments = 0;
  NMR::lib3mf_model_getattachmentcount(model.get(), &attachments);
  EXPECT_EQ(attachments, 1u);

  const MeshFile back = read_mesh_file(dir / "ball.3mf");
  EXPECT_EQ(back.soup.triangles.size(), r.report.triangles());
  const MeshValidity v = validate_mesh(back.soup);
  EXPECT_TRUE(v.valid()) << (v.problems().empty() ? "" : v.problems().front());
  ASSERT_TRUE(v.self_intersecting_pairs.has_value());
  EXPECT_EQ(*v.self_intersecting_pairs, 0u);
  EXPECT_NEAR(*v.volume, r.report.lattice_volume(), 1e-9 * r.report.lattice_volume());
  // The same job writes the same bytes: the attached report holds no seconds or peak memory.
  fs::create_directories(dir / "again");
  fill_to_file(test::make_sphere({0.3, 0.1, -0.2}, 5, 4), test::gyroid_options(2.5, 0.2),
               dir / "again" / "ball.3mf");
  EXPECT_TRUE(test::read_file(dir / "ball.3mf") == test::read_file(dir / "again" / "ball.3mf"));
}

TEST(ThreeMf, RepairedMessyMeshStaysValidThroughThePackage) {
  // A sphere with a hole and a flipped face, repaired with the 3MF's rounding: written, read
  // back and checked, it is still valid (rounding is applied before the final check).
  TriangleSoup messy = test::flip(test::make_sphere({1, 2, 3}, 4, 3), 5);
  messy = test::without_triangles(messy, [](const Vec3& c) { return c.z > 6.7; });  // a hole
  RepairOptions options;
  options.rounding = CoordinateRounding::ThreeMf;
  const RepairResult r = repair_mesh(messy, options);
  ASSERT_TRUE(r.report.after.valid());
  const fs::path path = test::scratch_dir() / "repaired.3mf";
  write_mesh(path, r.mesh);
  const MeshCheck check = check_mesh(read_mesh(path));
  EXPECT_TRUE(check.valid());
}

TEST(ThreeMf, PiecesHeldUntilCommitGiveTheWholeMesh) {
  // MeshWriter with faces before points, in pieces, and metadata set late: the same package as
  // write_mesh with that metadata.
  const fs::path dir = test::scratch_dir();
  const TriangleSoup mesh = rounded(test::make_torus(5, 2, 24, 12));
  MeshMetadata late{.title = "torus", .description = "a torus & <friends>", .attachments = {}};
  write_mesh(dir / "whole.3mf", mesh, {.metadata = late});
  {
    MeshWriter writer(dir / "pieces.3mf", mesh.points.size(), mesh.triangles.size());
    writer.add_triangles(std::span(mesh.triangles).first(50), mesh.points, 0);
    writer.add_points(std::span(mesh.points).first(100));
    writer.add_points(std::span(mesh.points).subspan(100));
    writer.add_triangles(std::span(mesh.triangles).subspan(50), mesh.points, 0);
    writer.set_metadata(late);
    writer.commit();
  }
  EXPECT_EQ(test::read_file(dir / "pieces.3mf"), test::read_file(dir / "whole.3mf"));
  const Handle model = read_model(dir / "whole.3mf");
  // The XML holds the text escaped (lib3mf 1.8 writes metadata as given, so tpmsfill escapes
  // it); lib3mf hands it back as the XML holds it, where a conforming XML reader unescapes it.
  EXPECT_EQ(metadata_value(model.get(), "Description"), "a torus &amp; &lt;friends&gt;");
  EXPECT_EQ(metadata_value(model.get(), "Title"), "torus");
}

TEST(ThreeMf, GzipOfAPackageIsRefusedAndNothingIsWritten) {
  const fs::path dir = test::scratch_dir();
  const TriangleSoup mesh = test::make_box({0, 0, 0}, {1, 1, 1});
  EXPECT_THROW(write_mesh(dir / "b.3mf.gz", mesh), InputError);
  EXPECT_THROW(write_mesh(dir / "b.3mf", mesh, {.compression = Compression::Gzip}), InputError);
  EXPECT_TRUE(test::files_in(dir, UINTMAX_MAX).empty());
}

// ---- what others write ----------------------------------------------------------------------

TEST(ThreeMf, BuildItemsComponentsUnitsAndSupportsAreReadAsASlicerWould) {
  // In centimetres: a tetrahedron placed twice by build items (once scaled by 2 and moved), a
  // components object placing it once more (moved, inside a moved build item), and a support
  // object that is not part of the part. Read: 3 tetrahedra in mm at the composed places, the
  // support skipped, both said in warnings.
  NMR::PLib3MFModel* raw = nullptr;
  ASSERT_EQ(NMR::lib3mf_createmodel(&raw), LIB3MF_OK);
  const Handle model(raw);
  ASSERT_EQ(NMR::lib3mf_model_setunit(raw, NMR::MODELUNIT_CENTIMETER), LIB3MF_OK);
  const Handle tet(add_tetrahedron(raw, NMR::MODELOBJECTTYPE_MODEL));
  const Handle support(add_tetrahedron(raw, NMR::MODELOBJECTTYPE_SUPPORT));
  NMR::PLib3MFModelComponentsObject* group = nullptr;
  ASSERT_EQ(NMR::lib3mf_model_addcomponentsobject(raw, &group), LIB3MF_OK);
  const Handle owned_group(group);
  NMR::PLib3MFModelComponent* component = nullptr;
  NMR::MODELTRANSFORM inner = transform(1, {0, 0, 5});
  ASSERT_EQ(NMR::lib3mf_componentsobject_addcomponent(group, tet.get(), &inner, &component),
            LIB3MF_OK);
  const Handle owned_component(component);
  NMR::PLib3MFModelBuildItem* item = nullptr;
  ASSERT_EQ(NMR::lib3mf_model_addbuilditem(raw, tet.get(), nullptr, &item), LIB3MF_OK);
  NMR::lib3mf_release(item);
  NMR::MODELTRANSFORM placed = transform(2, {10, 0, 0});
  ASSERT_EQ(NMR::lib3mf_model_addbuilditem(raw, tet.get(), &placed, &item), LIB3MF_OK);
  NMR::lib3mf_release(item);
  NMR::MODELTRANSFORM outer = transform(1, {0, 20, 0});
  ASSERT_EQ(NMR::lib3mf_model_addbuilditem(raw, group, &outer, &item), LIB3MF_OK);
  NMR::lib3mf_release(item);
  ASSERT_EQ(NMR::lib3mf_model_addbuilditem(raw, support.get(), nullptr, &item), LIB3MF_OK);
  NMR::lib3mf_release(item);
  const fs::path path = test::scratch_dir() / "assembly.3mf";
  write_model(raw, path);

  const MeshFile file = read_mesh_file(path);
  ASSERT_EQ(file.soup.triangles.size(), 12u);
  ASSERT_EQ(file.soup.points.size(), 12u);
  // Each tetrahedron's apex (its 4th point) in mm: 10 mm per cm.
  const Vec3 apex[3] = {{0, 0, 10}, {100, 0, 20}, {0, 200, 60}};
  for (int k = 0; k < 3; ++k) {
    const Vec3 p = file.soup.points[4 * k + 3];
    EXPECT_NEAR(p.x, apex[k].x, 1e-9) << k;
    EXPECT_NEAR(p.y, apex[k].y, 1e-9) << k;
    EXPECT_NEAR(p.z, apex[k].z, 1e-9) << k;
  }
  // Volumes: 1/6 cm³ = 166.7 mm³, scaled by 2³ for the second.
  EXPECT_NEAR(test::signed_volume(file.soup), 1000.0 / 6 * (1 + 8 + 1), 1e-6);
  ASSERT_EQ(file.warnings.size(), 2u);
  EXPECT_NE(file.warnings[0].find("centimeter"), std::string::npos) << file.warnings[0];
  EXPECT_NE(file.warnings[1].find("skipped 1"), std::string::npos) << file.warnings[1];
}

TEST(ThreeMf, BrokenPackagesAreRefusedWithASentence) {
  // Cut short, a zip of something else, and a package whose build is empty.
  const fs::path dir = test::scratch_dir();
  write_mesh(dir / "t.3mf", test::make_sphere({0, 0, 0}, 1, 2));
  const std::string bytes = test::read_file(dir / "t.3mf");
  test::write_file(dir / "cut.3mf", bytes.substr(0, bytes.size() / 2));
  try {
    read_mesh(dir / "cut.3mf");
    ADD_FAILURE() << "no exception";
  } catch (const ParseError& e) {
    EXPECT_NE(std::string(e.what()).find("not a readable 3MF package"), std::string::npos)
        << e.what();
  }
  // A zip's magic and then garbage: detected by content whatever the name, then refused.
  test::write_file(dir / "junk.stl", std::string("PK\x03\x04", 4) + std::string(300, 'x'));
  EXPECT_THROW(read_mesh(dir / "junk.stl"), ParseError);

  NMR::PLib3MFModel* raw = nullptr;
  ASSERT_EQ(NMR::lib3mf_createmodel(&raw), LIB3MF_OK);
  const Handle model(raw);
  write_model(raw, dir / "empty.3mf");
  EXPECT_THROW(read_mesh(dir / "empty.3mf"), InputError);
}

TEST(ThreeMf, GzippedPackageIsUnwrappedFirst) {
  // The readers inflate any gzip stream; a 3MF inside one is read like the package.
  const fs::path dir = test::scratch_dir();
  const TriangleSoup mesh = rounded(test::make_box({0, 0, 0}, {2, 3, 4}));
  write_mesh(dir / "box.3mf", mesh);
  const std::string package = test::read_file(dir / "box.3mf");
  ASSERT_EQ(std::system(("gzip -c '" + (dir / "box.3mf").string() + "' > '" +
                         (dir / "box.gz").string() + "'")
                            .c_str()),
            0);
  const MeshFile back = read_mesh_file(dir / "box.gz");
  EXPECT_TRUE(back.gzip);
  EXPECT_EQ(back.format, MeshFormat::ThreeMf);
  EXPECT_EQ(back.soup.triangles, mesh.triangles);
}

TEST(ThreeMf, ComponentsThatFanOutAreRefusedAtTheInstanceLimit) {
  // Components 8 wide and 12 deep place 8^12 tetrahedra from a package of a few KB: refused
  // once the limit's worth is placed (a second or so), not after days.
  NMR::PLib3MFModel* raw = nullptr;
  ASSERT_EQ(NMR::lib3mf_createmodel(&raw), LIB3MF_OK);
  const Handle model(raw);
  std::vector<Handle> owned;
  owned.emplace_back(add_tetrahedron(raw, NMR::MODELOBJECTTYPE_MODEL));
  for (int level = 0; level < 12; ++level) {
    NMR::PLib3MFModelComponentsObject* group = nullptr;
    ASSERT_EQ(NMR::lib3mf_model_addcomponentsobject(raw, &group), LIB3MF_OK);
    for (int k = 0; k < 8; ++k) {
      NMR::PLib3MFModelComponent* component = nullptr;
      NMR::MODELTRANSFORM shift = transform(1, {k * 2.0, 0, 0});
      ASSERT_EQ(
          NMR::lib3mf_componentsobject_addcomponent(group, owned.back().get(), &shift, &component),
          LIB3MF_OK);
      NMR::lib3mf_release(component);
    }
    owned.emplace_back(group);
  }
  NMR::PLib3MFModelBuildItem* item = nullptr;
  ASSERT_EQ(NMR::lib3mf_model_addbuilditem(raw, owned.back().get(), nullptr, &item), LIB3MF_OK);
  NMR::lib3mf_release(item);
  const fs::path path = test::scratch_dir() / "fan.3mf";
  write_model(raw, path);
  EXPECT_LT(fs::file_size(path), 8192u);
  try {
    read_mesh(path);
    ADD_FAILURE() << "no exception";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("places more than " +
                                         std::to_string(io::kMax3mfInstances) + " objects"),
              std::string::npos)
        << e.what();
  }
}

TEST(ThreeMf, TransformsThatAreNotFiniteAreRefused) {
  // A build item and a component whose transforms hold NaN (lib3mf reads "nan"; it refuses
  // "inf" itself): refused with the sentence every reader gives non-finite numbers, before
  // any point reaches a check or a fill.
  const fs::path dir = test::scratch_dir();
  for (const float bad :
       {std::numeric_limits<float>::quiet_NaN(), -std::numeric_limits<float>::quiet_NaN()}) {
    for (const bool component : {false, true}) {
      NMR::PLib3MFModel* raw = nullptr;
      ASSERT_EQ(NMR::lib3mf_createmodel(&raw), LIB3MF_OK);
      const Handle model(raw);
      const Handle tet(add_tetrahedron(raw, NMR::MODELOBJECTTYPE_MODEL));
      NMR::MODELTRANSFORM t = transform(1, {0, 0, 0});
      t.m_fFields[1][3] = bad;
      NMR::PLib3MFModelBuildItem* item = nullptr;
      if (component) {
        NMR::PLib3MFModelComponentsObject* group = nullptr;
        ASSERT_EQ(NMR::lib3mf_model_addcomponentsobject(raw, &group), LIB3MF_OK);
        const Handle owned_group(group);
        NMR::PLib3MFModelComponent* c = nullptr;
        ASSERT_EQ(NMR::lib3mf_componentsobject_addcomponent(group, tet.get(), &t, &c), LIB3MF_OK);
        NMR::lib3mf_release(c);
        ASSERT_EQ(NMR::lib3mf_model_addbuilditem(raw, group, nullptr, &item), LIB3MF_OK);
      } else {
        ASSERT_EQ(NMR::lib3mf_model_addbuilditem(raw, tet.get(), &t, &item), LIB3MF_OK);
      }
      NMR::lib3mf_release(item);
      const fs::path path = dir / "bad.3mf";
      write_model(raw, path);
      try {
        read_mesh(path);
        ADD_FAILURE() << "no exception: " << bad << " " << component;
      } catch (const ParseError& e) {
        EXPECT_NE(std::string(e.what()).find("transform holds a value that is not a finite"),
                  std::string::npos)
            << e.what();
      }
    }
  }
}

TEST(ThreeMf, AFullDiskIsAnErrorAndLeavesNoFiles) {
  // Writes past a file size limit fail as on a full disk (EFBIG, SIGXFSZ ignored): lib3mf's
  // writer threw from its destructor and aborted the process. Now: an IoError naming the
  // output, and neither the output nor a temporary left in the folder.
  const fs::path dir = test::scratch_dir() / "small";
  fs::create_directories(dir);
  const TriangleSoup sphere = rounded(test::make_sphere({0, 0, 0}, 10, 5));
  struct rlimit before {};
  ASSERT_EQ(getrlimit(RLIMIT_FSIZE, &before), 0);
  const auto old_handler = signal(SIGXFSZ, SIG_IGN);
  struct rlimit small = before;
  small.rlim_cur = 16384;
  ASSERT_EQ(setrlimit(RLIMIT_FSIZE, &small), 0);
  std::string what;
  try {
    write_mesh(dir / "out.3mf", sphere);
  } catch (const IoError& e) {
    what = e.what();
  } catch (const std::exception& e) {
    what = std::string("wrong type: ") + e.what();
  }
  setrlimit(RLIMIT_FSIZE, &before);
  signal(SIGXFSZ, old_handler);
  EXPECT_NE(what.find("cannot write " + (dir / "out.3mf").string()), std::string::npos) << what;
  EXPECT_TRUE(fs::is_empty(dir)) << fs::directory_iterator(dir)->path();
}

// A package of one model part, zipped here with its content types and relationships.
std::string zip_package(const std::string& model);

// A package written by hand: `items` build items placing one tetrahedron.
std::string package_with_items(int items) {
  std::string model =
      "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n<model unit=\"millimeter\" "
      "xmlns=\"http://schemas.microsoft.com/3dmanufacturing/core/2015/02\"><resources><object "
      "id=\"1\" type=\"model\"><mesh><vertices><vertex x=\"0\" y=\"0\" z=\"0\"/><vertex x=\"1\" "
      "y=\"0\" z=\"0\"/><vertex x=\"0\" y=\"1\" z=\"0\"/><vertex x=\"0\" y=\"0\" "
      "z=\"1\"/></vertices><triangles><triangle v1=\"0\" v2=\"2\" v3=\"1\"/><triangle v1=\"0\" "
      "v2=\"1\" v3=\"3\"/><triangle v1=\"1\" v2=\"2\" v3=\"3\"/><triangle v1=\"0\" v2=\"3\" "
      "v3=\"2\"/></triangles></mesh></object></resources><build>";
  for (int i = 0; i < items; ++i)
    model +=
        "<item objectid=\"1\" transform=\"1 0 0 0 1 0 0 0 1 " + std::to_string(2 * i) + " 0 0\"/>";
  model += "</build></model>\n";
  return zip_package(model);
}

TEST(ThreeMf, CyclicComponentsEndInARefusal) {
  // An object whose components are itself, twice: counted once each (the count neither
  // recurses forever nor doubles 64 times), then lib3mf refuses the cycle.
  const std::string model =
      "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n<model unit=\"millimeter\" "
      "xmlns=\"http://schemas.microsoft.com/3dmanufacturing/core/2015/02\"><resources><object "
      "id=\"2\" type=\"model\"><components><component objectid=\"2\"/><component "
      "objectid=\"2\"/></components></object></resources><build><item "
      "objectid=\"2\"/></build></model>\n";
  const auto start = std::chrono::steady_clock::now();
  EXPECT_THROW(parse_mesh(zip_package(model), "cycle.3mf"), Error);
  EXPECT_LT(std::chrono::steady_clock::now() - start, std::chrono::seconds(1));
}

std::string zip_package(const std::string& model) {
  const std::string types =
      "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n<Types "
      "xmlns=\"http://schemas.openxmlformats.org/package/2006/content-types\"><Default "
      "Extension=\"rels\" "
      "ContentType=\"application/vnd.openxmlformats-package.relationships+xml\"/>"
      "<Default Extension=\"model\" "
      "ContentType=\"application/vnd.ms-package.3dmanufacturing-3dmodel+xml\"/></Types>";
  const std::string rels =
      "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n<Relationships "
      "xmlns=\"http://schemas.openxmlformats.org/package/2006/relationships\"><Relationship "
      "Target=\"/3D/3dmodel.model\" Id=\"rel0\" "
      "Type=\"http://schemas.microsoft.com/3dmanufacturing/2013/01/3dmodel\"/></Relationships>";
  const fs::path path = test::scratch_dir() / "package.3mf";
  int error = 0;
  zip_t* z = zip_open(path.c_str(), ZIP_CREATE | ZIP_TRUNCATE, &error);
  EXPECT_NE(z, nullptr);
  for (const auto& [name, text] :
       {std::pair<const char*, const std::string*>{"[Content_Types].xml", &types},
        {"_rels/.rels", &rels},
        {"3D/3dmodel.model", &model}}) {
    zip_source_t* source = zip_source_buffer(z, text->data(), text->size(), 0);
    EXPECT_GE(zip_file_add(z, name, source, ZIP_FL_OVERWRITE), 0);
  }
  EXPECT_EQ(zip_close(z), 0);
  return test::read_file(path);
}

TEST(ThreeMf, ManyBuildItemsAreCountedBeforeLib3mfReadsThem) {
  // lib3mf's reading is quadratic in build items (32,768 took 17.7 s): past kMax3mfBuildItems
  // the package is refused from a count of its model part, in well under a second; a package
  // of 100 items reads as 100 tetrahedra.
  const std::string few = package_with_items(100);
  EXPECT_EQ(parse_mesh(few, "few.3mf").soup.triangles.size(), 400u);
  const std::string many = package_with_items(static_cast<int>(io::kMax3mfBuildItems) + 1);
  const auto start = std::chrono::steady_clock::now();
  try {
    parse_mesh(many, "many.3mf");
    ADD_FAILURE() << "read";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("holds more than 10000 build items"), std::string::npos)
        << e.what();
  }
  EXPECT_LT(std::chrono::steady_clock::now() - start, std::chrono::seconds(1));
}

}  // namespace
}  // namespace tpmsfill
