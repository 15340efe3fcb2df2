// fill()'s slab path: the grid a few node planes at a time, for jobs whose grid does not fit
// in memory. Each slab's φ is what the whole grid's would be (lattice/field_planes), marching
// cubes numbers its points as the whole grid's would (SlabMarchingCubes), and islands get the
// inside and solid masks as runs: the mesh comes out bit for bit the same.
#include <algorithm>
#include <optional>

#include "core/stage_progress.hpp"
#include "lattice/field_job.hpp"
#include "lattice/field_planes.hpp"
#include "lattice/fill_job.hpp"
#include "tpmsfill/sampling/marching_cubes.hpp"

namespace tpmsfill::detail {
namespace {

// The planes slab s of the share [first, end) reads: the ones it owns (its share's last slab
// may own fewer) and the two above them.
Grid slab_planes(const Grid& grid, int first, int end, int per_slab, std::uint64_t s) {
  Grid g = grid;
  const int begin = first + static_cast<int>(s) * per_slab;
  const int last = std::min(begin + std::min(per_slab, end - begin) + 1, grid.dims[2] - 1);
  g.dims[2] = last - begin + 1;
  g.z_offset = begin;
  return g;
}

// The first `owned` planes of a slab's mask.
Mask owned_planes(const Mask& m, int owned) {
  Grid g = m.grid;
  g.dims[2] = owned;
  return {g, std::vector<std::uint8_t>(
                 m.values.begin(), m.values.begin() + static_cast<std::ptrdiff_t>(g.node_count()))};
}

// The solid (φ < 0) of the first `owned` planes of a slab's field.
Mask owned_solid(const Field& phi, int owned) {
  Grid g = phi.grid;
  g.dims[2] = owned;
  Mask m{g, std::vector<std::uint8_t>(g.node_count())};
  for (std::size_t n = 0; n < m.values.size(); ++n) m.values[n] = phi.values[n] < 0;
  return m;
}

}  // namespace

std::vector<PlannedStage> slab_stages(const FillOptions& o) {
  std::vector<PlannedStage> plan = index_stages(o);
  plan.push_back({"slabs", 35});
  return plan;
}

FillPart mesh_planes(Job& job, int first, int end, const std::function<bool(bool)>& agree,
                     const AfterSlab& after_slab) {
  const FillOptions& o = job.options;
  FillReport& r = job.report;
  const InsideRule rule = o.inside.value_or(InsideRule::Winding);
  const LatticeDesign& design = job.result.resolved.design;
  const Grid& grid = job.grid;
  const int per_slab = job.slab_planes;
  const std::uint64_t slabs = static_cast<std::uint64_t>((end - first + per_slab - 1) / per_slab);
  const int halo = halo_planes(o, design, grid.spacing);

  IndexedModel indexed;
  index_for_rule(
      job.model, o, indexed, r, job.stage, slabs,
      [&](std::uint64_t s) { return widened(slab_planes(grid, first, end, per_slab, s), halo); },
      agree, job.progress);

  FillPart part;
  part.solved_porosity = solve_porosity_with_skin(o, *indexed.tree, job.result.resolved.design, r);
  part.first_plane = first;
  part.end_plane = end;
  part.clean = r.clean;
  job.stage("slabs", [&] {
    const FieldPlanes field{*indexed.tree, rule, o, design, halo};
    SlabMarchingCubes mc(grid, {.rounding = o.rounding}, first);
    Grid share = grid;
    share.z_offset = first;
    share.dims[2] = end - first;
    part.inside_runs.grid = part.solid_runs.grid = share;
    for (std::uint64_t s = 0; s < slabs; ++s) {
      const Grid planes = slab_planes(grid, first, end, per_slab, s);
      const int owned = std::min(per_slab, end - planes.z_offset);
      SampledPlanes sampled = sample_planes(field, planes);
      for (int k = 0; k < owned; ++k) {
        part.counts.push_back(sampled.counts[static_cast<std::size_t>(k)]);
        part.band_nodes.push_back(sampled.band_per_plane[static_cast<std::size_t>(k)]);
      }
      append_runs(part.inside_runs, owned_planes(sampled.inside, owned));
      append_runs(part.solid_runs, owned_solid(sampled.phi, owned));
      mc.add(sampled.phi, owned, part.mesh);
      if (after_slab) after_slab(mc, part.mesh);
      report_or_cancel(job.progress, static_cast<double>(s + 1) / static_cast<double>(slabs));
    }
    for (int k = first; k <= end; ++k) {
      part.layer_points.push_back(mc.first_point(k));
      part.layer_triangles.push_back(mc.first_triangle(k));
    }
    job.slabs_proved = o.validation == FillOptions::Validation::Proof && first == 0 &&
                       end == grid.dims[2] && mc.unproved().empty();
  });
  return part;
}

namespace {

// `part`'s runs after `into`'s (the next planes of the same grid).
void append_regions(Regions& into, const Regions& part) {
  if (into.row_start.empty()) into.row_start.push_back(0);
  const std::uint64_t base = into.runs.size();
  for (std::size_t row = 1; row < part.row_start.size(); ++row)
    into.row_start.push_back(base + part.row_start[row]);
  into.runs.insert(into.runs.end(), part.runs.begin(), part.runs.end());
}

}  // namespace

void join_parts(Job& job, std::vector<FillPart> parts) {
  const FillOptions& o = job.options;
  FillReport& r = job.report;
  const Grid& grid = job.grid;
  int next = 0;
  for (const FillPart& p : parts) {
    if (p.first_plane != next || p.end_plane <= p.first_plane ||
        p.counts.size() != static_cast<std::size_t>(p.end_plane - p.first_plane) ||
        p.band_nodes.size() != p.counts.size())
      throw InputError("fill_parts: the parts do not cover the grid's planes in order");
    next = p.end_plane;
  }
  if (next != grid.dims[2]) throw InputError("fill_parts: the parts do not cover the grid");
  // Parts from other processes solved the skin's porosity in their own jobs; this one (rank 0's
  // join) has not, unless it made the one part itself.
  LatticeDesign& design = job.result.resolved.design;
  if (parts.front().solved_porosity && design.porosity)
    apply_solved_porosity(*parts.front().solved_porosity, design, r);
  job.inside_runs = job.solid_runs = Regions{};
  job.inside_runs.grid = job.solid_runs.grid = grid;
  Occupancy::PlaneCounts total;
  TriangleSoup& mesh = job.mesh;
  mesh = {};
  for (FillPart& p : parts) {
    // Ids shift by the points before the part: its references to the next part's first points
    // (ids from its own count on) land on them too.
    if (mesh.points.empty()) {  // the first part needs no shift: no copy either
      mesh = std::move(p.mesh);
    } else {
      const std::uint32_t offset = static_cast<std::uint32_t>(mesh.points.size());
      if (mesh.points.size() + p.mesh.points.size() > UINT32_MAX)
        throw InputError("fill_parts: more than 2^32 - 1 points; use a coarser grid");
      mesh.points.insert(mesh.points.end(), p.mesh.points.begin(), p.mesh.points.end());
      for (Triangle t : p.mesh.triangles) {
        for (std::uint32_t& v : t) v += offset;
        mesh.triangles.push_back(t);
      }
    }
    p.mesh = {};
    for (std::size_t k = 0; k < p.counts.size(); ++k) {
      total += p.counts[k];
      if (!o.full_field) r.band_nodes += p.band_nodes[k];
    }
    append_regions(job.inside_runs, p.inside_runs);
    append_regions(job.solid_runs, p.solid_runs);
    if (p.clean.input_triangles > 0) r.clean = p.clean;
  }
  r.distance_queries = o.full_field ? r.samples : r.band_nodes;
  record_classification(o, total, !job.inside_runs.runs.empty(), r);
}

void mesh_in_slabs(Job& job) {
  std::vector<FillPart> parts;
  parts.push_back(mesh_planes(job, 0, job.grid.dims[2], {}, {}));
  join_parts(job, std::move(parts));
  if (job.slabs_proved)
    job.proof = ConstructionProof{job.mesh.triangles.size(), job.mesh.points.size()};
}

}  // namespace tpmsfill::detail
