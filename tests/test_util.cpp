#include "test_util.hpp"

#include <gtest/gtest.h>
#include <sys/wait.h>
#include <zlib.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <map>
#include <numbers>
#include <sstream>
#include <utility>

namespace tpmsfill::test {

float tpms_value(Vec3 p, const TpmsOptions& options) {
  return field_value(tpms_source(options), p);
}

float design_value(Vec3 p, const LatticeDesign& design) {
  return field_value(design_source(design), p);
}

TriangleSoup make_box(Vec3 min, Vec3 max) {
  TriangleSoup box;
  for (int i = 0; i < 8; ++i)
    box.points.push_back(
        {(i & 1) ? max.x : min.x, (i & 2) ? max.y : min.y, (i & 4) ? max.z : min.z});
  box.triangles = {{0, 2, 1}, {1, 2, 3}, {4, 5, 6}, {5, 7, 6}, {0, 1, 4}, {1, 5, 4},
                   {2, 6, 3}, {3, 6, 7}, {0, 4, 2}, {2, 4, 6}, {1, 3, 5}, {3, 7, 5}};
  return box;
}

TriangleSoup make_sphere(Vec3 center, double radius, int levels) {
  const double t = (1.0 + std::sqrt(5.0)) / 2.0;
  std::vector<Vec3> p = {{-1, t, 0},  {1, t, 0},  {-1, -t, 0}, {1, -t, 0}, {0, -1, t},  {0, 1, t},
                         {0, -1, -t}, {0, 1, -t}, {t, 0, -1},  {t, 0, 1},  {-t, 0, -1}, {-t, 0, 1}};
  std::vector<Triangle> f = {{0, 11, 5}, {0, 5, 1},  {0, 1, 7},   {0, 7, 10}, {0, 10, 11},
                             {1, 5, 9},  {5, 11, 4}, {11, 10, 2}, {10, 7, 6}, {7, 1, 8},
                             {3, 9, 4},  {3, 4, 2},  {3, 2, 6},   {3, 6, 8},  {3, 8, 9},
                             {4, 9, 5},  {2, 4, 11}, {6, 2, 10},  {8, 6, 7},  {9, 8, 1}};
  for (int l = 0; l < levels; ++l) {
    std::map<std::pair<std::uint32_t, std::uint32_t>, std::uint32_t> mid;
    auto midpoint = [&](std::uint32_t a, std::uint32_t b) {
      auto key = std::minmax(a, b);
      auto [it, inserted] = mid.emplace(key, static_cast<std::uint32_t>(p.size()));
      if (inserted) p.push_back(0.5 * (p[a] + p[b]));
      return it->second;
    };
    std::vector<Triangle> g;
    for (auto [a, b, c] : f) {
      std::uint32_t ab = midpoint(a, b), bc = midpoint(b, c), ca = midpoint(c, a);
      g.insert(g.end(), {{a, ab, ca}, {b, bc, ab}, {c, ca, bc}, {ab, bc, ca}});
    }
    f = std::move(g);
  }
  for (Vec3& q : p) q = center + (radius / norm(q)) * q;
  return {std::move(p), std::move(f)};
}

namespace {

// The quad a → b → c → d as two triangles, (a, b, c) and (a, c, d): the same turn as the quad.
void add_quad(TriangleSoup& s, std::uint32_t a, std::uint32_t b, std::uint32_t c, std::uint32_t d) {
  s.triangles.push_back({a, b, c});
  s.triangles.push_back({a, c, d});
}

}  // namespace

TriangleSoup make_height_field(int n, double L, const std::function<double(double, double)>& z) {
  TriangleSoup s;
  for (int j = 0; j <= n; ++j)
    for (int i = 0; i <= n; ++i) {
      const double x = L * i / n, y = L * j / n;
      s.points.push_back({x, y, z(x, y)});
    }
  auto id = [n](int i, int j) { return std::uint32_t(i + (n + 1) * j); };
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) add_quad(s, id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1));
  return s;
}

TriangleSoup make_spherical_cap(double R, double angle, int rings, int segments) {
  TriangleSoup s;
  s.points.push_back({0, 0, R});
  for (int r = 1; r <= rings; ++r) {
    const double theta = angle * r / rings;
    for (int k = 0; k < segments; ++k) {
      const double phi = 2 * std::numbers::pi * k / segments;
      s.points.push_back({R * std::sin(theta) * std::cos(phi), R * std::sin(theta) * std::sin(phi),
                          R * std::cos(theta)});
    }
  }
  auto id = [segments](int r, int k) {
    return std::uint32_t(1 + (r - 1) * segments + (k % segments));
  };
  for (int k = 0; k < segments; ++k) s.triangles.push_back({0, id(1, k), id(1, k + 1)});
  for (int r = 1; r < rings; ++r)
    for (int k = 0; k < segments; ++k)
      add_quad(s, id(r, k), id(r + 1, k), id(r + 1, k + 1), id(r, k + 1));
  return s;
}

TriangleSoup make_open_cylinder(double R, double H, int segments, int rows) {
  TriangleSoup s;
  for (int j = 0; j <= rows; ++j)
    for (int k = 0; k < segments; ++k) {
      const double phi = 2 * std::numbers::pi * k / segments;
      s.points.push_back({R * std::cos(phi), R * std::sin(phi), H * j / rows});
    }
  auto id = [segments](int j, int k) { return std::uint32_t(j * segments + (k % segments)); };
  for (int j = 0; j < rows; ++j)
    for (int k = 0; k < segments; ++k)
      add_quad(s, id(j, k), id(j, k + 1), id(j + 1, k + 1), id(j + 1, k));
  return s;
}

TriangleSoup make_torus(double R, double r, int nu, int nv) {
  TriangleSoup torus;
  const double two_pi = 2 * std::numbers::pi;
  for (int i = 0; i < nu; ++i)
    for (int j = 0; j < nv; ++j) {
      double u = two_pi * i / nu, v = two_pi * j / nv;
      torus.points.push_back({(R + r * std::cos(v)) * std::cos(u),
                              (R + r * std::cos(v)) * std::sin(u), r * std::sin(v)});
    }
  auto id = [&](int i, int j) { return static_cast<std::uint32_t>((i % nu) * nv + (j % nv)); };
  for (int i = 0; i < nu; ++i)
    for (int j = 0; j < nv; ++j) {
      // (u, v) is a right-handed chart whose normal points away from the tube's core.
      torus.triangles.push_back({id(i, j), id(i + 1, j), id(i + 1, j + 1)});
      torus.triangles.push_back({id(i, j), id(i + 1, j + 1), id(i, j + 1)});
    }
  return torus;
}

TriangleSoup make_tube(double outer_radius, double inner_radius, double height, int segments,
                       int rings) {
  TriangleSoup tube;
  const double two_pi = 2 * std::numbers::pi;
  for (int r = 0; r < rings; ++r)
    for (int s = 0; s < segments; ++s) {
      const double u = two_pi * s / segments, z = height * r / (rings - 1);
      tube.points.push_back({outer_radius * std::cos(u), outer_radius * std::sin(u), z});
      tube.points.push_back({inner_radius * std::cos(u), inner_radius * std::sin(u), z});
    }
  auto outer = [&](int s, int r) {
    return static_cast<std::uint32_t>(2 * (r * segments + s % segments));
  };
  auto inner = [&](int s, int r) { return outer(s, r) + 1; };
  for (int r = 0; r + 1 < rings; ++r)
    for (int s = 0; s < segments; ++s) {
      // (angle, z) is right-handed with the normal pointing away from the axis.
      tube.triangles.push_back({outer(s, r), outer(s + 1, r), outer(s + 1, r + 1)});
      tube.triangles.push_back({outer(s, r), outer(s + 1, r + 1), outer(s, r + 1)});
      tube.triangles.push_back({inner(s, r), inner(s + 1, r + 1), inner(s + 1, r)});
      tube.triangles.push_back({inner(s, r), inner(s, r + 1), inner(s + 1, r + 1)});
    }
  const int top = rings - 1;
  for (int s = 0; s < segments; ++s) {
    tube.triangles.push_back({outer(s, top), outer(s + 1, top), inner(s + 1, top)});
    tube.triangles.push_back({outer(s, top), inner(s + 1, top), inner(s, top)});
    tube.triangles.push_back({outer(s, 0), inner(s + 1, 0), outer(s + 1, 0)});
    tube.triangles.push_back({outer(s, 0), inner(s, 0), inner(s + 1, 0)});
  }
  return tube;
}

TriangleSoup make_box_with_hole(Vec3 min, Vec3 max) {
  TriangleSoup box = make_box(min, max);
  box.triangles.resize(10);  // the last two triangles are the +x side
  return box;
}

TriangleSoup make_bow_tie() {
  // Apex 0 at the origin; one tetrahedron above it, one mirrored below.
  TriangleSoup s;
  s.points = {{0, 0, 0}, {-1, -1, 1}, {1, -1, 1}, {0, 1, 1}, {-1, -1, -1}, {1, -1, -1}, {0, 1, -1}};
  s.triangles = {{1, 2, 3}, {0, 2, 1}, {0, 3, 2}, {0, 1, 3},
                 {4, 6, 5}, {0, 6, 4}, {0, 5, 6}, {0, 4, 5}};
  return s;
}

TriangleSoup concat(const TriangleSoup& a, const TriangleSoup& b) {
  TriangleSoup s = a;
  const auto offset = static_cast<std::uint32_t>(a.points.size());
  s.points.insert(s.points.end(), b.points.begin(), b.points.end());
  for (Triangle t : b.triangles)
    s.triangles.push_back({t[0] + offset, t[1] + offset, t[2] + offset});
  return s;
}

TriangleSoup flip(TriangleSoup soup, long i) {
  for (std::size_t k = 0; k < soup.triangles.size(); ++k)
    if (i < 0 || static_cast<std::size_t>(i) == k)
      std::swap(soup.triangles[k][1], soup.triangles[k][2]);
  return soup;
}

TriangleSoup without_triangles(const TriangleSoup& soup,
                               const std::function<bool(const Vec3& centroid)>& drop) {
  TriangleSoup out;
  out.points = soup.points;
  for (const Triangle& t : soup.triangles) {
    const Vec3 c = (1.0 / 3.0) * (soup.points[t[0]] + soup.points[t[1]] + soup.points[t[2]]);
    if (!drop(c)) out.triangles.push_back(t);
  }
  return out;
}

std::vector<std::filesystem::path> files_in(const std::filesystem::path& dir,
                                            std::uintmax_t max_bytes) {
  std::vector<std::filesystem::path> files;
  if (!std::filesystem::exists(dir)) return files;
  for (const auto& entry : std::filesystem::directory_iterator(dir))
    if (entry.is_regular_file() && entry.file_size() < max_bytes) files.push_back(entry.path());
  std::sort(files.begin(), files.end());
  return files;
}

TriangleSoup unshare_points(const TriangleSoup& soup) {
  TriangleSoup s;
  for (Triangle t : soup.triangles) {
    auto n = static_cast<std::uint32_t>(s.points.size());
    for (std::uint32_t v : t) s.points.push_back(soup.points[v]);
    s.triangles.push_back({n, n + 1, n + 2});
  }
  return s;
}

Grid grid_around(Box3 box, double spacing, double pad) {
  Grid g;
  g.origin = box.min - Vec3{pad, pad, pad};
  g.spacing = spacing;
  for (int a = 0; a < 3; ++a)
    g.dims[a] = static_cast<int>(std::ceil((box.max[a] - box.min[a] + 2 * pad) / spacing)) + 1;
  return g;
}

double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

double signed_volume(const TriangleSoup& soup) {
  double v = 0;
  for (Triangle t : soup.triangles)
    v += dot(soup.points[t[0]], cross(soup.points[t[1]], soup.points[t[2]]));
  return v / 6.0;
}

std::filesystem::path scratch_dir() {
  const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
  std::string name = info ? std::string(info->test_suite_name()) + "." + info->name() : "misc";
  for (char& c : name)
    if (c == '/') c = '_';
      // Inside the build tree when the build says where: two builds' suites running at once on one
      // machine (a CI clone beside a sanitizer build) must not clear each other's files.
#ifdef TPMSFILL_SCRATCH_DIR
  auto dir = std::filesystem::path(TPMSFILL_SCRATCH_DIR) / name;
#else
  auto dir = std::filesystem::temp_directory_path() / "tpmsfill-tests" / name;
#endif
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  return dir;
}

void write_file(const std::filesystem::path& path, const std::string& bytes) {
  std::ofstream out(path, std::ios::binary);
  out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
  if (!out) throw std::runtime_error("cannot write " + path.string());
}

std::string read_file(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

std::string gzip(const std::string& bytes, int level) {
  std::string out(compressBound(static_cast<uLong>(bytes.size())) + 64, '\0');
  z_stream z{};
  deflateInit2(&z, level, Z_DEFLATED, 15 + 16, 8, Z_DEFAULT_STRATEGY);
  z.next_in = reinterpret_cast<Bytef*>(const_cast<char*>(bytes.data()));
  z.avail_in = static_cast<uInt>(bytes.size());
  z.next_out = reinterpret_cast<Bytef*>(out.data());
  z.avail_out = static_cast<uInt>(out.size());
  deflate(&z, Z_FINISH);
  out.resize(out.size() - z.avail_out);
  deflateEnd(&z);
  return out;
}

int run_command(const std::string& command, std::string* output) {
  FILE* pipe = popen((command + " 2>&1").c_str(), "r");
  if (!pipe) return -1;
  std::array<char, 4096> buffer;
  std::string out;
  while (std::size_t n = std::fread(buffer.data(), 1, buffer.size(), pipe))
    out.append(buffer.data(), n);
  int status = pclose(pipe);
  if (output) *output = std::move(out);
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

namespace {

std::uint32_t be32(const std::string& s, std::size_t at) {
  return std::uint32_t(std::uint8_t(s[at])) << 24 | std::uint32_t(std::uint8_t(s[at + 1])) << 16 |
         std::uint32_t(std::uint8_t(s[at + 2])) << 8 | std::uint32_t(std::uint8_t(s[at + 3]));
}

}  // namespace

Png decode_png(const std::string& bytes, int channels) {
  Png png;
  png.channels = channels;
  EXPECT_EQ(bytes.substr(0, 8), std::string("\x89PNG\r\n\x1a\n", 8));
  std::string idat;
  bool ended = false;
  for (std::size_t at = 8; at + 12 <= bytes.size() && !ended;) {
    const std::uint32_t length = be32(bytes, at);
    const std::string type = bytes.substr(at + 4, 4);
    EXPECT_LE(at + 12 + length, bytes.size()) << type;
    const std::string data = bytes.substr(at + 8, length);
    const auto crc = crc32(0, reinterpret_cast<const Bytef*>(bytes.data() + at + 4), length + 4);
    EXPECT_EQ(be32(bytes, at + 8 + length), crc) << type;
    if (type == "IHDR") {
      EXPECT_EQ(length, 13u);
      png.width = int(be32(data, 0));
      png.height = int(be32(data, 4));
      const char colour = channels == 3 ? 2 : 0;  // RGB or grey, 8 bits, not interlaced
      EXPECT_EQ(data.substr(8), std::string("\x08", 1) + colour + std::string(3, '\0'));
    } else if (type == "pHYs") {
      EXPECT_TRUE(idat.empty());  // pHYs must precede IDAT
      png.phys_x = be32(data, 0);
      png.phys_y = be32(data, 4);
      png.phys_unit = data.at(8);
    } else if (type == "IDAT") {
      idat += data;
    } else if (type == "IEND") {
      ended = true;
      EXPECT_EQ(at + 12, bytes.size());
    }
    at += 12 + length;
  }
  EXPECT_TRUE(ended);
  const std::size_t stride = std::size_t(png.width) * channels;
  std::vector<std::uint8_t> raw((stride + 1) * png.height);
  uLongf raw_size = raw.size();
  EXPECT_EQ(
      uncompress(raw.data(), &raw_size, reinterpret_cast<const Bytef*>(idat.data()), idat.size()),
      Z_OK);
  EXPECT_EQ(raw_size, raw.size());
  png.pixels.assign(stride * png.height, 0);
  const std::size_t c = static_cast<std::size_t>(channels);
  for (int y = 0; y < png.height; ++y) {
    const std::uint8_t filter = raw[y * (stride + 1)];
    EXPECT_LE(filter, 4);
    const std::uint8_t* in = &raw[y * (stride + 1) + 1];
    std::uint8_t* row = &png.pixels[y * stride];
    for (std::size_t i = 0; i < stride; ++i) {
      const int a = i >= c ? row[i - c] : 0, b = y > 0 ? row[i - stride] : 0,
                d = i >= c && y > 0 ? row[i - stride - c] : 0;
      const int p = a + b - d, pa = std::abs(p - a), pb = std::abs(p - b), pd = std::abs(p - d);
      const int predictor = filter == 1   ? a
                            : filter == 2 ? b
                            : filter == 3 ? (a + b) / 2
                            : filter == 4 ? (pa <= pb && pa <= pd ? a : (pb <= pd ? b : d))
                                          : 0;
      row[i] = std::uint8_t(in[i] + predictor);
    }
  }
  return png;
}

Field wavy_field(const Grid& grid) {
  Field f{grid, std::vector<float>(grid.node_count())};
  const auto [nx, ny, nz] = grid.dims;
  for (int k = 0; k < nz; ++k)
    for (int j = 0; j < ny; ++j)
      for (int i = 0; i < nx; ++i) {
        const Vec3 p = grid.node(i, j, k);
        const bool border = i == 0 || j == 0 || k == 0 || i == nx - 1 || j == ny - 1 || k == nz - 1;
        f.values[grid.index(i, j, k)] =
            border ? 1.0f
                   : static_cast<float>(std::sin(7 * p.x) + std::cos(9 * p.y) * std::sin(5 * p.z) -
                                        0.2);
      }
  return f;
}

FillOptions gyroid_options(double cell, double voxel) {
  FillOptions o;
  o.design.cell = {cell, cell, cell};
  o.grid.voxel_size = voxel;
  return o;
}

TetMesh make_tet_grid(Vec3 min, Vec3 max, std::array<int, 3> cells, double jitter,
                      const std::function<bool(int, int, int)>& keep) {
  const int nx = cells[0] + 1, ny = cells[1] + 1, nz = cells[2] + 1;
  auto id = [&](int i, int j, int k) { return static_cast<std::uint32_t>(i + nx * (j + ny * k)); };
  TetMesh mesh;
  Random numbers{0x9e3779b97f4a7c15ULL};
  auto random = [&] { return 2 * numbers.next() - 1.0; };  // in [-1, 1)
  for (int k = 0; k < nz; ++k)
    for (int j = 0; j < ny; ++j)
      for (int i = 0; i < nx; ++i) {
        const int index[3] = {i, j, k};
        double p[3];
        for (int a = 0; a < 3; ++a) {
          const double step = (max[a] - min[a]) / cells[a];
          const double shift = random() * jitter;
          p[a] = min[a] + step * (index[a] + (index[a] == 0 || index[a] == cells[a] ? 0 : shift));
        }
        mesh.points.push_back({p[0], p[1], p[2]});
      }
  // Kuhn: the six paths from the cube's corner 0 to corner 7, one axis at a time.
  constexpr int kPaths[6][3] = {{0, 1, 2}, {0, 2, 1}, {1, 0, 2}, {1, 2, 0}, {2, 0, 1}, {2, 1, 0}};
  for (int k = 0; k < cells[2]; ++k)
    for (int j = 0; j < cells[1]; ++j)
      for (int i = 0; i < cells[0]; ++i) {
        if (keep && !keep(i, j, k)) continue;
        for (int p = 0; p < 6; ++p) {
          int at[3] = {i, j, k};
          Tet t{};
          t[0] = id(at[0], at[1], at[2]);
          for (int s = 0; s < 3; ++s) {
            ++at[kPaths[p][s]];
            t[s + 1] = id(at[0], at[1], at[2]);
          }
          // Odd permutations of the axes give negative tets: turn them.
          if (p == 1 || p == 2 || p == 5) std::swap(t[2], t[3]);
          mesh.tets.push_back(t);
        }
      }
  // Points in no kept cube are left out, so the mesh has no unused points.
  std::vector<std::int64_t> renumber(mesh.points.size(), -1);
  TetMesh used;
  for (Tet& t : mesh.tets)
    for (std::uint32_t& v : t) {
      if (renumber[v] < 0) {
        renumber[v] = static_cast<std::int64_t>(used.points.size());
        used.points.push_back(mesh.points[v]);
      }
      v = static_cast<std::uint32_t>(renumber[v]);
    }
  used.tets = std::move(mesh.tets);
  return used;
}

double tet_section_area(const TetMesh& mesh, double z) {
  double total = 0;
  for (const Tet& t : mesh.tets) {
    std::vector<std::array<double, 2>> points;
    for (int a = 0; a < 4; ++a)
      for (int b = a + 1; b < 4; ++b) {
        const Vec3 p = mesh.points[t[a]], q = mesh.points[t[b]];
        if ((p.z < z) == (q.z < z)) continue;
        const double s = (z - p.z) / (q.z - p.z);
        points.push_back({p.x + s * (q.x - p.x), p.y + s * (q.y - p.y)});
      }
    if (points.size() < 3) continue;
    // Convex: sorted around the centre, then the shoelace.
    double cx = 0, cy = 0;
    for (const auto& p : points) cx += p[0] / points.size(), cy += p[1] / points.size();
    std::sort(points.begin(), points.end(), [&](const auto& a, const auto& b) {
      return std::atan2(a[1] - cy, a[0] - cx) < std::atan2(b[1] - cy, b[0] - cx);
    });
    for (std::size_t i = 0; i < points.size(); ++i) {
      const auto& p = points[i];
      const auto& q = points[(i + 1) % points.size()];
      total += (p[0] * q[1] - q[0] * p[1]) / 2;
    }
  }
  return total;
}

double section_area(const TriangleSoup& mesh, double z) {
  double twice = 0;
  for (const Triangle& t : mesh.triangles) {
    const Vec3 p[3] = {mesh.points[t[0]], mesh.points[t[1]], mesh.points[t[2]]};
    Vec3 cut[2];
    int n = 0;
    for (int e = 0; e < 3; ++e) {
      const Vec3 a = p[e], b = p[(e + 1) % 3];
      if ((a.z < z) != (b.z < z)) cut[n++] = a + ((z - a.z) / (b.z - a.z)) * (b - a);
    }
    if (n != 2) continue;
    const Vec3 normal = cross(p[1] - p[0], p[2] - p[0]);
    Vec3 d = cut[1] - cut[0];
    if (d.y * normal.x - d.x * normal.y < 0) std::swap(cut[0], cut[1]);
    twice += cut[0].x * cut[1].y - cut[1].x * cut[0].y;
  }
  return 0.5 * twice;
}

}  // namespace tpmsfill::test
