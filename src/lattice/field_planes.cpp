// fill()'s field on a run of planes: classify a wider slab, band it, then distances, depth and
// the design on the planes only.
#include "lattice/field_planes.hpp"

#include <algorithm>
#include <cmath>
#include <optional>
#include <thread>

#include <tbb/parallel_for.h>

#include "core/stage_progress.hpp"
#include "lattice/field_job.hpp"
#include "tpmsfill/lattice/compose.hpp"
#include "tpmsfill/sampling/distance.hpp"
#include "tpmsfill/sampling/voxel.hpp"

namespace tpmsfill::detail {

int halo_planes(const FillOptions& o, const LatticeDesign& design, double spacing) {
  const double reach = depth_reach(design);
  return std::max(band_width(o, spacing),
                  reach > 0 ? static_cast<int>(std::ceil(reach / spacing)) + 1 : 0);
}

Grid widened(const Grid& planes, int halo) {
  Grid g = planes;
  g.dims[2] += 2 * halo;
  g.z_offset -= halo;
  return g;
}

SampledPlanes sample_planes(const FieldPlanes& job, const Grid& planes) {
  const FillOptions& o = job.options;
  const Grid slab = widened(planes, job.halo);
  const std::size_t per_plane = static_cast<std::size_t>(planes.dims[0]) * planes.dims[1];
  const std::size_t first = per_plane * static_cast<std::size_t>(job.halo);
  const std::size_t count = planes.node_count();
  SampledPlanes out;
  Occupancy occ = classify_grid(job.tree, slab, {.rule = job.rule});
  out.unbalanced_rows = occ.unbalanced_rows;
  out.counts.assign(occ.planes.begin() + job.halo, occ.planes.begin() + job.halo + planes.dims[2]);
  out.inside = Mask{planes, std::vector<std::uint8_t>(occ.inside.values.begin() + first,
                                                      occ.inside.values.begin() + first + count)};
  // Depth below the surface: nodes beyond the slab count as inside, so the distance is exact
  // wherever it is within the halo, and deeper ones read the ramps' far end either way.
  std::optional<Field> depth;
  if (depth_reach(job.design) > 0 && job.depth) {
    depth = job.depth(out.inside);
  } else if (depth_reach(job.design) > 0) {
    const Field edt = distance_transform(occ.inside, /*beyond_grid_set=*/true);
    depth = Field{
        planes, std::vector<float>(edt.values.begin() + first, edt.values.begin() + first + count)};
  }
  const FieldSource lattice = design_source(job.design, depth ? &*depth : nullptr);
  const ComposeOptions compose = compose_options(o, nullptr);
  if (o.full_field) {
    const Field d = signed_distance_field(job.tree, out.inside);
    out.band_nodes = count;
    out.band_per_plane.assign(static_cast<std::size_t>(planes.dims[2]), per_plane);
    out.phi = compose_field(d, lattice, compose);
    return out;
  }
  const Band band = band_voxels(occ.inside, {band_width(o, planes.spacing)});
  occ.inside = Mask{};  // what the planes need of it is copied
  const auto lo = std::lower_bound(band.nodes.begin(), band.nodes.end(), first);
  const auto hi = std::lower_bound(lo, band.nodes.end(), first + count);
  Band on_planes{planes, std::vector<std::uint64_t>(lo, hi)};
  for (std::uint64_t& n : on_planes.nodes) n -= first;
  out.band_nodes = on_planes.nodes.size();
  out.band_per_plane.assign(static_cast<std::size_t>(planes.dims[2]), 0);
  for (std::uint64_t n : on_planes.nodes) ++out.band_per_plane[n / per_plane];
  const std::vector<float> d = band_distances(job.tree, out.inside, on_planes);
  out.phi = compose_field(out.inside, on_planes, d, lattice, compose);
  return out;
}

std::vector<PlannedStage> index_stages(const FillOptions& o) {
  const InsideRule rule = o.inside.value_or(InsideRule::Winding);
  std::vector<PlannedStage> plan;
  if (rule == InsideRule::Parity || !o.inside) plan.push_back({"spatial", 10});
  if (!o.inside) plan.push_back({"classify", 5});
  if (rule == InsideRule::Winding) plan.insert(plan.end(), {{"clean", 5}, {"spatial", 10}});
  return plan;
}

std::size_t slabs_at_once() {
  const unsigned cores = std::max(1u, std::thread::hardware_concurrency());
  return std::clamp<std::size_t>(cores, 1, 8);
}

bool any_unbalanced(const MeshIndex& tree, std::uint64_t count,
                    const std::function<Grid(std::uint64_t)>& grid_of, Progress* progress) {
  const std::size_t at_once = slabs_at_once();
  for (std::uint64_t first = 0; first < count; first += at_once) {
    const std::size_t n = static_cast<std::size_t>(std::min<std::uint64_t>(at_once, count - first));
    std::vector<std::uint64_t> rows(n);
    tbb::parallel_for(std::size_t{0}, n, [&](std::size_t b) {
      rows[b] =
          classify_grid(tree, grid_of(first + b), {.rule = InsideRule::Winding}).unbalanced_rows;
    });
    for (std::uint64_t u : rows)
      if (u) return true;
    report_or_cancel(progress, static_cast<double>(first + n) / static_cast<double>(count));
  }
  return false;
}

}  // namespace tpmsfill::detail
