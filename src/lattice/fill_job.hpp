/// @file fill_job.hpp
/// @brief fill()'s state between its stages, shared by the whole-grid path (fill.cpp), the slab
/// path (fill_slabs.cpp), the streamed path (fill_stream.cpp) and the islands stage
/// (fill_islands.cpp).
#pragma once

#include <filesystem>
#include <functional>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "core/job_progress.hpp"
#include "lattice/field_job.hpp"
#include "tpmsfill/error.hpp"
#include "tpmsfill/fill.hpp"
#include "tpmsfill/io.hpp"
#include "tpmsfill/mesh/components.hpp"
#include "tpmsfill/mesh/validate.hpp"
#include "tpmsfill/report.hpp"
#include "tpmsfill/sampling/classify.hpp"
#include "tpmsfill/sampling/marching_cubes.hpp"
#include "tpmsfill/sampling/spatial.hpp"
#include "tpmsfill/sampling/voxel.hpp"

namespace tpmsfill::detail {

// The job's state between stages: what later stages need of earlier ones.
struct Job {
  const TriangleSoup& model;
  const FillOptions& options;
  FillResult& result;
  /// > 0: the field and marching cubes go slab by slab, this many node planes each
  int slab_planes = 0;
  FillReport& report;
  detail::JobProgress job_progress;
  Progress* progress;  ///< what the stages report to: job_progress, or null without a caller's
  StageClock stage;
  Grid grid;
  Occupancy occupancy;
  std::optional<MeshIndex> tree;
  std::optional<Field> depth;
  Field phi;  ///< the whole grid's (not in slabs)
  /// In slabs: the inside and solid (φ < 0) masks as runs, what islands need of them
  Regions inside_runs, solid_runs;
  TriangleSoup mesh;
  /// What marching cubes proved of `mesh` (FillOptions::Validation::Proof, the whole grid);
  /// dropped by anything that changes the mesh but islands, which carry it over.
  std::optional<ConstructionProof> proof;
  /// In slabs: the one part made every plane and SlabMarchingCubes proved them all
  /// (FillOptions::Validation::Proof), so the mesh, held or streamed, needs no search.
  bool slabs_proved = false;

  Job(const TriangleSoup& m, const FillOptions& o, FillResult& r,
      std::vector<detail::PlannedStage> plan, int slabs)
      : model(m),
        options(o),
        result(r),
        slab_planes(slabs),
        report(r.report),
        job_progress(o.progress, std::move(plan)),
        progress(job_progress.get()),
        stage(r.report, job_progress) {}
};

/// How fill() will use memory: the whole grid at once (slab_planes 0) or slabs; the estimate;
/// and, when nothing fits the budget, the refusal (thrown after the review).
struct MemoryPlan {
  int slab_planes = 0;
  std::uint64_t bytes = 0;
  std::string refusal;
};

/// The slab path: classification, field and marching cubes slab by slab, the masks islands
/// need kept as runs (fill_slabs.cpp). Leaves job.mesh as the whole-grid path makes it.
void mesh_in_slabs(Job& job);

/// Called after each slab's marching cubes with what it appended to the part's mesh; it may
/// take the finished points and triangles out (SlabMarchingCubes::drop_points).
using AfterSlab = std::function<void(SlabMarchingCubes&, TriangleSoup&)>;

/// The slab path's work on node planes [first, end) (all of them, or one process's share):
/// `agree` settles the auto inside rule across shares (unset: this share alone).
FillPart mesh_planes(Job& job, int first, int end, const std::function<bool(bool)>& agree,
                     const AfterSlab& after_slab);

/// What islands are judged by, per component of the lattice (numbered by first triangle, as
/// mesh_components numbers them).
struct ComponentFacts {
  std::vector<Components::Info> info;
  std::vector<Vec3> first_centroid;  ///< of each one's first triangle
  /// The boxes of the components that keep[c] drops (the others' may be left empty).
  std::function<std::vector<Box3>(const std::vector<bool>& keep)> boxes;
};

/// The streamed path's last stage: the mesh validated and written as it passes.
inline constexpr const char* kValidateAndWrite = "validate and write";

/// The refusal when nothing of the lattice is left.
inline constexpr const char* kEmptyLattice =
    "the lattice is empty: no part of the model is thicker than the lattice's struts at this "
    "voxel size (try a smaller --voxel or a larger --cell)";

/// @throws ValidationError  `v` is not valid: nothing is written (the problems, one sentence)
inline void require_valid_lattice(const MeshValidity& v) {
  if (v.valid()) return;
  std::string why;
  for (const std::string& p : v.problems()) why += (why.empty() ? "" : "; ") + p;
  throw ValidationError("the lattice failed validation, nothing was written: " + why);
}

/// Which components stay: cavities counted, islands (pieces that are not the main body of
/// their part of the model) dropped unless kept; the report's island and cavity figures and
/// warnings (fill_islands.cpp).
std::vector<bool> judge_islands(const Job& job, const ComponentFacts& comps);

/// The islands stage on the mesh held whole (job.mesh): its components judged, the islands
/// dropped (fill_islands.cpp).
void remove_islands(Job& job);

/// The slab path with the mesh streamed to `path` rather than held: slabs' triangles spill to
/// a temporary file beside `path`; components are labelled across slabs; islands are judged;
/// then the mesh is validated window by window and written as validated (MeshWriter), the
/// same bytes as write_mesh of fill()'s mesh. Nothing is left at `path` unless it is valid.
/// (fill_stream.cpp)
void fill_streamed(Job& job, const std::filesystem::path& path, const WriteOptions& write);

/// fill_streamed() for a job split into parts (fill_parts_to_file): `count` parts from
/// `next_part`, in plane order, each spilled as it arrives. (fill_stream.cpp)
void fill_parts_streamed(Job& job, int count, const std::function<FillPart()>& next_part,
                         const std::filesystem::path& path, const WriteOptions& write);

/// Parts covering the grid in order into the job: the mesh, the runs and the report's
/// classification figures, as mesh_in_slabs leaves them.
/// @throws InputError  the parts do not cover the grid in order, or nothing is inside
void join_parts(Job& job, std::vector<FillPart> parts);

/// The stages of the slab path up to islands, for the job's plan.
std::vector<PlannedStage> slab_stages(const FillOptions& options);

}  // namespace tpmsfill::detail
