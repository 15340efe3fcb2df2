/// @file field_planes.hpp
/// @brief fill()'s field on a run of whole planes, without the rest of the grid: what slice()
/// samples per layer and fill() per slab when the grid does not fit in memory.
///
/// A node's φ depends on its row's classification (one ray), on whether some node within the
/// band's width is on the other side (the band), on the depth below the surface (depth ramps)
/// and on the node itself. So the planes are classified together with `halo` planes on each
/// side, and every value comes out as fill() computes it on the whole grid, bit for bit where
/// the planes are a slab of fill()'s grid (Grid::z_offset).
#pragma once

#include <cstdint>
#include <functional>
#include <optional>
#include <vector>

#include "core/job_progress.hpp"
#include "tpmsfill/error.hpp"
#include "tpmsfill/fill.hpp"
#include "tpmsfill/lattice/design.hpp"
#include "tpmsfill/mesh/clean.hpp"
#include "tpmsfill/progress.hpp"
#include "tpmsfill/report.hpp"
#include "tpmsfill/sampling/classify.hpp"
#include "tpmsfill/sampling/spatial.hpp"
#include "tpmsfill/types.hpp"

namespace tpmsfill::detail {

/// What sampling needs, settled once per job.
struct FieldPlanes {
  const MeshIndex& tree;
  InsideRule rule;
  const FillOptions& options;
  const LatticeDesign& design;  ///< resolved (resolve_design)
  int halo = 1;                 ///< halo_planes()
  /// Depth below the surface on the planes from their inside mask, for planes off fill()'s
  /// grid (slice's layers): unset, the depth comes from the halo, which must then reach as deep
  /// as the design's depth ramps (halo_planes()).
  std::function<Field(const Mask& inside)> depth = {};
};

/// Planes on each side that make the planes' φ fill()'s: the band's half-width, and the depth
/// (in planes, plus one) that the design's depth ramps read.
int halo_planes(const FillOptions& options, const LatticeDesign& design, double spacing);

struct SampledPlanes {
  Field phi;                                   ///< on the planes
  Mask inside;                                 ///< on the planes
  std::vector<Occupancy::PlaneCounts> counts;  ///< per plane
  std::uint64_t band_nodes = 0;                ///< exact distances computed (on the planes)
  std::vector<std::uint64_t> band_per_plane;   ///< of those, per plane
  /// Rows of the planes and their halo whose crossings do not balance (the auto inside rule's
  /// reason to clean the input).
  std::uint64_t unbalanced_rows = 0;
};

/// The planes widened by `halo` planes on each side: the slab that is classified.
Grid widened(const Grid& planes, int halo);

/// φ, inside and the classification's counts on `planes` (whole x-y planes of fill()'s grid,
/// or any grid of whole planes with its spacing and x-y nodes).
SampledPlanes sample_planes(const FieldPlanes& job, const Grid& planes);

}  // namespace tpmsfill::detail

namespace tpmsfill::detail {

/// The model as the inside rule needs it indexed: as it is, or cleaned with its holes capped.
/// The tree may read the model's points in place: the model outlives it.
struct IndexedModel {
  std::optional<CleanResult> cleaned;
  std::optional<MeshIndex> tree;
};

/// Cleans `model`, caps its holes and indexes both, as fill() does for the winding rule;
/// `stage(name, work)` runs and times each step.
/// @throws InputError  nothing is left after cleaning
template <class Stage>
void index_cleaned(const TriangleSoup& model, IndexedModel& m, JobReport& report, Stage&& stage) {
  m.tree.reset();
  stage("clean", [&] { m.cleaned.emplace(clean_soup(model, {})); });
  report.clean = m.cleaned->report;
  if (m.cleaned->soup.triangles.empty())
    throw InputError("the mesh encloses no volume: no triangle has three distinct corners");
  stage("spatial",
        [&] { m.tree.emplace(build_index(m.cleaned->soup, {.hole_caps = &m.cleaned->caps})); });
}

/// The auto inside rule's test over `count` slabs (grid_of(s)), a few at a time: whether some
/// row of them finds the model open or inside out. Stops at the first that does.
/// @throws Cancelled  when progress says so (reported as the fraction of slabs tested)
bool any_unbalanced(const MeshIndex& tree, std::uint64_t count,
                    const std::function<Grid(std::uint64_t)>& grid_of, Progress* progress);

/// Slabs or layers worked on at once: enough to keep the cores busy between the stages' own
/// parallel loops, few enough that their memory stays small.
std::size_t slabs_at_once();

/// The stages index_for_rule() runs for the options' inside rule, for a job's plan.
std::vector<PlannedStage> index_stages(const FillOptions& options);

/// The model indexed as fill's inside rule needs it: as it is for parity and auto, cleaned and
/// capped for winding, and for auto too when a row of one of `count` slabs (grid_of(s)) finds
/// it open or inside out (the test's stage "classify"; `agree`, when set, settles the answer
/// across processes). `stage(name, work)` runs and times each step.
template <class Stage>
void index_for_rule(const TriangleSoup& model, const FillOptions& o, IndexedModel& m,
                    JobReport& report, Stage&& stage, std::uint64_t count,
                    const std::function<Grid(std::uint64_t)>& grid_of,
                    const std::function<bool(bool)>& agree, Progress* progress) {
  const InsideRule rule = o.inside.value_or(InsideRule::Winding);
  report.inside_rule = inside_name(rule);
  if (rule == InsideRule::Winding && o.inside) return index_cleaned(model, m, report, stage);
  // `model` outlives the job: the tree reads an STL's corners in place.
  stage("spatial", [&] { m.tree.emplace(build_index(model, {.borrow_points = true})); });
  if (o.inside) return;  // parity
  bool unbalanced = false;
  stage("classify", [&] {
    unbalanced = any_unbalanced(*m.tree, count, grid_of, progress);
    if (agree) unbalanced = agree(unbalanced);
  });
  if (unbalanced) index_cleaned(model, m, report, stage);
}

}  // namespace tpmsfill::detail
