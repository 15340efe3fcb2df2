// tests/tools/render_png, run as a program: a sphere seen head-on must be a disc covering π/4
// of the fitted square, a cut must be exact per sample, and the PNG must decode (signature,
// IHDR, CRCs, zlib stream, row filters) with nothing but zlib.
#include <gtest/gtest.h>
#include <zlib.h>

#include <array>
#include <cstdint>
#include <filesystem>
#include <numbers>
#include <string>
#include <tpmsfill/io.hpp>
#include <vector>

#include "test_util.hpp"

using namespace tpmsfill;

namespace {

std::string render_png() {
  return TPMSFILL_RENDER_PNG;
}

using Png = test::Png;

bool background(const Png& png, int x, int y) {
  const std::uint8_t* p = png.at(x, y);
  return p[0] == 255 && p[1] == 255 && p[2] == 255;
}

/// Decodes what render_png writes (8-bit RGB); fails the test on anything else.
Png decode(const std::string& bytes) {
  return test::decode_png(bytes, 3);
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

class RenderPng : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = test::scratch_dir();
    write_mesh(dir_ / "ball.stl", test::make_sphere({1, 2, 3}, 10.0, 5));
  }
  /// Runs render_png on ball.stl with `flags`, returns its exit code; the output in *png.
  int render(const std::string& flags, Png* png, std::string* out = nullptr) {
    const std::filesystem::path file = dir_ / "ball.png";
    std::filesystem::remove(file);
    std::string text;
    const int code = test::run_command(
        render_png() + " '" + (dir_ / "ball.stl").string() + "' '" + file.string() + "' " + flags,
        &text);
    if (out) *out = text;
    if (code == 0 && png) *png = decode(test::read_file(file));
    return code;
  }
  std::filesystem::path dir_;
};

constexpr int kSize = 400;
constexpr int kMargin = 16;  // render_png's kMargin (4 %) of kSize, rounded
constexpr int kSide = kSize - 2 * kMargin;

TEST_F(RenderPng, SphereHeadOnIsADiscCoveringQuarterPiOfTheFittedSquare) {
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

TEST_F(RenderPng, ClipCutsPerSampleAndRefitsTheCamera) {
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

TEST_F(RenderPng, ElevationPastNinetyTurnsThePictureOver) {
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

TEST_F(RenderPng, InsideSeenThroughACutIsDarkerAndWarmer) {
  // From +y with the near half (y > 2) cut away, the centre shows the inside of the far half:
  // back faces, drawn in the cut's tint: darker than the outside seen head-on, and red where
  // the default colour is blue.
  Png outside, inside;
  std::string out;
  ASSERT_EQ(render("--size 200 --view 180 0", &outside, &out), 0) << out;
  ASSERT_EQ(render("--size 200 --view 180 0 --clip y 2", &inside, &out), 0) << out;
  ASSERT_EQ(inside.width, outside.width);
  ASSERT_EQ(inside.height, outside.height);
  const std::uint8_t* o = outside.at(100, 100);
  const std::uint8_t* i = inside.at(100, 100);
  EXPECT_LT(i[0] + i[1] + i[2], (o[0] + o[1] + o[2]) * 3 / 4);
  EXPECT_GT(i[0], i[2]);
  EXPECT_LT(o[0], o[2]);
}

TEST_F(RenderPng, SameInputSameBytes) {
  std::string out;
  ASSERT_EQ(render("--size 160 --color 200 100 50 --background 0 0 40", nullptr, &out), 0) << out;
  const std::string first = test::read_file(dir_ / "ball.png");
  ASSERT_EQ(render("--size 160 --color 200 100 50 --background 0 0 40", nullptr, &out), 0) << out;
  EXPECT_EQ(test::read_file(dir_ / "ball.png"), first);
  const Png png = decode(first);
  EXPECT_EQ(png.at(0, 0)[2], 40);
}

TEST_F(RenderPng, ErrorsAreOneLineAndLeaveNoFile) {
  std::string out;
  EXPECT_EQ(render("--size 10", nullptr, &out), 2) << out;
  EXPECT_EQ(render("--view 0", nullptr, &out), 2) << out;
  EXPECT_EQ(render("--clip w 0", nullptr, &out), 2) << out;
  EXPECT_EQ(render("--color 0 0 300", nullptr, &out), 2) << out;
  EXPECT_EQ(render("--no-such-flag", nullptr, &out), 2) << out;
  EXPECT_EQ(render("--clip z -100", nullptr, &out), 1) << out;
  EXPECT_NE(out.find("nothing is left"), std::string::npos) << out;
  EXPECT_EQ(std::count(out.begin(), out.end(), '\n'), 1) << out;
  EXPECT_FALSE(std::filesystem::exists(dir_ / "ball.png"));
  EXPECT_EQ(test::run_command(render_png() + " '" + (dir_ / "missing.stl").string() + "' '" +
                                  (dir_ / "x.png").string() + "'",
                              &out),
            2);
  EXPECT_EQ(std::count(out.begin(), out.end(), '\n'), 1) << out;
  EXPECT_FALSE(std::filesystem::exists(dir_ / "x.png"));
}

}  // namespace
