// A fitted solid's material sampled onto a volume (material_volume.hpp).
#include "tpmsfill/solid/material_volume.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <optional>
#include <string>

#include "core/parallel.hpp"
#include "core/stage_progress.hpp"
#include "io/file_bytes.hpp"
#include "tpmsfill/error.hpp"
#include "tpmsfill/sampling/classify.hpp"
#include "tpmsfill/solid/solid_inverse.hpp"
#include "tpmsfill/solid/solid_model.hpp"

namespace tpmsfill {
namespace {

// Gives every sample without a value the mean of its 6-neighbours that have one, a layer at
// a time (each layer reads only the layers before it, so the result is order-free).
void extend_outwards(ScalarVolume& v, std::vector<std::uint8_t>& known) {
  const int nx = v.dims[0], ny = v.dims[1], nz = v.dims[2];
  const std::size_t sx = 1, sy = std::size_t(nx), sz = std::size_t(nx) * ny;
  std::vector<std::size_t> front;
  for (;;) {
    front.clear();
    std::vector<double> next;
    for (int k = 0; k < nz; ++k)
      for (int j = 0; j < ny; ++j)
        for (int i = 0; i < nx; ++i) {
          const std::size_t n = i * sx + j * sy + k * sz;
          if (known[n]) continue;
          double sum = 0;
          int count = 0;
          auto take = [&](bool exists, std::size_t m) {
            if (exists && known[m]) sum += v.values[m], ++count;
          };
          take(i > 0, n - sx), take(i + 1 < nx, n + sx);
          take(j > 0, n - sy), take(j + 1 < ny, n + sy);
          take(k > 0, n - sz), take(k + 1 < nz, n + sz);
          if (count) front.push_back(n), next.push_back(sum / count);
        }
    if (front.empty()) return;
    for (std::size_t f = 0; f < front.size(); ++f)
      v.values[front[f]] = next[f], known[front[f]] = 1;
  }
}

// G on the cube's faces, n × n quads a face, as a closed triangle mesh: each point of the
// cube's surface lattice is one vertex, shared by the faces that meet there.
TriangleSoup boundary_surface(const SolidSpline& spline, int n) {
  TriangleSoup soup;
  std::map<std::array<int, 3>, std::uint32_t> id;
  auto vertex = [&](std::array<int, 3> c) {
    auto [it, added] = id.try_emplace(c, static_cast<std::uint32_t>(soup.points.size()));
    if (added)
      soup.points.push_back(
          evaluate_solid(spline, {double(c[0]) / n, double(c[1]) / n, double(c[2]) / n}).position);
    return it->second;
  };
  for (int axis = 0; axis < 3; ++axis)
    for (int side = 0; side < 2; ++side) {
      const int a = (axis + 1) % 3, b = (axis + 2) % 3;
      for (int i = 0; i < n; ++i)
        for (int j = 0; j < n; ++j) {
          std::array<std::uint32_t, 4> q;
          for (int c = 0; c < 4; ++c) {
            std::array<int, 3> at{};
            at[axis] = side * n;
            at[a] = i + ((c == 1 || c == 2) ? 1 : 0);
            at[b] = j + (c >= 2 ? 1 : 0);
            q[c] = vertex(at);
          }
          // Parity decides inside, so the faces' orientation does not matter.
          soup.triangles.push_back({q[0], q[1], q[2]});
          soup.triangles.push_back({q[0], q[2], q[3]});
        }
    }
  return soup;
}

}  // namespace

MaterialVolume material_volume(const SolidSpline& spline, const MaterialVolumeOptions& options) {
  if (spline.material.empty())
    throw InputError("the model has no material to grade by (it was fitted without one)");
  if (options.cells < 4 || options.cells > 512)
    throw InputError("a material volume takes 4 to 512 samples along the longest side");
  if (options.padding < 1 || options.padding > 16)
    throw InputError("a material volume's padding is 1 to 16 samples");
  const Box3 box = solid_box(spline);
  const Vec3 size = box.size();
  const double longest = std::max({size.x, size.y, size.z});
  if (!(longest > 0) || !std::isfinite(longest))
    throw InputError("the model's solid has no extent to sample");
  const double h = longest / options.cells;

  MaterialVolume out;
  ScalarVolume& v = out.volume;
  for (int a = 0; a < 3; ++a) {
    const int inner = std::max(1, static_cast<int>(std::ceil(size[a] / h)));
    v.dims[a] = inner + 2 * options.padding;
    v.spacing[a] = h;
    // Centred on the box: the inner samples' centres span it symmetrically.
    (&v.origin.x)[a] = box.centre()[a] - 0.5 * (v.dims[a] - 1) * h;
  }
  v.values.assign(v.count(), 0.0);
  std::vector<std::uint8_t> known(v.count(), 0);

  // Newton from outside the solid wanders along the cube's faces before it gives up, so only
  // samples inside G's boundary (sampled as a mesh, classified by parity) are inverted; a
  // sample the mesh misplaces near the surface gets its value from its neighbours.
  const Grid grid{.origin = v.origin, .spacing = h, .dims = v.dims};
  const Mask candidates =
      classify_grid(build_index(boundary_surface(spline, std::max(2 * options.cells, 16))), grid,
                    {.rule = InsideRule::Parity})
          .inside;
  const SolidLocator locator = build_solid_locator(spline);
  const std::size_t row = std::size_t(v.dims[0]);
  const std::size_t rows = std::size_t(v.dims[1]) * v.dims[2];
  detail::ProgressCounter progress(options.progress, "material volume", rows);
  detail::parallel_for(rows, 4, [&](std::size_t begin, std::size_t end) {
    for (std::size_t r = begin; r < end; ++r) {
      const int j = static_cast<int>(r % v.dims[1]), k = static_cast<int>(r / v.dims[1]);
      std::optional<std::array<double, 3>> previous;  // along the row: Newton's first start
      for (std::size_t i = 0; i < row; ++i) {
        const std::size_t n = r * row + i;
        if (!candidates.values[n]) {
          previous.reset();
          continue;
        }
        const Vec3 p{v.origin.x + i * h, v.origin.y + j * h, v.origin.z + k * h};
        const Preimage x = invert_solid(spline, locator, p, {}, previous);
        if (!x.inside) {
          previous.reset();
          continue;
        }
        previous = x.uvw;
        v.values[n] = evaluate_solid(spline, x.uvw).material;
        known[n] = 1;
      }
      progress.add(1);
    }
  });
  progress.finish();
  out.inside = static_cast<std::size_t>(std::count(known.begin(), known.end(), 1));
  if (out.inside == 0)
    throw InputError("no sample of the material volume fell inside the model's solid");
  out.min = HUGE_VAL, out.max = -HUGE_VAL;
  for (std::size_t n = 0; n < v.values.size(); ++n)
    if (known[n])
      out.min = std::min(out.min, v.values[n]), out.max = std::max(out.max, v.values[n]);
  extend_outwards(v, known);
  return out;
}

ScalarVolume read_grading_volume(const std::filesystem::path& path,
                                 const MaterialVolumeOptions& options) {
  if (detail::lower_extension(path) == ".tsm") {
    const SolidModel model = read_solid_model(path);
    if (model.fit.spline.material.empty())
      throw InputError(path.string() +
                       ": the model has no material to grade by (it was fitted without one)");
    return material_volume(model.fit.spline, options).volume;
  }
  ScalarVolume volume = read_volume_file(path).volume;
  if (!volume.has_physical_size())
    throw InputError(path.string() +
                     ": the volume has no physical size (spacing), so it cannot be placed in mm");
  return volume;
}

}  // namespace tpmsfill
