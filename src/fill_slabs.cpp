// fill()'s slab path: the grid a few node planes at a time, for jobs whose grid does not fit
// in memory. Each slab's φ is what the whole grid's would be (detail/field_planes), marching
// cubes numbers its points as the whole grid's would (SlabMarchingCubes), and islands get the
// inside and solid masks as runs: the mesh comes out bit for bit the same.
#include <algorithm>
#include <optional>

#include "detail/field_planes.hpp"
#include "detail/fill_job.hpp"
#include "detail/job_settings.hpp"
#include "detail/stage_progress.hpp"
#include "tpmsfill/marching_cubes.hpp"

namespace tpmsfill::detail {
namespace {

// The planes slab s reads: the ones it owns and the two above them.
Grid slab_planes(const Grid& grid, int per_slab, std::uint64_t s) {
  Grid g = grid;
  const int first = static_cast<int>(s) * per_slab;
  const int last = std::min(first + per_slab + 1, grid.dims[2] - 1);
  g.dims[2] = last - first + 1;
  g.z_offset = first;
  return g;
}

// The first `owned` planes of a slab's mask.
Mask owned_planes(const Mask& m, int owned) {
  Grid g = m.grid;
  g.dims[2] = owned;
  return {g, std::vector<std::uint8_t>(
                 m.values.begin(), m.values.begin() + static_cast<std::ptrdiff_t>(g.node_count()))};
}

}  // namespace

std::vector<PlannedStage> slab_stages(const FillOptions& o) {
  const InsideRule rule = o.inside.value_or(InsideRule::Winding);
  std::vector<PlannedStage> plan;
  if (rule == InsideRule::Parity || !o.inside) plan.push_back({"spatial", 10});
  if (!o.inside) plan.push_back({"classify", 5});
  if (rule == InsideRule::Winding) plan.insert(plan.end(), {{"clean", 5}, {"spatial", 10}});
  plan.push_back({"slabs", 35});
  return plan;
}

void mesh_in_slabs(Job& job) {
  const FillOptions& o = job.options;
  FillReport& r = job.report;
  const InsideRule rule = o.inside.value_or(InsideRule::Winding);
  r.inside_rule = inside_name(rule);
  const LatticeDesign& design = job.result.resolved.design;
  const Grid& grid = job.grid;
  const int per_slab = job.slab_planes, nz = grid.dims[2];
  const std::uint64_t slabs = static_cast<std::uint64_t>((nz + per_slab - 1) / per_slab);
  const int halo = halo_planes(o, design, grid.spacing);
  auto stage = [&](const char* name, auto&& work) { job.stage(name, work); };

  IndexedModel indexed;
  if (rule == InsideRule::Parity || !o.inside)
    stage("spatial", [&] { indexed.tree.emplace(build_index(job.model)); });
  if (!o.inside) {
    bool unbalanced = false;
    stage("classify", [&] {
      unbalanced = any_unbalanced(
          *indexed.tree, slabs,
          [&](std::uint64_t s) { return widened(slab_planes(grid, per_slab, s), halo); },
          job.progress);
    });
    if (unbalanced) index_cleaned(job.model, indexed, r, stage);
  } else if (rule == InsideRule::Winding) {
    index_cleaned(job.model, indexed, r, stage);
  }

  stage("slabs", [&] {
    const FieldPlanes field{*indexed.tree, rule, o, design, halo};
    SlabMarchingCubes mc(grid);
    job.inside_runs = job.solid_runs = Regions{};
    job.inside_runs.grid = job.solid_runs.grid = grid;
    Occupancy::PlaneCounts total;
    for (std::uint64_t s = 0; s < slabs; ++s) {
      const Grid planes = slab_planes(grid, per_slab, s);
      const int owned = std::min(per_slab, nz - planes.z_offset);
      SampledPlanes sampled = sample_planes(field, planes);
      for (int k = 0; k < owned; ++k) {
        total += sampled.counts[static_cast<std::size_t>(k)];
        if (!o.full_field) r.band_nodes += sampled.band_per_plane[static_cast<std::size_t>(k)];
      }
      append_runs(job.inside_runs, owned_planes(sampled.inside, owned));
      Mask solid{sampled.phi.grid, std::vector<std::uint8_t>(sampled.phi.values.size())};
      for (std::size_t n = 0; n < solid.values.size(); ++n)
        solid.values[n] = sampled.phi.values[n] < 0;
      append_runs(job.solid_runs, owned_planes(solid, owned));
      mc.add(sampled.phi, owned, job.mesh);
      report_or_cancel(job.progress, static_cast<double>(s + 1) / static_cast<double>(slabs));
    }
    r.distance_queries = o.full_field ? r.samples : r.band_nodes;
    record_classification(o, total, !job.inside_runs.runs.empty(), r);
  });
}

}  // namespace tpmsfill::detail
