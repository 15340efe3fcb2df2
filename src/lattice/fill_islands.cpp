// Stage "islands": fill's lattice components judged, cavities counted and islands (pieces that
// are not the main body of their part of the model) dropped, on every path (whole grid, slabs,
// streamed).
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <functional>
#include <limits>
#include <string>

#include "core/grid_buffer.hpp"
#include "core/index_limits.hpp"
#include "core/parallel.hpp"
#include "lattice/fill_job.hpp"
#include "tpmsfill/mesh/components.hpp"
#include "tpmsfill/sampling/voxel.hpp"

namespace tpmsfill::detail {
namespace {

// What islands are judged by: which nodes are solid (φ < 0), the model's parts (26-connected
// regions of inside nodes) and, on demand, the solid's pieces (6-connected regions of solid
// nodes). The whole-grid path reads them from φ and the occupancy, the slab path from runs.
struct IslandMasks {
  std::function<bool(int, int, int)> solid;
  Regions parts;
  std::function<Regions()> pieces;
};

// The masks of the path the job took.
IslandMasks island_masks(const Job& job) {
  if (job.slab_planes == 0) {
    const Field& phi = job.phi;
    return {[&phi](int i, int j, int k) { return phi.values[phi.grid.index(i, j, k)] < 0; },
            label_regions(job.occupancy.inside),
            [&phi] {
              Mask solid{phi.grid, detail::grid_buffer<std::uint8_t>(phi.values.size())};
              detail::parallel_for(solid.values.size(), std::size_t{1} << 16,
                                   [&](std::size_t b, std::size_t e) {
                                     for (std::size_t n = b; n < e; ++n)
                                       solid.values[n] = phi.values[n] < 0;
                                   });
              return label_regions(solid, Connectivity::Face);
            }};
  }
  return {
      [&job](int i, int j, int k) { return job.solid_runs.region_at(i, j, k) != detail::kNoIndex; },
      label_runs(job.inside_runs),
      [&job] { return label_runs(job.solid_runs, Connectivity::Face); }};
}

// Islands: lattice components that are not the largest piece within their part of the model
// (a 26-connected region of inside nodes). A component is located by a solid corner (φ < 0
// implies the node is inside) of the cell holding its first triangle: its node index, or none.
std::vector<std::uint64_t> solid_nodes(const std::vector<Vec3>& first_centroid, const Grid& g,
                                       const IslandMasks& masks) {
  std::vector<std::uint64_t> node(first_centroid.size(), UINT64_MAX);
  for (std::size_t c = 0; c < first_centroid.size(); ++c) {
    const Vec3 centroid = first_centroid[c];
    int cell[3];
    for (int axis = 0; axis < 3; ++axis)
      cell[axis] =
          std::clamp(static_cast<int>(std::floor((centroid[axis] - g.origin[axis]) / g.spacing)), 0,
                     g.dims[axis] - 2);
    for (int corner = 0; corner < 8 && node[c] == UINT64_MAX; ++corner) {
      const int i = cell[0] + (corner & 1), j = cell[1] + (corner >> 1 & 1),
                k = cell[2] + (corner >> 2 & 1);
      if (masks.solid(i, j, k)) node[c] = g.index(i, j, k);
    }
  }
  return node;
}

std::vector<bool> main_bodies(const detail::ComponentFacts& comps, const Grid& g,
                              const IslandMasks& masks) {
  const std::uint32_t none = detail::kNoIndex;
  const std::vector<std::uint64_t> node = solid_nodes(comps.first_centroid, g, masks);
  auto region_of = [&](const Regions& r, std::size_t c) {
    if (node[c] == UINT64_MAX) return none;
    const std::uint64_t n = node[c], nx = g.dims[0], ny = g.dims[1];
    return r.region_at(static_cast<int>(n % nx), static_cast<int>(n / nx % ny),
                       static_cast<int>(n / (nx * ny)));
  };
  std::vector<std::uint32_t> part(comps.info.size(), none);
  for (std::size_t c = 0; c < comps.info.size(); ++c) part[c] = region_of(masks.parts, c);
  std::vector<std::size_t> largest(masks.parts.count, std::numeric_limits<std::size_t>::max());
  for (std::size_t c = 0; c < comps.info.size(); ++c) {
    if (part[c] == none || comps.info[c].volume < 0) continue;
    std::size_t& best = largest[part[c]];
    if (best == std::numeric_limits<std::size_t>::max() ||
        std::fabs(comps.info[c].volume) > std::fabs(comps.info[best].volume))
      best = c;
  }
  std::vector<bool> keep(comps.info.size(), false);
  bool cavity = false, removed = false;
  for (std::size_t c = 0; c < comps.info.size(); ++c) {
    cavity = cavity || comps.info[c].volume < 0;
    keep[c] = part[c] == none || largest[part[c]] == c || comps.info[c].volume < 0;
    removed = removed || !keep[c];
  }
  if (!cavity || !removed) return keep;
  // A component of negative volume bounds a cavity (the pore inside a shell, a void a skin
  // encloses): it goes with the solid around it, which the shell's outer surface bounds too.
  // It stays only if a kept positive component bounds the same solid (6-connected φ < 0).
  const Regions pieces = masks.pieces();
  std::vector<bool> kept_piece(pieces.count, false);
  for (std::size_t c = 0; c < comps.info.size(); ++c)
    if (const std::uint32_t p = region_of(pieces, c);
        keep[c] && comps.info[c].volume > 0 && p != none)
      kept_piece[p] = true;
  for (std::size_t c = 0; c < comps.info.size(); ++c)
    if (const std::uint32_t p = region_of(pieces, c); comps.info[c].volume < 0 && p != none)
      keep[c] = kept_piece[p];
  return keep;
}

// Sealed voids hold unfused powder or resin: say how many, whatever sealed them. Voids
// smaller than a voxel are marching cubes' specks between nearly touching surfaces, not pores.
void warn_cavities(const FillOptions& o, const detail::ComponentFacts& comps,
                   const std::vector<bool>& keep, double voxel, FillReport& r) {
  std::uint64_t count = 0;
  double volume = 0;
  for (std::size_t c = 0; c < comps.info.size(); ++c)
    if (keep[c] && -comps.info[c].volume >= voxel * voxel * voxel)
      ++count, volume -= comps.info[c].volume;
  if (!count) return;
  char figures[96];
  std::snprintf(figures, sizeof figures, "%llu void(s) (%.3g mm3)",
                static_cast<unsigned long long>(count), volume);
  const std::string drain = ", where unfused powder or resin cannot drain";
  if (o.skin > 0 && !o.skin_windows)
    r.warnings.push_back("the closed skin seals " + std::string(figures) + " in" + drain +
                         " (--skin-windows opens the skin at the pores)");
  else if (o.skin > 0)
    r.warnings.push_back("the skin windows left " + std::string(figures) + " sealed" + drain +
                         " (pores that never reach the skin; a thinner --skin or a larger --cell "
                         "opens more)");
  else
    r.warnings.push_back("the lattice encloses " + std::string(figures) + drain);
}

// Islands that are whole features: removal of more than 5 % of the lattice, or of any piece
// larger than a cell, is not the tidying it is meant to be.
void warn_islands(const FillOptions& o, double lattice_before, FillReport& r) {
  const double fraction = lattice_before > 0 ? r.islands_volume / lattice_before : 0;
  const Vec3 c = r.cell;
  const double largest = r.largest_islands.empty() ? 0 : r.largest_islands.front().volume;
  if (fraction <= 0.05 && largest <= c.x * c.y * c.z) return;
  const Vec3 s = r.largest_islands.front().bbox.size();
  char text[320];
  std::snprintf(text, sizeof text,
                "removing %llu island(s) took %.3g mm3, %.1f %% of the lattice (the largest "
                "%.3g mm3, %.3g x %.3g x %.3g mm)",
                static_cast<unsigned long long>(r.islands_removed), r.islands_volume,
                100 * fraction, largest, s.x, s.y, s.z);
  // Over half: the lattice itself falls apart (a level near its limit); else the islands
  // are parts of the model too thin for the lattice to join.
  const std::string apart =
      o.design.structure
          ? ": the structure falls apart into pieces at these thresholds; widen them (a lower "
            "--porosity) or --keep-islands keeps them"
          : ": the lattice falls apart into pieces at this level or thickness; move it towards "
            "0 (or --porosity nearer 0.5)";
  if (o.design.structure && fraction <= 0.5) {
    r.warnings.push_back(std::string(text) +
                         ": they are pieces of the structure that touch no larger piece "
                         "within the model; --keep-islands keeps them");
    return;
  }
  r.warnings.push_back(
      std::string(text) +
      (fraction > 0.5 ? apart
                      : std::string(": they are features of the model too thin for the lattice "
                                    "to join; a smaller --cell") +
                            (o.skin > 0 ? "" : ", a --skin") + " or --keep-islands keeps them"));
}

}  // namespace

// Cavities are counted (a closed skin seals them in); islands, the pieces that are not the
// main body of their part of the model, are to be removed unless kept, the largest listed.
std::vector<bool> judge_islands(const Job& job, const ComponentFacts& comps) {
  const FillOptions& o = job.options;
  FillReport& r = job.report;
  double lattice_before = 0;
  for (const auto& c : comps.info) lattice_before += c.volume;
  std::vector<bool> keep(comps.info.size(), true);
  if (!o.keep_islands && comps.info.size() >= 2)
    keep = main_bodies(comps, job.grid, island_masks(job));
  for (std::size_t c = 0; c < keep.size(); ++c)
    if (keep[c] && comps.info[c].volume < 0)
      ++r.cavities, r.cavities_volume -= comps.info[c].volume;
  warn_cavities(o, comps, keep, job.grid.spacing, r);
  if (std::find(keep.begin(), keep.end(), false) == keep.end()) return keep;
  // An island is a removed piece of positive volume; the cavities it enclosed go with it, so
  // the volume removed is the signed sum.
  const std::vector<Box3> box = comps.boxes(keep);
  for (std::size_t c = 0; c < keep.size(); ++c)
    if (!keep[c]) {
      r.islands_volume += comps.info[c].volume;
      if (comps.info[c].volume < 0) continue;
      ++r.islands_removed;
      r.largest_islands.push_back({comps.info[c].volume, box[c]});
    }
  // Largest first; equal volumes keep component order, so the list is deterministic.
  std::stable_sort(
      r.largest_islands.begin(), r.largest_islands.end(),
      [](const RemovedIsland& a, const RemovedIsland& b) { return a.volume > b.volume; });
  if (r.largest_islands.size() > 10) r.largest_islands.resize(10);
  if (r.islands_removed) warn_islands(o, lattice_before, r);
  return keep;
}

// Islands of the mesh held whole: its components, judged, and the islands dropped.
void remove_islands(Job& job) {
  const Components comps = mesh_components(job.mesh);
  detail::ComponentFacts facts;
  facts.info = comps.info;
  for (const Components::Info& c : comps.info) {
    const Triangle& t = job.mesh.triangles[c.first_triangle];
    const TriangleSoup& m = job.mesh;
    facts.first_centroid.push_back((1.0 / 3.0) *
                                   (m.points[t[0]] + m.points[t[1]] + m.points[t[2]]));
  }
  facts.boxes = [&](const std::vector<bool>& keep) {
    std::vector<Box3> box(comps.info.size());
    for (std::size_t t = 0; t < job.mesh.triangles.size(); ++t)
      if (const std::uint32_t c = comps.triangle_component[t]; !keep[c])
        for (std::uint32_t v : job.mesh.triangles[t]) box[c].extend(job.mesh.points[v]);
    return box;
  };
  const std::vector<bool> keep = judge_islands(job, facts);
  if (std::find(keep.begin(), keep.end(), false) != keep.end()) {
    if (job.proof) job.proof = keep_components(*job.proof, job.mesh, comps, keep);
    job.mesh = keep_components(std::move(job.mesh), comps, keep);
  }
}

}  // namespace tpmsfill::detail
