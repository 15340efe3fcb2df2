// Stage "cube map" (cube_map.hpp): the box maps affinely, a ball and a warped box map without
// flips, and meshes the cube cannot take are refused with a sentence.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <random>
#include <set>
#include <tpmsfill/error.hpp>
#include <tpmsfill/io.hpp>
#include <tpmsfill/solid/cube_map.hpp>
#include <tpmsfill/solid/tetrahedralize.hpp>

#include "solid/internal/untangle.hpp"
#include "test_util.hpp"

namespace tpmsfill {
namespace {

using test::make_tet_grid;

// The point ids of the box's corners, corner k at (k & 1, k >> 1 & 1, k >> 2 & 1) of the box.
std::array<std::uint32_t, 8> box_corners(const TetMesh& mesh, Vec3 min, Vec3 max) {
  std::array<std::uint32_t, 8> corners{};
  for (int k = 0; k < 8; ++k) {
    const Vec3 at{k & 1 ? max.x : min.x, k & 2 ? max.y : min.y, k & 4 ? max.z : min.z};
    for (std::uint32_t v = 0; v < mesh.points.size(); ++v)
      if (mesh.points[v] == at) corners[k] = v;
  }
  return corners;
}

void expect_affine_image(const TetMesh& mesh, const CubeMap& map, Vec3 min, Vec3 max) {
  const Vec3 size = max - min;
  double worst = 0;
  for (std::size_t v = 0; v < mesh.points.size(); ++v)
    for (int a = 0; a < 3; ++a)
      worst = std::max(worst, std::abs(map.uvw[v][a] - (mesh.points[v][a] - min[a]) / size[a]));
  EXPECT_LT(worst, 1e-12);
}

TEST(CubeMap, CubeEdgesJoinCornersThatDifferInTheirAxis) {
  std::set<std::pair<int, int>> seen;
  for (int e = 0; e < 12; ++e) {
    const auto [a, b] = cube_edge_corners(e);
    EXPECT_EQ(b - a, 1 << (e / 4)) << "edge " << e;
    EXPECT_EQ(a & (1 << (e / 4)), 0);
    seen.insert({a, b});
  }
  EXPECT_EQ(seen.size(), 12u);
}

TEST(CubeMap, BoxMapsToItsAffineImage) {
  const Vec3 min{-1, 2, 0.5}, max{3, 3, 2};
  const TetMesh box = make_tet_grid(min, max, {6, 4, 5}, 0.12);
  const CubeMap map = map_to_cube(box);  // corners found: the box's corners
  EXPECT_EQ(map.corners, box_corners(box, min, max));
  expect_affine_image(box, map, min, max);
  EXPECT_EQ(map.flipped_boundary_faces, 0u);
  EXPECT_EQ(map.inverted_tets, 0u);
  EXPECT_EQ(map.flat_tets, 0u);
  EXPECT_EQ(map.tets, box.tets.size());
  EXPECT_EQ(map.interior_points, 5u * 3 * 4);
  // Faces u = 0 and u = 1 hold 4 × 5 squares of two triangles each, and so on.
  EXPECT_EQ(map.patch_faces, (std::array<std::uint64_t, 6>{40, 40, 60, 60, 48, 48}));
  for (int e = 0; e < 12; ++e) EXPECT_EQ(map.curves[e].size(), (e < 4 ? 6u : e < 8 ? 4u : 5u) + 1);
}

TEST(CubeMap, GivenCornersAreUsed) {
  const Vec3 min{0, 0, 0}, max{2, 1, 1};
  const TetMesh box = make_tet_grid(min, max, {4, 2, 2}, 0.1);
  const CubeMap map = map_to_cube(box, {.corners = box_corners(box, min, max)});
  expect_affine_image(box, map, min, max);
}

TEST(CubeMap, TiltedBoxMapsAffinelyByItsPrincipalAxes) {
  // Tilted, the box's corners are not the extremes towards its bounding box's corners (with
  // only those the stage refuses); its principal axes are its own edges.
  TetMesh box = make_tet_grid({-2, -1, -0.5}, {2, 1, 0.5}, {8, 4, 3}, 0.1);
  const double a = 0.5, b = 0.3;
  for (Vec3& p : box.points) {
    const Vec3 q{std::cos(a) * p.x - std::sin(a) * p.y, std::sin(a) * p.x + std::cos(a) * p.y, p.z};
    p = {q.x, std::cos(b) * q.y - std::sin(b) * q.z, std::sin(b) * q.y + std::cos(b) * q.z};
  }
  const CubeMap map = map_to_cube(box);
  EXPECT_EQ(map.flipped_boundary_faces, 0u);
  EXPECT_EQ(map.inverted_tets, 0u);
  // (u, v, w) is the affine map that takes corners 0, 1, 2, 4 to the cube's.
  const Vec3 o = box.points[map.corners[0]];
  const Vec3 e[3] = {box.points[map.corners[1]] - o, box.points[map.corners[2]] - o,
                     box.points[map.corners[4]] - o};
  const double det = dot(e[0], cross(e[1], e[2]));
  ASSERT_GT(det, 0);
  double worst = 0;
  for (std::size_t v = 0; v < box.points.size(); ++v) {
    const Vec3 d = box.points[v] - o;
    const double uvw[3] = {dot(d, cross(e[1], e[2])) / det, dot(e[0], cross(d, e[2])) / det,
                           dot(e[0], cross(e[1], d)) / det};
    for (int k = 0; k < 3; ++k) worst = std::max(worst, std::abs(map.uvw[v][k] - uvw[k]));
  }
  EXPECT_LT(worst, 1e-9);
}

TEST(CubeMap, MirroredCornersAreRefused) {
  const Vec3 min{0, 0, 0}, max{1, 1, 1};
  const TetMesh box = make_tet_grid(min, max, {3, 3, 3});
  auto corners = box_corners(box, min, max);
  for (int k = 0; k < 8; k += 2) std::swap(corners[k], corners[k + 1]);  // x mirrored
  try {
    map_to_cube(box, {.corners = corners});
    FAIL() << "mirrored corners were accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("mirrored"), std::string::npos) << e.what();
  }
}

TEST(CubeMap, BadCornersAreRefused) {
  const TetMesh box = make_tet_grid({0, 0, 0}, {1, 1, 1}, {2, 2, 2});
  std::array<std::uint32_t, 8> corners = box_corners(box, {0, 0, 0}, {1, 1, 1});
  auto refused = [&](std::array<std::uint32_t, 8> c, const std::string& words) {
    try {
      map_to_cube(box, {.corners = c});
      ADD_FAILURE() << "accepted";
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find(words), std::string::npos) << e.what();
    }
  };
  auto inner = corners;
  for (std::uint32_t v = 0; v < box.points.size(); ++v)
    if (box.points[v] == Vec3{0.5, 0.5, 0.5}) inner[3] = v;  // the centre, inside
  ASSERT_NE(inner[3], corners[3]);
  refused(inner, "not a vertex of the boundary");
  auto twice = corners;
  twice[5] = twice[4];
  refused(twice, "same vertex");
  auto outside = corners;
  outside[0] = 1000;
  refused(outside, "not a vertex of the boundary");
}

// The cube [-1, 1]³ onto the ball, smoothly (the elliptical grid map): corners to the
// diagonals, faces to the sphere.
Vec3 cube_to_ball(Vec3 p) {
  const double x2 = p.x * p.x, y2 = p.y * p.y, z2 = p.z * p.z;
  return {p.x * std::sqrt(1 - y2 / 2 - z2 / 2 + y2 * z2 / 3),
          p.y * std::sqrt(1 - z2 / 2 - x2 / 2 + z2 * x2 / 3),
          p.z * std::sqrt(1 - x2 / 2 - y2 / 2 + x2 * y2 / 3)};
}

TEST(CubeMap, BallMapsWithoutFlips) {
  TetMesh ball = make_tet_grid({-1, -1, -1}, {1, 1, 1}, {8, 8, 8}, 0.1);
  for (Vec3& p : ball.points) p = cube_to_ball(p);
  ASSERT_FALSE(ball_problem(check_tet_mesh(ball))) << *ball_problem(check_tet_mesh(ball));
  const CubeMap map = map_to_cube(ball);
  EXPECT_EQ(map.flipped_boundary_faces, 0u);
  EXPECT_EQ(map.inverted_tets, 0u);
  EXPECT_EQ(map.flat_tets, 0u);
  for (const auto& p : map.uvw)
    for (double c : p) {
      EXPECT_GE(c, 0);
      EXPECT_LE(c, 1);
    }
  // By symmetry each corner is the sphere's point on a diagonal, and every face holds a sixth.
  for (int k = 0; k < 8; ++k) {
    const Vec3 p = ball.points[map.corners[k]];
    EXPECT_NEAR(std::abs(p.x), 1 / std::sqrt(3.0), 1e-12);
    EXPECT_NEAR(std::abs(p.y), std::abs(p.z), 1e-12);
  }
  for (std::uint64_t faces : map.patch_faces) EXPECT_EQ(faces, map.boundary_faces / 6);
}

TEST(CubeMap, WarpedBoxKeepsItsCornersOnTheCube) {
  TetMesh blob = make_tet_grid({0, 0, 0}, {2, 1, 1}, {10, 5, 5}, 0.1);
  for (Vec3& p : blob.points)
    p = Vec3{p.x + 0.2 * std::sin(3 * p.y), p.y + 0.15 * std::sin(2 * p.z + p.x),
             p.z * (1 + 0.3 * p.x)};
  const auto report = check_tet_mesh(blob);
  ASSERT_FALSE(ball_problem(report)) << *ball_problem(report);
  const CubeMap map = map_to_cube(blob);
  EXPECT_EQ(map.flipped_boundary_faces, 0u);
  EXPECT_EQ(map.inverted_tets, 0u);
  EXPECT_EQ(map.flat_tets, 0u);
  for (int k = 0; k < 8; ++k)
    for (int a = 0; a < 3; ++a) EXPECT_EQ(map.uvw[map.corners[k]][a], (k >> a) & 1);
}

TEST(CubeMap, NonBallsAreRefusedWithTheCheckSentence) {
  const TetMesh ring = make_tet_grid({0, 0, 0}, {3, 3, 1}, {3, 3, 1}, 0,
                                     [](int i, int j, int) { return !(i == 1 && j == 1); });
  try {
    map_to_cube(ring);
    FAIL() << "a ring was accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("genus 1"), std::string::npos) << e.what();
  }
  TetMesh box = make_tet_grid({0, 0, 0}, {1, 1, 1}, {2, 2, 2});
  for (Tet& t : box.tets) std::swap(t[0], t[1]);
  EXPECT_THROW(map_to_cube(box), InputError);
  EXPECT_NO_THROW(map_to_cube(with_positive_tets(box, check_tet_mesh(box))));
}

TEST(CubeMap, ThinSlabCornersCoincideAndAreRefused) {
  // One cube thick along z, a single vertex per corner column: still eight distinct corners.
  const TetMesh slab = make_tet_grid({0, 0, 0}, {4, 4, 0.1}, {4, 4, 1});
  EXPECT_NO_THROW(map_to_cube(slab));
  // A tet alone has four vertices: two corners must coincide.
  TetMesh tet;
  tet.points = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  tet.tets = {{0, 1, 2, 3}};
  try {
    map_to_cube(tet);
    FAIL() << "a single tet was accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("give the eight corner"), std::string::npos) << e.what();
  }
}

// An ordinary closed genus-0 scan with limbs (libcgal-demo's triceratops: horns, tail, legs):
// the corners of the boxes along its axes and principal axes give curves that cannot cut its
// boundary as the cube's edges do; a box turned by 45° gives corners that can, with no point
// ids asked of the user.
TEST(CubeMap, LimbedScanFindsItsOwnCorners) {
  const TriangleSoup surface =
      read_mesh(std::filesystem::path(TPMSFILL_CGAL_MESHES) / "triceratops.off");
  Vec3 lo = surface.points[0], hi = lo;
  for (const Vec3& p : surface.points) {
    lo = {std::min(lo.x, p.x), std::min(lo.y, p.y), std::min(lo.z, p.z)};
    hi = {std::max(hi.x, p.x), std::max(hi.y, p.y), std::max(hi.z, p.z)};
  }
  // Organic: no sharp edges kept (as `material` does by default; at 60° Mesh_3 stops on this
  // one, Tetrahedralize.MesherFailureIsARefusalWithoutLeftovers).
  const TetMesh tets =
      tetrahedralize(surface, {.cell_size = norm(hi - lo) / 30, .feature_angle = 180});
  const CubeMap map = map_to_cube(tets);
  std::set<std::uint32_t> corners(map.corners.begin(), map.corners.end());
  EXPECT_EQ(corners.size(), 8u);
  std::size_t mapped = 0;
  for (const auto& uvw : map.uvw) mapped += !std::isnan(uvw[0]);
  EXPECT_EQ(mapped, tets.points.size());
  // Each patch is a disk on a convex square: Floater's map of it does not flip.
  EXPECT_EQ(map.flipped_boundary_faces, 0u);
}

double image_volume(const Tet& t, const std::vector<std::array<double, 3>>& uvw) {
  auto at = [&](int k) { return Vec3{uvw[t[k]][0], uvw[t[k]][1], uvw[t[k]][2]}; };
  return dot(at(1) - at(0), cross(at(2) - at(0), at(3) - at(0))) / 6;
}

// A grid whose interior points are thrown about by up to 1.8 cells (hundreds of tets inverted):
// untangled, every tet is positive, and the points not free have not moved.
TEST(CubeMap, UntangleMendsAScrambledGridMovingOnlyItsFreePoints) {
  const TetMesh grid = make_tet_grid({0, 0, 0}, {1, 1, 1}, {6, 6, 6});
  std::vector<std::array<double, 3>> uvw(grid.points.size());
  std::vector<char> movable(grid.points.size(), 0);
  std::mt19937 random(7);
  std::uniform_real_distribution<double> offset(-0.3, 0.3);
  for (std::size_t v = 0; v < grid.points.size(); ++v) {
    const Vec3 p = grid.points[v];
    uvw[v] = {p.x, p.y, p.z};
    movable[v] = p.x > 0 && p.x < 1 && p.y > 0 && p.y < 1 && p.z > 0 && p.z < 1;
    if (movable[v])
      for (double& c : uvw[v]) c += offset(random);
  }
  std::size_t inverted = 0;
  for (const Tet& t : grid.tets) inverted += image_volume(t, uvw) <= 0;
  ASSERT_GT(inverted, 100u);
  CubeMap map;  // folded_tets() names the same tets
  map.uvw = uvw;
  EXPECT_EQ(folded_tets(grid, map).size(), inverted);
  const auto start = uvw;
  // A schedule cut to one value of ε and one step stops there with folds left, as a large
  // mesh's whole interior can use up the paper's 100 values (docs/method.md, seed 001 step 4);
  // the paper's schedule opens them all.
  auto cut = uvw;
  const detail::UntangleResult short_run =
      detail::untangle(grid, movable, cut, {}, {.max_rounds = 1, .max_steps = 1});
  EXPECT_EQ(short_run.rounds, 1);
  EXPECT_LT(short_run.min_det_after, 0);
  const detail::UntangleResult r = detail::untangle(grid, movable, uvw);
  EXPECT_GT(r.min_det_after, 0);
  inverted = 0;
  for (const Tet& t : grid.tets) inverted += image_volume(t, uvw) <= 0;
  EXPECT_EQ(inverted, 0u);
  map.uvw = uvw;
  EXPECT_TRUE(folded_tets(grid, map).empty());
  for (std::size_t v = 0; v < grid.points.size(); ++v) {
    if (!movable[v]) {
      EXPECT_EQ(uvw[v], start[v]);
    }
  }
}

// A map folded in one spot (an interior point pushed past its neighbours, as untangling can
// leave a large mesh when its schedule runs out): with_folds_opened() opens it by moving only
// interior points near the fold. A fold no interior point touches (two boundary points'
// images swapped) cannot open: the map comes back as it was, never worse.
TEST(CubeMap, FoldsOpenLocallyAndTheBoundaryStays) {
  const TetMesh grid = make_tet_grid({0, 0, 0}, {1, 1, 1}, {8, 8, 8});
  CubeMap identity;
  for (const Vec3& p : grid.points) identity.uvw.push_back({p.x, p.y, p.z});
  EXPECT_EQ(with_folds_opened(grid, identity).uvw, identity.uvw);  // nothing folded

  CubeMap pushed = identity;
  std::uint32_t centre = 0;
  for (std::uint32_t v = 0; v < grid.points.size(); ++v)
    if (grid.points[v] == Vec3{0.5, 0.5, 0.5}) centre = v;
  pushed.uvw[centre][0] += 0.2;  // past the next point along x, 0.125 away
  const std::size_t folded = folded_tets(grid, pushed).size();
  ASSERT_GT(folded, 0u);
  const CubeMap opened = with_folds_opened(grid, pushed);
  EXPECT_TRUE(folded_tets(grid, opened).empty());
  EXPECT_EQ(opened.inverted_tets + opened.flat_tets, 0u);
  EXPECT_GT(opened.opened_points, 0u);
  std::size_t moved = 0;
  for (std::uint32_t v = 0; v < grid.points.size(); ++v) {
    const Vec3 p = grid.points[v];
    if (opened.uvw[v] == pushed.uvw[v]) continue;
    ++moved;
    // Within 4 rings of the folded tets, whose corners are a cell from the centre at most.
    const Vec3 d = p - Vec3{0.5, 0.5, 0.5};
    EXPECT_LE(std::max({std::abs(d.x), std::abs(d.y), std::abs(d.z)}), 5 * 0.125 + 1e-12);
    EXPECT_TRUE(p.x > 0 && p.x < 1 && p.y > 0 && p.y < 1 && p.z > 0 && p.z < 1);
  }
  EXPECT_EQ(moved, opened.opened_points);

  CubeMap swapped = identity;  // two boundary points on the face z = 0 trade places
  std::uint32_t a = 0, b = 0;
  for (std::uint32_t v = 0; v < grid.points.size(); ++v) {
    if (grid.points[v] == Vec3{0.5, 0.5, 0}) a = v;
    if (grid.points[v] == Vec3{0.625, 0.5, 0}) b = v;
  }
  std::swap(swapped.uvw[a], swapped.uvw[b]);
  const std::size_t stuck = folded_tets(grid, swapped).size();
  ASSERT_GT(stuck, 0u);
  const CubeMap kept = with_folds_opened(grid, swapped);
  EXPECT_LE(folded_tets(grid, kept).size(), stuck);
  EXPECT_EQ(kept.uvw[a], swapped.uvw[a]);
  EXPECT_EQ(kept.uvw[b], swapped.uvw[b]);
}

// Ordinary scans, tetrahedralized as `material` does: Mesh_3 leaves chords whose two ends land
// on one cube face (flat tets no interior point can mend), and the harmonic interior inverts
// tets where limbs squeeze into thin slabs. With the chords split and the folds untangled,
// bear's every tet image is positive: with the boundary on the cube's faces unflipped, the
// map is a bijection onto the cube, and most of the interior keeps its harmonic place.
// Triceratops's legs and horns are protrusions of their patches, which Floater's maps crowd:
// those patches relaxed, its map is fold-free too (before: 153 of 11,669 tets left inverted).
TEST(CubeMap, ScansMapWithoutFoldsOnceTheirChordsAreSplit) {
  for (const char* name : {"bear.off", "triceratops.off"}) {
    SCOPED_TRACE(name);
    const bool bear = name == std::string("bear.off");
    const TriangleSoup surface = read_mesh(std::filesystem::path(TPMSFILL_CGAL_MESHES) / name);
    Box3 box;
    for (const Vec3& p : surface.points) box.extend(p);
    const TetMesh tets =
        tetrahedralize(surface, {.cell_size = norm(box.size()) / 30, .feature_angle = 180});
    EXPECT_GT(map_to_cube(tets).flat_tets, 0u);
    const TetMesh split = with_chords_split(tets);
    const CubeMap map = map_to_cube(split);
    EXPECT_GT(map.harmonic_inverted_tets, 0u);  // there was something to untangle
    EXPECT_EQ(map.flipped_boundary_faces, 0u);
    EXPECT_EQ(map.flat_tets, 0u);
    EXPECT_EQ(map.relaxed_patches > 0, !bear);
    EXPECT_EQ(map.inverted_tets, 0u);
    double smallest = HUGE_VAL;
    for (const Tet& t : split.tets) smallest = std::min(smallest, image_volume(t, map.uvw));
    EXPECT_GT(smallest, 0);
    for (const auto& p : map.uvw)
      for (double c : p) {
        EXPECT_GE(c, 0);
        EXPECT_LE(c, 1);
      }
    if (bear) {
      EXPECT_LT(2 * map.untangled_points, map.interior_points);
    }
  }
}

// The least share of the face any boundary triangle's image holds, over its share of the
// boundary's area (1: areas kept; Floater's map of a protrusion gives 10⁻¹⁰ and less).
double least_image_share(const TetMesh& mesh, const CubeMap& map) {
  const std::vector<Triangle> faces = tet_boundary(mesh).triangles;
  double area = 0;
  for (const Triangle& t : faces)
    area +=
        norm(cross(mesh.points[t[1]] - mesh.points[t[0]], mesh.points[t[2]] - mesh.points[t[0]]));
  auto at = [&](std::uint32_t v) { return Vec3{map.uvw[v][0], map.uvw[v][1], map.uvw[v][2]}; };
  double least = HUGE_VAL;
  for (const Triangle& t : faces) {
    const double share =
        norm(cross(mesh.points[t[1]] - mesh.points[t[0]], mesh.points[t[2]] - mesh.points[t[0]])) /
        area;
    // Each face of the cube holds 1/6 of its area.
    least = std::min(least, norm(cross(at(t[1]) - at(t[0]), at(t[2]) - at(t[0]))) / 6 / share);
  }
  return least;
}

// A slab with a tall post, its corners the slab's: the post is a protrusion of the top patch,
// which Floater's map squeezes exponentially with its height. The crowded patch is relaxed: no
// image flipped, every triangle's image a fair share of its face, and no tet inverted.
TEST(CubeMap, CrowdedPatchesAreRelaxed) {
  const TetMesh post = with_chords_split(make_tet_grid(
      {0, 0, 0}, {6, 6, 12}, {6, 6, 12}, 0,
      [](int i, int j, int k) { return k < 2 || (i >= 2 && i < 4 && j >= 2 && j < 4); }));
  const CubeMap map = map_to_cube(post, {.corners = box_corners(post, {0, 0, 0}, {6, 6, 2})});
  EXPECT_GE(map.relaxed_patches, 1u);
  EXPECT_EQ(map.flipped_boundary_faces, 0u);
  EXPECT_EQ(map.inverted_tets, 0u);
  EXPECT_EQ(map.flat_tets, 0u);
  EXPECT_GT(least_image_share(post, map), 1e-2);
}

// In the plane: a grid whose inside points crowd into one corner (u⁸, v⁸ inside, the border
// kept: the least image 3.5·10⁻¹⁵ of its share) is spread by the Newton steps to a fair share
// everywhere, every triangle counter-clockwise, the border where it was.
TEST(CubeMap, UntangleTrianglesSpreadsACrowdedGrid) {
  constexpr int n = 16;
  std::vector<Vec3> points;
  std::vector<std::array<double, 2>> uv;
  std::vector<char> movable;
  for (int j = 0; j <= n; ++j)
    for (int i = 0; i <= n; ++i) {
      const double x = double(i) / n, y = double(j) / n;
      points.push_back({x, y, 0});
      movable.push_back(i > 0 && i < n && j > 0 && j < n);
      uv.push_back(movable.back() ? std::array<double, 2>{std::pow(x, 8), std::pow(y, 8)}
                                  : std::array<double, 2>{x, y});
    }
  std::vector<Triangle> triangles;
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      const auto v = [&](int a, int b) { return std::uint32_t((j + b) * (n + 1) + i + a); };
      triangles.push_back({v(0, 0), v(1, 0), v(1, 1)});
      triangles.push_back({v(0, 0), v(1, 1), v(0, 1)});
    }
  auto least_share = [&] {
    double least = HUGE_VAL;
    for (const Triangle& t : triangles) {
      const auto &a = uv[t[0]], &b = uv[t[1]], &c = uv[t[2]];
      const double image = 0.5 * ((b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]));
      least = std::min(least, image * 2 * n * n);  // each triangle's share: 1 / (2 n²)
    }
    return least;
  };
  ASSERT_LT(least_share(), 1e-12);
  ASSERT_GT(least_share(), 0);
  const auto start = uv;
  const detail::UntangleResult r = detail::untangle_triangles(points, triangles, movable, 0.5, uv);
  EXPECT_GT(r.min_det_after, 0);
  EXPECT_GT(least_share(), 0.3);
  for (std::size_t v = 0; v < uv.size(); ++v)
    if (!movable[v]) {
      EXPECT_EQ(uv[v], start[v]);
    }
}

}  // namespace
}  // namespace tpmsfill
