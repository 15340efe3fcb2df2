// Stage "render" and the commands that make pictures (render, check --picture, fill --preview).
// Geometric truths, not pixel snapshots: a sphere seen head-on is a disc covering π/4 of the
// fitted square, a cut is exact per sample, and each defect's colour is found where the
// camera (fit_camera, the renderer's own projection) puts the defect. PNGs are decoded with
// nothing but zlib (test::decode_png).
#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <numbers>
#include <string>
#include <tpmsfill/check.hpp>
#include <tpmsfill/error.hpp>
#include <tpmsfill/io.hpp>
#include <tpmsfill/render.hpp>
#include <vector>

#include "test_util.hpp"

using namespace tpmsfill;

namespace {

std::string cli() {
  return TPMSFILL_CLI;
}

using Png = test::Png;

bool background(const Png& png, int x, int y) {
  const std::uint8_t* p = png.at(x, y);
  return p[0] == 255 && p[1] == 255 && p[2] == 255;
}

struct Coverage {
  long pixels = 0;                                               ///< not background
  int min_x = 1 << 30, max_x = -1, min_y = 1 << 30, max_y = -1;  ///< their extent
};

Coverage coverage(const Png& png) {
  Coverage c;
  for (int y = 0; y < png.height; ++y)
    for (int x = 0; x < png.width; ++x)
      if (!background(png, x, y)) {
        ++c.pixels;
        c.min_x = std::min(c.min_x, x);
        c.max_x = std::max(c.max_x, x);
        c.min_y = std::min(c.min_y, y);
        c.max_y = std::max(c.max_y, y);
      }
  return c;
}

/// `tpmsfill render` on a sphere (ball.stl) into ball.png.
class RenderCli : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = test::scratch_dir();
    write_mesh(dir_ / "ball.stl", test::make_sphere({1, 2, 3}, 10.0, 5));
  }
  /// Runs render on ball.stl with `flags`, returns its exit code; the output in *png.
  int render(const std::string& flags, Png* png, std::string* out = nullptr) {
    const std::filesystem::path file = dir_ / "ball.png";
    std::filesystem::remove(file);
    std::string text;
    const int code = test::run_command(cli() + " render '" + (dir_ / "ball.stl").string() + "' '" +
                                           file.string() + "' --quiet " + flags + " 2>&1",
                                       &text);
    if (out) *out = text;
    if (code == 0 && png) *png = test::decode_png(test::read_file(file), 3);
    return code;
  }
  std::filesystem::path dir_;
};

constexpr int kSize = 400;
constexpr int kMargin = 16;  // render's margin (4 %) of kSize, rounded
constexpr int kSide = kSize - 2 * kMargin;

TEST_F(RenderCli, SphereHeadOnIsADiscCoveringQuarterPiOfTheFittedSquare) {
  Png png;
  std::string out;
  ASSERT_EQ(render("--size 400 --view 0 0", &png, &out), 0) << out;
  EXPECT_EQ(png.width, kSize);
  EXPECT_EQ(png.height, kSize);
  const Coverage c = coverage(png);
  // The icosphere's points lie on the sphere, so its silhouette spans the fitted square.
  EXPECT_NEAR(c.max_x - c.min_x + 1, kSide, 0.01 * kSide);
  EXPECT_NEAR(c.max_y - c.min_y + 1, kSide, 0.01 * kSide);
  EXPECT_NEAR(double(c.pixels) / (kSide * kSide), std::numbers::pi / 4,
              0.02 * std::numbers::pi / 4);
  // Centred: the same free border left and right, top and bottom (within a pixel).
  EXPECT_NEAR(c.min_x, kSize - 1 - c.max_x, 1);
  EXPECT_NEAR(c.min_y, kSize - 1 - c.max_y, 1);
  // Corners are background, the centre is lit (not background, not black).
  EXPECT_TRUE(background(png, 0, 0));
  EXPECT_FALSE(background(png, kSize / 2, kSize / 2));
  EXPECT_GT(png.at(kSize / 2, kSize / 2)[0], 60);
}

TEST_F(RenderCli, NamedViewsAndWidthTimesHeight) {
  // -y is azimuth 0, elevation 0; a given width and height are kept, the disc fitted into
  // the shorter side and centred.
  Png named, numbers, wide;
  std::string out;
  ASSERT_EQ(render("--size 200 --view=-y", &named, &out), 0) << out;
  ASSERT_EQ(render("--size 200 --view 0 0", &numbers, &out), 0) << out;
  EXPECT_EQ(named.pixels, numbers.pixels);
  ASSERT_EQ(render("--size 300 100 --view z", &wide, &out), 0) << out;
  EXPECT_EQ(wide.width, 300);
  EXPECT_EQ(wide.height, 100);
  const Coverage c = coverage(wide);
  EXPECT_NEAR(c.max_y - c.min_y + 1, 100 - 2 * 4, 1.5);
  EXPECT_NEAR(c.min_x, 300 - 1 - c.max_x, 1);
}

TEST_F(RenderCli, ClipCutsPerSampleAndRefitsTheCamera) {
  // The upper half cut away (z > 3, the centre's height): a half disc in a picture half as high,
  // still π/4 of the fitted rectangle.
  Png png;
  std::string out;
  ASSERT_EQ(render("--size 400 --view 0 0 --clip z 3", &png, &out), 0) << out;
  EXPECT_EQ(png.width, kSize);
  EXPECT_NEAR(png.height, kSide / 2 + 2 * kMargin, 1);
  const Coverage c = coverage(png);
  EXPECT_NEAR(c.max_x - c.min_x + 1, kSide, 0.01 * kSide);
  EXPECT_NEAR(c.max_y - c.min_y + 1, kSide / 2, 0.01 * kSide);
  EXPECT_NEAR(double(c.pixels) / (kSide * kSide / 2), std::numbers::pi / 4,
              0.02 * std::numbers::pi / 4);
}

TEST_F(RenderCli, ElevationPastNinetyTurnsThePictureOver) {
  // The lower half of the sphere: seen from -y its flat cut is the top row; from +y over the
  // top (elevation 180) the picture is upside down and the flat cut is the bottom row.
  auto widths = [](const Png& png) {  // covered pixels in the first and last covered rows
    const Coverage c = coverage(png);
    std::array<int, 2> w{0, 0};
    for (int x = 0; x < png.width; ++x) {
      w[0] += !background(png, x, c.min_y);
      w[1] += !background(png, x, c.max_y);
    }
    return w;
  };
  Png upright, over;
  std::string out;
  ASSERT_EQ(render("--size 200 --view 0 0 --clip z 3", &upright, &out), 0) << out;
  ASSERT_EQ(render("--size 200 --view 0 180 --clip z 3", &over, &out), 0) << out;
  EXPECT_GT(widths(upright)[0], 4 * widths(upright)[1]);
  EXPECT_GT(widths(over)[1], 4 * widths(over)[0]);
  EXPECT_EQ(render("--view 0 181", nullptr, &out), 2) << out;
}

TEST_F(RenderCli, InsideSeenThroughACutIsDarkerAndWarmer) {
  // From +y with the near half (y > 2) cut away, the centre shows the inside of the far half:
  // back faces, drawn in the cut's tint: darker than the outside seen head-on, and red where
  // the default colour is blue.
  Png outside, inside;
  std::string out;
  ASSERT_EQ(render("--size 200 --view 180 0", &outside, &out), 0) << out;
  ASSERT_EQ(render("--size 200 --view y --clip y 2", &inside, &out), 0) << out;
  ASSERT_EQ(inside.width, outside.width);
  ASSERT_EQ(inside.height, outside.height);
  const std::uint8_t* o = outside.at(100, 100);
  const std::uint8_t* i = inside.at(100, 100);
  EXPECT_LT(i[0] + i[1] + i[2], (o[0] + o[1] + o[2]) * 3 / 4);
  EXPECT_GT(i[0], i[2]);
  EXPECT_LT(o[0], o[2]);
}

TEST_F(RenderCli, SameInputSameBytesWhateverTheThreads) {
  std::string out;
  const std::string flags = "--size 160 --color 200 100 50 --background 0 0 40";
  ASSERT_EQ(render(flags + " --threads 1", nullptr, &out), 0) << out;
  const std::string first = test::read_file(dir_ / "ball.png");
  ASSERT_EQ(render(flags + " --threads 4", nullptr, &out), 0) << out;
  EXPECT_EQ(test::read_file(dir_ / "ball.png"), first);
  const Png png = test::decode_png(first, 3);
  EXPECT_EQ(png.at(0, 0)[2], 40);
}

TEST_F(RenderCli, ErrorsAreOneLineExitTwoAndLeaveNoFile) {
  std::string out;
  for (const char* flags : {"--size 10", "--view 0", "--view sideways", "--clip w 0",
                            "--color 0 0 300", "--no-such-flag", "--size 100 100 100"}) {
    EXPECT_EQ(render(flags, nullptr, &out), 2) << flags << ": " << out;
    EXPECT_EQ(std::count(out.begin(), out.end(), '\n'), 1) << flags << ": " << out;
  }
  EXPECT_EQ(render("--clip z -100", nullptr, &out), 2) << out;
  EXPECT_NE(out.find("nothing is left"), std::string::npos) << out;
  EXPECT_EQ(std::count(out.begin(), out.end(), '\n'), 1) << out;
  EXPECT_FALSE(std::filesystem::exists(dir_ / "ball.png"));
  // A name that is not .png, an unreadable input, an output that is the input: refused.
  const std::string ball = "'" + (dir_ / "ball.stl").string() + "' ";
  for (const std::string& args :
       {ball + "'" + (dir_ / "ball.jpg").string() + "'",
        "'" + (dir_ / "missing.stl").string() + "' '" + (dir_ / "x.png").string() + "'",
        ball + ball}) {
    EXPECT_EQ(test::run_command(cli() + " render " + args + " 2>&1", &out), 2) << out;
    EXPECT_EQ(std::count(out.begin(), out.end(), '\n'), 1) << out;
  }
  EXPECT_FALSE(std::filesystem::exists(dir_ / "ball.jpg"));
  EXPECT_FALSE(std::filesystem::exists(dir_ / "x.png"));
  EXPECT_EQ(read_mesh(dir_ / "ball.stl").triangles.size(), 20u * 4 * 4 * 4 * 4 * 4);
}

// --- the library: projection, marks, defects ----------------------------------------------

Rgb pixel_at(const Image& image, const Projection& p) {
  return image.pixel(static_cast<int>(std::floor(p.x)), static_cast<int>(std::floor(p.y)));
}

/// Marks `soup`'s defects (every location kept) and renders them; the camera in *cam.
Image defect_picture(const TriangleSoup& soup, Camera* cam, RenderOptions* used = nullptr,
                     MeshCheck* check_out = nullptr) {
  CheckOptions co;
  co.max_examples = SIZE_MAX;
  const MeshCheck check = check_mesh(soup, co);
  const RenderOptions options = mark_defects(soup, check);
  *cam = fit_camera(soup, options);
  if (used) *used = options;
  if (check_out) *check_out = check;
  return render_mesh(soup, options);
}

Vec3 lerp(const std::array<Vec3, 2>& e, double t) {
  return e[0] + t * (e[1] - e[0]);
}

TEST(Render, ProjectionPutsTheViewCentreInTheMiddle) {
  const TriangleSoup ball = test::make_sphere({1, 2, 3}, 10.0, 3);
  RenderOptions o;
  o.width = 300;
  const Camera cam = fit_camera(ball, o);
  const Projection c = cam.project({1, 2, 3});
  EXPECT_NEAR(c.x, cam.width / 2.0, 0.6);
  EXPECT_NEAR(c.y, cam.height / 2.0, 0.6);
  // z is up in the picture for an elevation below 90: a point above the centre is higher.
  EXPECT_LT(cam.project({1, 2, 13}).y, c.y);
  EXPECT_THROW(named_view("sideways"), InputError);
  o.clip = {2, -100, 0};
  EXPECT_THROW(fit_camera(ball, o), InputError);
}

TEST(Render, HoleRimIsDrawnInTheBorderColourWhereItProjects) {
  // The box lacks its +x side; the default view looks from +x, -y, +z, into the hole.
  const TriangleSoup box = test::make_box_with_hole({0, 0, 0}, {10, 10, 10});
  Camera cam;
  RenderOptions used;
  MeshCheck check;
  const Image image = defect_picture(box, &cam, &used, &check);
  const DefectColours colours;
  ASSERT_EQ(check.border_edge_examples.size(), 4u);
  for (const EdgeLocation& e : check.border_edge_examples)
    for (double t : {0.25, 0.5, 0.75})
      EXPECT_EQ(pixel_at(image, cam.project(lerp(e.ends, t))), colours.border_edge)
          << "rim point " << t << " of the edge from (" << e.ends[0].x << ", " << e.ends[0].y
          << ", " << e.ends[0].z << ")";
  // Away from the rim, the top face is plain grey (shaded: equal channels).
  const Rgb top = pixel_at(image, cam.project({4, 4, 10}));
  EXPECT_EQ(top.r, top.g);
  EXPECT_EQ(top.g, top.b);
  // The legend is a band below the picture.
  EXPECT_EQ(image.width, cam.width);
  EXPECT_GT(image.height, cam.height);
  ASSERT_FALSE(used.legend.empty());
  EXPECT_EQ(used.legend[0].text.rfind("not valid", 0), 0u) << used.legend[0].text;
}

TEST(Render, NonManifoldEdgeAndVertexGetTheirColoursAtTheirPlaces) {
  // Two cubes sharing the edge x = y = 1: four triangles on it.
  const TriangleSoup cubes =
      test::concat(test::make_box({0, 0, 0}, {1, 1, 1}), test::make_box({1, 1, 0}, {2, 2, 1}));
  Camera cam;
  MeshCheck check;
  const Image edge_image = defect_picture(cubes, &cam, nullptr, &check);
  const DefectColours colours;
  ASSERT_EQ(check.non_manifold_edges, 1u);
  for (double t : {0.3, 0.5, 0.7})
    EXPECT_EQ(pixel_at(edge_image, cam.project(lerp(check.non_manifold_edge_examples[0].ends, t))),
              colours.non_manifold_edge);

  // Two tetrahedra meeting at one apex, the origin.
  const TriangleSoup bow_tie = test::make_bow_tie();
  const Image vertex_image = defect_picture(bow_tie, &cam, nullptr, &check);
  ASSERT_EQ(check.non_manifold_vertices, 1u);
  EXPECT_EQ(pixel_at(vertex_image, cam.project({0, 0, 0})), colours.non_manifold_vertex);
}

TEST(Render, SelfIntersectingPairsAreOutlinedInTheirColour) {
  // A bar poking through the +x side of a cube: the bar's -y side crosses the cube's +x side.
  const TriangleSoup soup = test::concat(test::make_box({0, 0, 0}, {2, 2, 2}),
                                         test::make_box({1, 0.5, 0.5}, {3, 1.5, 1.5}));
  Camera cam;
  MeshCheck check;
  RenderOptions used;
  const Image image = defect_picture(soup, &cam, &used, &check);
  ASSERT_GT(check.self_intersecting_pairs.value_or(0), 0u);
  const DefectColours colours;
  // Triangle 12 + 5 = 17, the bar's -y side, holds the bar's end edge x = 3, y = 0.5.
  const bool found =
      std::any_of(check.self_intersection_examples.begin(), check.self_intersection_examples.end(),
                  [](const auto& pair) { return pair[0] == 17 || pair[1] == 17; });
  ASSERT_TRUE(found);
  EXPECT_EQ(used.face_colours[17], colours.self_intersection);
  for (double z : {0.75, 1.0, 1.25})
    EXPECT_EQ(pixel_at(image, cam.project({3, 0.5, z})), colours.self_intersection);
}

TEST(Render, FlippedTrianglesAreColouredAsFlipped) {
  // Triangle 4 of the box (its -y side, facing the default camera) turned round.
  const TriangleSoup box = test::flip(test::make_box({0, 0, 0}, {10, 10, 10}), 4);
  Camera cam;
  RenderOptions used;
  const Image image = defect_picture(box, &cam, &used);
  const DefectColours colours;
  ASSERT_EQ(used.face_colours.size(), box.triangles.size());
  for (std::size_t t = 0; t < box.triangles.size(); ++t)
    EXPECT_EQ(used.face_colours[t], t == 4 ? colours.flipped : colours.surface) << t;
  // Shaded, the flipped face keeps its hue, though it turns its back to the camera: red and
  // blue over green.
  const Rgb c = pixel_at(image, cam.project({3, 0, 3}));
  EXPECT_GT(c.r, c.g);
  EXPECT_GT(c.b, c.g);
}

TEST(Render, ValidMeshGetsAPlainPictureThatSaysSo) {
  const TriangleSoup ball = test::make_sphere({0, 0, 0}, 5.0, 3);
  CheckOptions co;
  co.max_examples = SIZE_MAX;
  const RenderOptions used = mark_defects(ball, check_mesh(ball, co));
  EXPECT_TRUE(used.face_colours.empty());
  EXPECT_TRUE(used.edges.empty());
  EXPECT_TRUE(used.points.empty());
  ASSERT_FALSE(used.legend.empty());
  EXPECT_EQ(used.legend[0].text.rfind("valid", 0), 0u);
}

TEST(Render, SameBytesWhateverTheThreadCount) {
  const TriangleSoup box = test::concat(test::make_box_with_hole({0, 0, 0}, {10, 10, 10}),
                                        test::make_sphere({5, 5, 5}, 4.0, 4));
  Camera cam;
  std::vector<std::uint8_t> one, many;
  {
    tbb::global_control serial(tbb::global_control::max_allowed_parallelism, 1);
    one = defect_picture(box, &cam).rgb;
  }
  {
    tbb::global_control parallel(tbb::global_control::max_allowed_parallelism, 4);
    many = defect_picture(box, &cam).rgb;
  }
  EXPECT_EQ(one, many);
}

// --- check --picture and fill --preview ----------------------------------------------------

TEST(CheckPicture, HoleRimIsTheBorderColourInTheWrittenPicture) {
  const auto dir = test::scratch_dir();
  write_mesh(dir / "open.stl", test::make_box_with_hole({0, 0, 0}, {10, 10, 10}));
  std::string out;
  // Not valid: exit 1, and the picture written all the same.
  ASSERT_EQ(test::run_command(cli() + " check '" + (dir / "open.stl").string() + "' --picture '" +
                                  (dir / "open.png").string() + "' 2>&1",
                              &out),
            1)
      << out;
  EXPECT_NE(out.find("picture: "), std::string::npos) << out;
  const Png png = test::decode_png(test::read_file(dir / "open.png"), 3);
  const TriangleSoup soup = read_mesh(dir / "open.stl");
  const Camera cam = fit_camera(soup, RenderOptions{});
  EXPECT_EQ(std::max(cam.width, cam.height), 640);
  EXPECT_EQ(png.width, cam.width);
  EXPECT_GT(png.height, cam.height);  // the legend's band
  const DefectColours colours;
  const std::array<Vec3, 4> rim_midpoints{Vec3{10, 0, 5}, Vec3{10, 10, 5}, Vec3{10, 5, 0},
                                          Vec3{10, 5, 10}};
  for (const Vec3& p : rim_midpoints) {
    const Projection q = cam.project(p);
    const std::uint8_t* px = png.at(static_cast<int>(q.x), static_cast<int>(q.y));
    EXPECT_EQ((Rgb{px[0], px[1], px[2]}), colours.border_edge) << p.x << " " << p.y << " " << p.z;
  }
  // --json keeps stdout one JSON object; the examples stay --max-examples.
  ASSERT_EQ(test::run_command(cli() + " check '" + (dir / "open.stl").string() +
                                  "' --json --max-examples 1 --picture '" +
                                  (dir / "open2.png").string() + "'",
                              &out),
            1);
  EXPECT_EQ(out.front(), '{') << out;
  EXPECT_EQ(out.find("picture"), std::string::npos) << out;
  EXPECT_TRUE(std::filesystem::exists(dir / "open2.png"));
}

TEST(CheckPicture, BadNameIsRefusedBeforeTheWork) {
  const auto dir = test::scratch_dir();
  write_mesh(dir / "box.stl", test::make_box({0, 0, 0}, {1, 1, 1}));
  std::string out;
  EXPECT_EQ(test::run_command(cli() + " check '" + (dir / "box.stl").string() + "' --picture '" +
                                  (dir / "box.ppm").string() + "' 2>&1",
                              &out),
            2)
      << out;
  EXPECT_NE(out.find(".png"), std::string::npos) << out;
  EXPECT_FALSE(std::filesystem::exists(dir / "box.ppm"));
}

TEST(FillPreview, WritesAPictureThatDecodesBesideTheMesh) {
  const auto dir = test::scratch_dir();
  write_mesh(dir / "cube.stl", test::make_box({0, 0, 0}, {10, 10, 10}));
  const std::string fill = cli() + " fill '" + (dir / "cube.stl").string() + "' '" +
                           (dir / "lattice.stl").string() + "' --cell 5 --voxel 0.5 --quiet";
  std::string out;
  ASSERT_EQ(
      test::run_command(fill + " --preview '" + (dir / "preview.png").string() + "' 2>&1", &out), 0)
      << out;
  const Png png = test::decode_png(test::read_file(dir / "preview.png"), 3);
  EXPECT_EQ(std::max(png.width, png.height), 640);
  EXPECT_GT(coverage(png).pixels, 640 * 100);
  // A picture name that is not .png: refused before the work, neither file written.
  EXPECT_EQ(test::run_command(fill + " --preview '" + (dir / "p.jpg").string() + "' 2>&1", &out), 2)
      << out;
  EXPECT_FALSE(std::filesystem::exists(dir / "p.jpg"));
  std::filesystem::remove(dir / "lattice.stl");
  EXPECT_EQ(test::run_command(fill + " --preview '" + (dir / "p.jpg").string() + "' 2>&1", &out),
            2);
  EXPECT_FALSE(std::filesystem::exists(dir / "lattice.stl"));
}

}  // namespace

// The picture is framed on the mesh's outline, not on its box's projected corners: in the
// default three-quarter view a long bar and a ball reach the margin on both sides of the
// longer axis and leave the same border on both sides of the other (25 to 45 % of the frame
// used to stay empty).
TEST(Render, ObliqueViewsFrameTheOutline) {
  for (const TriangleSoup& mesh :
       {test::make_box({0, 0, 0}, {60, 8, 8}), test::make_sphere({5, -3, 2}, 10, 4),
        test::make_torus(10, 3, 64, 32)}) {
    RenderOptions o;
    o.width = 400;
    const Image image = render_mesh(mesh, o);
    const Rgb bg = image.pixel(0, 0);
    int min_x = image.width, max_x = -1, min_y = image.height, max_y = -1;
    for (int y = 0; y < image.height; ++y)
      for (int x = 0; x < image.width; ++x)
        if (!(image.pixel(x, y) == bg)) {
          min_x = std::min(min_x, x), max_x = std::max(max_x, x);
          min_y = std::min(min_y, y), max_y = std::max(max_y, y);
        }
    const int margin = 16;  // 4 % of 400
    const bool wide = image.width >= image.height;
    const int used = wide ? max_x - min_x + 1 : max_y - min_y + 1;
    EXPECT_NEAR(used, 400 - 2 * margin, 3) << "the longer side spans the frame";
    EXPECT_NEAR(min_x, image.width - 1 - max_x, 2) << "centred across";
    EXPECT_NEAR(min_y, image.height - 1 - max_y, 2) << "centred up and down";
    const int other = wide ? max_y - min_y + 1 : max_x - min_x + 1;
    EXPECT_NEAR(other, (wide ? image.height : image.width) - 2 * margin, 3)
        << "the shorter side is cut to fit";
  }
}

// The picture's legend says what check's text says: an open mesh turned inside out is flipped
// "once its holes are capped" (check cannot call an open mesh inside out, and the picture
// marked all its faces flipped without saying why), and holes that open only where
// non-manifold edges are split are said to be so ("0 border edges, 6 holes" read as a
// contradiction).
TEST(CheckPicture, LegendSaysWhyFacesAreFlippedAndWhereHolesAre) {
  const TriangleSoup open_inward = test::flip(test::make_box_with_hole({0, 0, 0}, {10, 10, 10}));
  const MeshCheck c = check_mesh(open_inward);
  ASSERT_FALSE(c.closed());
  ASSERT_FALSE(c.outward);
  std::string legend;
  for (const LegendEntry& e : mark_defects(open_inward, c, {}).legend) legend += e.text + "\n";
  EXPECT_NE(legend.find("flipped triangles: 10 (1 piece facing inward once its holes are capped)"),
            std::string::npos)
      << legend;
  // assimp's 3DSMaxExport.STL: closed, 16 non-manifold edges, 6 holes once they are split.
  const std::filesystem::path max_export =
      std::filesystem::path(TPMSFILL_ASSIMP_MODELS) / "STL" / "3DSMaxExport.STL";
  if (!std::filesystem::exists(max_export)) GTEST_SKIP() << max_export << ": assimp-testmodels";
  const TriangleSoup split = read_mesh(max_export);
  const MeshCheck t = check_mesh(split);
  ASSERT_TRUE(t.closed());
  ASSERT_GT(t.holes, 0u);
  legend.clear();
  for (const LegendEntry& e : mark_defects(split, t, {}).legend) legend += e.text + "\n";
  EXPECT_NE(legend.find("border edges: 0; " + std::to_string(t.holes.value_or(0)) +
                        " holes once its non-manifold edges are split"),
            std::string::npos)
      << legend;
}
