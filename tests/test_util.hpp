// Meshes made in code and small helpers shared by the test files.
#pragma once

#include <array>
#include <chrono>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <string>
#include <tpmsfill/field.hpp>
#include <tpmsfill/fill.hpp>
#include <tpmsfill/lattice/design.hpp>
#include <tpmsfill/solid/tet_mesh.hpp>
#include <tpmsfill/types.hpp>
#include <vector>

namespace tpmsfill::test {

/// The tests' pseudo-random numbers (a 64-bit LCG): the same sequence on every machine.
struct Random {
  std::uint64_t state;
  double next() {  // in [0, 1)
    state = state * 6364136223846793005ULL + 1442695040888963407ULL;
    return static_cast<double>(state >> 11) / static_cast<double>(1ULL << 53);
  }
  std::array<double, 3> point(double scale = 1) {
    return {scale * next(), scale * next(), scale * next()};
  }
};

/// Every TPMS type, in the order of the table in docs/method.md (for loops).
inline constexpr TpmsType kAllTpmsTypes[] = {
    TpmsType::Primitive, TpmsType::Gyroid, TpmsType::Diamond,  TpmsType::Iwp,
    TpmsType::Neovius,   TpmsType::Frd,    TpmsType::Lidinoid, TpmsType::SplitP};
/// φ at one point of a TPMS or a design: field_value() of its source.
float tpms_value(Vec3 p, const TpmsOptions& options);
float design_value(Vec3 p, const LatticeDesign& design);

/// Axis-aligned box, 8 points, 12 triangles, outward.
TriangleSoup make_box(Vec3 min, Vec3 max);
/// Icosphere: icosahedron subdivided `levels` times, projected on the sphere; outward, genus 0.
TriangleSoup make_sphere(Vec3 center, double radius, int levels);
/// Torus around the z axis (major radius R, minor radius r), nu x nv quads split; genus 1.
TriangleSoup make_torus(double R, double r, int nu, int nv);
/// Thin-walled tube around the z axis from z = 0 to z = height: outer and inner walls with
/// `segments` quads around and rings − 1 bands up, plus the two annuli; outward, genus 1.
/// 2,048 segments and 573 rings give the benchmark's 4.7 million triangles.
TriangleSoup make_tube(double outer_radius, double inner_radius, double height, int segments,
                       int rings);
/// make_box without the two triangles of its +x side: one hole of four border edges.
TriangleSoup make_box_with_hole(Vec3 min, Vec3 max);
/// A box of cells[0] × cells[1] × cells[2] cubes, each split into 6 positive tets (Kuhn), with
/// `keep(i, j, k)` choosing the cubes (all when empty: holes, cavities, pieces otherwise).
/// `jitter` moves each vertex by up to that share of a cube, pseudo-randomly, along the axes on
/// which it is not on the box's side: face vertices stay on their face, edge vertices on their
/// edge, corners fixed, so the boundary is still the box. No material.
TetMesh make_tet_grid(Vec3 min, Vec3 max, std::array<int, 3> cells, double jitter = 0,
                      const std::function<bool(int, int, int)>& keep = {});
/// The area of a tet mesh's cross-section by the plane at height z, mm²: each tet's section
/// (a triangle or a convex quad) by the shoelace rule.
double tet_section_area(const TetMesh& mesh, double z);
/// The area of a closed, outward surface's cross-section at height z, mm²: the segments where
/// its triangles cross the plane, each oriented with the solid on its left (its triangle's
/// outward normal on its right), summed by the shoelace rule.
double section_area(const TriangleSoup& mesh, double z);
/// Two tetrahedra sharing one apex: closed, but the shared vertex is pinched (non-manifold).
TriangleSoup make_bow_tie();
/// Open surfaces (seed 004's layouts): an n × n grid of squares over [0, L]² lifted by z(x, y),
/// counter-clockwise seen from +z (a disk);
TriangleSoup make_height_field(int n, double L, const std::function<double(double, double)>& z);
/// a spherical cap of radius R around +z up to polar angle `angle` (π/2: a hemisphere), rings of
/// latitude from the pole, normals outward (a disk);
TriangleSoup make_spherical_cap(double R, double angle, int rings, int segments);
/// an open cylinder of radius R from z = 0 to H, normals outward (a tube: two loops).
TriangleSoup make_open_cylinder(double R, double H, int segments, int rows);

/// Both soups in one (b's indices shifted).
TriangleSoup concat(const TriangleSoup& a, const TriangleSoup& b);
/// Reverses the winding of triangle i (or of all when i < 0).
TriangleSoup flip(TriangleSoup soup, long i = -1);
/// Every triangle gets its own three points, as an STL file stores them.
TriangleSoup unshare_points(const TriangleSoup& soup);
/// The soup without the triangles whose centroid satisfies `drop` (points kept).
TriangleSoup without_triangles(const TriangleSoup& soup,
                               const std::function<bool(const Vec3& centroid)>& drop);

/// A grid with `spacing` (mm) whose nodes cover `box` grown by `pad` mm on every side.
Grid grid_around(Box3 box, double spacing, double pad);

/// Seconds since t0 (benchmarks).
double seconds_since(std::chrono::steady_clock::time_point t0);

/// Signed volume by the divergence theorem (mm^3), positive for outward closed meshes.
double signed_volume(const TriangleSoup& soup);

/// A fresh empty folder under the system temp folder, unique per test.
std::filesystem::path scratch_dir();
/// Regular files directly in `dir` smaller than `max_bytes`, sorted by path (none if absent).
std::vector<std::filesystem::path> files_in(const std::filesystem::path& dir,
                                            std::uintmax_t max_bytes);
void write_file(const std::filesystem::path& path, const std::string& bytes);
std::string read_file(const std::filesystem::path& path);
/// `bytes` as one gzip member (zlib, deflate `level`).
std::string gzip(const std::string& bytes, int level = 6);

/// fill's defaults with a gyroid network of cubic cells `cell` mm and a grid of `voxel` mm.
FillOptions gyroid_options(double cell, double voxel);

/// A wavy field on `grid` (sines of the node's coordinates, 1 on the grid's faces): a closed
/// marching-cubes surface of many pieces, for slab and window tests.
Field wavy_field(const Grid& grid);

/// A decoded 8-bit PNG (greyscale or RGB, not interlaced), rows top to bottom, and its pHYs.
struct Png {
  int width = 0, height = 0, channels = 0;
  std::uint32_t phys_x = 0, phys_y = 0;  ///< pixels per unit (pHYs), 0 when absent
  int phys_unit = -1;                    ///< 1: metre; -1 when absent
  std::vector<std::uint8_t> pixels;      ///< channels bytes per pixel
  const std::uint8_t* at(int x, int y) const {
    return &pixels[(std::size_t(y) * width + x) * channels];
  }
  int value(int x, int y) const { return at(x, y)[0]; }
};

/// Decodes what tpmsfill writes: checks the signature, every chunk's CRC, that pHYs precedes
/// IDAT and that the image is 8-bit `channels`-channel (1 grey, 3 RGB); fails the test on
/// anything else.
Png decode_png(const std::string& bytes, int channels);

/// Runs a shell command, returns its exit status (not the raw wait status); output goes to
/// *output when given (stdout and stderr together).
int run_command(const std::string& command, std::string* output = nullptr);

}  // namespace tpmsfill::test
