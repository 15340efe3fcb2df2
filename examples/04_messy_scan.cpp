// A "scan" with the usual defects — holes, flipped faces, unwelded points, a second shell
// overlapping the first — made in code, checked, and filled anyway: fill() decides inside by
// the generalized winding number, closing the holes the way a person would.
//
//   04_messy_scan [OUT.stl]
#include <cmath>
#include <cstdio>
#include <tpmsfill/check.hpp>
#include <tpmsfill/error.hpp>
#include <tpmsfill/fill.hpp>
#include <tpmsfill/io.hpp>

using namespace tpmsfill;

namespace {

/// A UV sphere, every facet with points of its own (as STL stores them).
TriangleSoup sphere_soup(Vec3 c, double r, int n) {
  TriangleSoup s;
  auto at = [&](int i, int j) {
    const double theta = M_PI * i / n, phi = 2 * M_PI * j / (2 * n);
    return c + r * Vec3{std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi),
                        std::cos(theta)};
  };
  auto facet = [&](Vec3 a, Vec3 b, Vec3 d) {
    const auto k = static_cast<std::uint32_t>(s.points.size());
    s.points.insert(s.points.end(), {a, b, d});
    s.triangles.push_back({k, k + 1, k + 2});
  };
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < 2 * n; ++j) {
      if (i > 0) facet(at(i, j), at(i + 1, j), at(i, j + 1));
      if (i < n - 1) facet(at(i, j + 1), at(i + 1, j), at(i + 1, j + 1));
    }
  return s;
}

}  // namespace

int main(int argc, char** argv) {
  try {
    TriangleSoup scan = sphere_soup({0, 0, 0}, 10, 40);
    TriangleSoup second = sphere_soup({8, 0, 0}, 6, 30);  // overlaps the first
    // Defects: a hole (facets near the north pole dropped) and every 50th facet flipped.
    TriangleSoup messy;
    for (const TriangleSoup* part : {&scan, &second}) {
      const auto base = static_cast<std::uint32_t>(messy.points.size());
      messy.points.insert(messy.points.end(), part->points.begin(), part->points.end());
      for (std::size_t t = 0; t < part->triangles.size(); ++t) {
        Triangle tri = part->triangles[t];
        if (part == &scan && part->points[tri[0]].z > 9.3) continue;  // the hole
        if (t % 50 == 0) std::swap(tri[1], tri[2]);                   // flipped
        messy.triangles.push_back({base + tri[0], base + tri[1], base + tri[2]});
      }
    }

    const MeshCheck check = check_mesh(messy, {.self_intersections = false});
    std::printf("input: %s\n", check.valid() ? "valid" : "not valid:");
    for (const std::string& p : check.problems()) std::printf("  %s\n", p.c_str());

    FillOptions options;  // inside = InsideRule::Winding (the default)
    options.grid.voxel_size = 0.25;
    options.design.cell = {4, 4, 4};
    const FillResult r = fill(messy, options);
    std::printf("%s", to_text(r.report).c_str());
    if (argc > 1) write_mesh(argv[1], r.mesh);
    return r.report.validation.valid() ? 0 : 1;
  } catch (const Error& e) {
    std::fprintf(stderr, "error: %s\n", e.what());
    return 1;
  }
}
