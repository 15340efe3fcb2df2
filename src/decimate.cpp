// Stage "decimate": CGAL edge collapse inside a polyhedral envelope of the input, validated,
// with rounds that lock the input where a round's result was not valid (see decimate.hpp).
//
// Phases: weld and validate the input; build a CGAL Surface_mesh whose vertex i is the welded
// point i; per round, collapse (serial) with a visitor that records which input vertices each
// surviving vertex absorbed (union-find over input vertex ids, which Surface_mesh keeps stable
// while it only marks removals); validate the result; where it fails, lock the absorbed input
// vertices of the offending triangles and go again. The distances are measured at the end.
#include "tpmsfill/decimate.hpp"

#include <CGAL/Surface_mesh_simplification/Edge_collapse_visitor_base.h>
#include <CGAL/Surface_mesh_simplification/Policies/Edge_collapse/Bounded_normal_change_filter.h>
#include <CGAL/Surface_mesh_simplification/Policies/Edge_collapse/Constrained_placement.h>
#include <CGAL/Surface_mesh_simplification/Policies/Edge_collapse/LindstromTurk_cost.h>
#include <CGAL/Surface_mesh_simplification/Policies/Edge_collapse/LindstromTurk_placement.h>
#include <CGAL/Surface_mesh_simplification/Policies/Edge_collapse/Polyhedral_envelope_filter.h>
#include <CGAL/Surface_mesh_simplification/edge_collapse.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <limits>
#include <string>
#include <utility>
#include <vector>

#include "detail/cgal_types.hpp"
#include "detail/disjoint_sets.hpp"
#include "detail/soup_topology.hpp"
#include "detail/stage_progress.hpp"
#include "detail/surface_deviation.hpp"
#include "tpmsfill/error.hpp"

namespace tpmsfill {
namespace {

namespace SMS = CGAL::Surface_mesh_simplification;
using detail::Kernel;
using detail::Point3;
using detail::SurfaceMesh;
using VertexIndex = SurfaceMesh::Vertex_index;
using EdgeIndex = SurfaceMesh::Edge_index;
using LockMap = SurfaceMesh::Property_map<EdgeIndex, bool>;

std::string format(const char* fmt, double a = 0, double b = 0, double c = 0, double d = 0) {
  char s[512];
  std::snprintf(s, sizeof s, fmt, a, b, c, d);
  return s;
}

// --- input ---------------------------------------------------------------------------------

/// The input with bit-identical points merged and only referenced points kept, in order of
/// their first point.
struct Welded {
  TriangleSoup mesh;
  std::uint64_t merged = 0;
};

Welded weld(const TriangleSoup& in) {
  const detail::PointMerge merge = detail::merge_equal_points(in.points);
  std::vector<std::uint8_t> referenced(in.points.size(), 0);
  for (const Triangle& t : in.triangles)
    for (std::uint32_t p : t) referenced[p] = 1;
  constexpr std::uint32_t kNone = std::numeric_limits<std::uint32_t>::max();
  std::vector<std::uint32_t> id_of_vertex(merge.first_point.size(), kNone);
  Welded w;
  std::uint64_t referenced_points = 0;
  for (std::size_t p = 0; p < in.points.size(); ++p) {
    if (!referenced[p]) continue;
    ++referenced_points;
    std::uint32_t& id = id_of_vertex[merge.vertex_of_point[p]];
    if (id != kNone) continue;
    id = static_cast<std::uint32_t>(w.mesh.points.size());
    w.mesh.points.push_back(in.points[p]);
  }
  w.mesh.triangles.reserve(in.triangles.size());
  for (const Triangle& t : in.triangles)
    w.mesh.triangles.push_back({id_of_vertex[merge.vertex_of_point[t[0]]],
                                id_of_vertex[merge.vertex_of_point[t[1]]],
                                id_of_vertex[merge.vertex_of_point[t[2]]]});
  w.merged = referenced_points - w.mesh.points.size();
  return w;
}

SurfaceMesh surface_mesh(const TriangleSoup& mesh) {
  SurfaceMesh sm;
  sm.reserve(static_cast<SurfaceMesh::size_type>(mesh.points.size()),
             static_cast<SurfaceMesh::size_type>(mesh.triangles.size() * 3 / 2),
             static_cast<SurfaceMesh::size_type>(mesh.triangles.size()));
  for (const Vec3& p : mesh.points) sm.add_vertex(detail::to_cgal(p));
  for (const Triangle& t : mesh.triangles)
    if (sm.add_face(VertexIndex(t[0]), VertexIndex(t[1]), VertexIndex(t[2])) ==
        SurfaceMesh::null_face())
      throw Error("decimate: a validated mesh did not build a Surface_mesh (internal)");
  return sm;
}

// --- the edge collapse's policies ------------------------------------------------------------

/// A placement whose points are rounded as the file will hold them (DecimateOptions::rounding),
/// so the envelope and the normal filter judge the point that will be written.
template <class Base>
class FloatPlacement : public Base {
 public:
  explicit FloatPlacement(CoordinateRounding rounding) : rounding_(rounding) {}
  template <class Profile>
  boost::optional<typename Profile::Point> operator()(const Profile& profile) const {
    boost::optional<typename Profile::Point> p = Base::operator()(profile);
    if (p && rounding_ != CoordinateRounding::None) {
      const Vec3 q = round_coordinates(rounding_, {p->x(), p->y(), p->z()});
      p = Point3(q.x, q.y, q.z);
    }
    return p;
  }

 private:
  CoordinateRounding rounding_;
};

/// What a round shares with its visitor and stop predicate (they are copied into CGAL).
struct RoundState {
  detail::DisjointSets absorbed;   ///< input vertices joined when one collapses into another
  std::size_t edge_threshold = 0;  ///< stop below this many edges (0: no target)
  bool target_reached = false;
  bool cancelled = false;
  Progress* progress = nullptr;
  std::size_t reported = 0;  ///< last whole percent reported
  explicit RoundState(std::size_t vertices) : absorbed(vertices) {}
};

struct Visitor : SMS::Edge_collapse_visitor_base<SurfaceMesh> {
  RoundState* state;
  explicit Visitor(RoundState* s) : state(s) {}
  template <class Profile>
  void OnCollapsed(const Profile& profile, VertexIndex) const {
    state->absorbed.unite(static_cast<std::uint32_t>(profile.v0()),
                          static_cast<std::uint32_t>(profile.v1()));
  }
};

struct StopPredicate {
  RoundState* state;
  template <class F, class Profile>
  bool operator()(const F&, const Profile&, std::size_t initial, std::size_t current) const {
    if (current < state->edge_threshold) return state->target_reached = true;
    if (state->progress && initial > 0) {
      const std::size_t percent = 100 * (initial - current) / initial;
      if (percent > state->reported) {
        state->reported = percent;
        if (!state->progress->report(static_cast<double>(percent) / 100.0))
          return state->cancelled = true;
      }
    }
    return false;
  }
};

/// One simplification of `input` with the vertices in `locked` held.
struct RoundResult {
  TriangleSoup mesh;
  std::vector<std::uint32_t> input_vertex;  ///< per result point: the input vertex it is
  detail::DisjointSets absorbed{0};
  bool target_reached = false;
};

RoundResult simplify(const TriangleSoup& input, const std::vector<std::uint8_t>& locked,
                     const DecimateOptions& options) {
  SurfaceMesh sm = surface_mesh(input);
  LockMap lock = sm.add_property_map<EdgeIndex, bool>("e:locked", false).first;
  for (EdgeIndex e : sm.edges())
    if (locked[sm.vertex(e, 0)] || locked[sm.vertex(e, 1)]) lock[e] = true;

  RoundState state(input.points.size());
  if (options.target_triangles > 0)
    state.edge_threshold = static_cast<std::size_t>(options.target_triangles) * 3 / 2 + 1;
  state.progress = options.progress;

  using Placement =
      SMS::Constrained_placement<FloatPlacement<SMS::LindstromTurk_placement<SurfaceMesh>>,
                                 LockMap>;
  const Placement placement(
      lock, FloatPlacement<SMS::LindstromTurk_placement<SurfaceMesh>>(options.rounding));
  // Inside the envelope, and no face around the collapse turned over (the base filter).
  const SMS::Polyhedral_envelope_filter<Kernel, SMS::Bounded_normal_change_filter<>> filter(
      options.tolerance);
  SMS::edge_collapse(sm, StopPredicate{&state},
                     CGAL::parameters::get_cost(SMS::LindstromTurk_cost<SurfaceMesh>())
                         .get_placement(placement)
                         .filter(filter)
                         .edge_is_constrained_map(lock)
                         .visitor(Visitor(&state)));
  if (state.cancelled) throw Cancelled("cancelled");

  RoundResult r;
  std::vector<std::uint32_t> id(input.points.size(), 0);  // collapses add no vertex
  for (VertexIndex v : sm.vertices()) {
    id[v] = static_cast<std::uint32_t>(r.mesh.points.size());
    const Point3& p = sm.point(v);
    r.mesh.points.push_back({p.x(), p.y(), p.z()});
    r.input_vertex.push_back(static_cast<std::uint32_t>(v));
  }
  for (SurfaceMesh::Face_index f : sm.faces()) {
    Triangle t{};
    int k = 0;
    for (VertexIndex v : sm.vertices_around_face(sm.halfedge(f))) t[k++] = id[v];
    r.mesh.triangles.push_back(t);
  }
  r.absorbed = std::move(state.absorbed);
  r.target_reached = state.target_reached;
  return r;
}

// --- rounds ----------------------------------------------------------------------------------

/// Result points that take part in what made `v` fail: corners of self-intersecting pairs and
/// degenerate triangles, and points sharing a position. Empty when the failure is of a kind
/// that cannot be put on points (topology, orientation).
std::vector<std::uint32_t> offending_points(const TriangleSoup& mesh, const ValidationReport& v) {
  std::vector<std::uint32_t> points;
  const bool topology = v.border_edges > 0 || !v.manifold() || v.inconsistent_edges > 0 ||
                        !v.outward || v.triangles == 0;
  if (topology) return points;
  for (const auto& pair : v.self_intersection_examples)
    for (std::uint32_t t : pair)
      for (std::uint32_t p : mesh.triangles[t]) points.push_back(p);
  for (std::uint32_t t : v.degenerate_examples)
    for (std::uint32_t p : mesh.triangles[t]) points.push_back(p);
  if (v.duplicate_points > 0) {
    std::vector<std::uint32_t> order(mesh.points.size());
    for (std::uint32_t i = 0; i < order.size(); ++i) order[i] = i;
    auto key = [&](std::uint32_t i) {
      const Vec3& p = mesh.points[i];
      return std::array<double, 3>{p.x + 0.0, p.y + 0.0, p.z + 0.0};  // -0 == +0
    };
    std::sort(order.begin(), order.end(),
              [&](std::uint32_t a, std::uint32_t b) { return key(a) < key(b); });
    for (std::size_t i = 1; i < order.size(); ++i)
      if (key(order[i]) == key(order[i - 1])) {
        points.push_back(order[i]);
        points.push_back(order[i - 1]);
      }
  }
  return points;
}

/// Locks the input vertices absorbed into `bad` result points, then grows the locked set by
/// `rings` rings of the input. Returns how many input vertices were newly locked.
std::uint64_t lock_region(const TriangleSoup& input, RoundResult& round,
                          const std::vector<std::uint32_t>& bad, int rings,
                          std::vector<std::uint8_t>& locked) {
  std::vector<std::uint8_t> bad_root(input.points.size(), 0);
  for (std::uint32_t p : bad) bad_root[round.absorbed.find(round.input_vertex[p])] = 1;
  std::uint64_t added = 0;
  for (std::uint32_t v = 0; v < input.points.size(); ++v)
    if (bad_root[round.absorbed.find(v)] && !locked[v]) {
      locked[v] = 1;
      ++added;
    }
  for (int ring = 0; ring < rings; ++ring) {
    std::vector<std::uint8_t> grown = locked;
    for (const Triangle& t : input.triangles)
      if (locked[t[0]] || locked[t[1]] || locked[t[2]])
        for (std::uint32_t p : t)
          if (!grown[p]) {
            grown[p] = 1;
            ++added;
          }
    locked = std::move(grown);
  }
  return added;
}

ValidateOptions round_validation(const DecimateOptions& options, bool all_examples) {
  ValidateOptions v;
  v.self_intersections = options.self_intersections;
  // Every offending triangle, to lock them all in the next round.
  if (all_examples) v.max_examples = std::numeric_limits<std::uint32_t>::max();
  v.progress = options.progress;
  return v;
}

void check_options(const DecimateOptions& o) {
  if (!(o.tolerance > 0) || !std::isfinite(o.tolerance))
    throw InputError(
        format("decimate: the tolerance must be a positive length in mm, not %g", o.tolerance));
  if (o.max_rounds < 1)
    throw InputError(format("decimate: max_rounds must be at least 1, not %g", o.max_rounds));
}

void add_warnings(DecimateReport& r) {
  if (r.stop == DecimateStop::Unchanged) return;  // warned where it was decided
  if (r.target_triangles > 0 && r.triangles_after > r.target_triangles)
    r.warnings.push_back(format(
        "the target of %.0f triangles was not reached: the tolerance of %g mm (and validity) "
        "stopped the collapse at %.0f triangles (%.2fx fewer than the input's)",
        static_cast<double>(r.target_triangles), r.tolerance,
        static_cast<double>(r.triangles_after), r.reduction()));
  else if (r.reduction() < 2)
    r.warnings.push_back(
        format("decimation removed only %.1f %% of the triangles (%.0f -> %.0f) at a tolerance of "
               "%g mm: few edges can collapse that close to the input (a larger tolerance "
               "removes more)",
               100.0 * (1.0 - 1.0 / r.reduction()), static_cast<double>(r.triangles_before),
               static_cast<double>(r.triangles_after), r.tolerance));
}

struct RoundsOutcome {
  TriangleSoup mesh;
  bool valid = false;
  bool target_reached = false;
};

/// Runs rounds until one result is valid or options.max_rounds are spent.
RoundsOutcome run_rounds(const TriangleSoup& input, const DecimateOptions& options,
                         DecimateReport& report) {
  std::vector<std::uint8_t> locked(input.points.size(), 0);
  RoundsOutcome out;
  for (int round = 1; round <= options.max_rounds; ++round) {
    detail::begin_stage(options.progress, "decimate");
    RoundResult r = simplify(input, locked, options);
    report.rounds = round;
    const bool last = round == options.max_rounds;
    report.validation = validate_mesh(r.mesh, round_validation(options, !last));
    if (report.validation.valid()) {
      out.mesh = std::move(r.mesh);
      out.valid = true;
      out.target_reached = r.target_reached;
      return out;
    }
    report.invalid_pairs.push_back(report.validation.self_intersecting_pairs.value_or(0));
    if (last) break;
    const std::vector<std::uint32_t> bad = offending_points(r.mesh, report.validation);
    if (bad.empty()) break;  // a failure that locking cannot address
    lock_region(input, r, bad, round - 1, locked);
    report.locked_vertices =
        static_cast<std::uint64_t>(std::count(locked.begin(), locked.end(), 1));
  }
  return out;
}

}  // namespace

const char* decimate_stop_name(DecimateStop stop) {
  switch (stop) {
    case DecimateStop::Tolerance:
      return "tolerance";
    case DecimateStop::Target:
      return "target";
    case DecimateStop::Unchanged:
      return "unchanged";
  }
  return "?";
}

DecimateResult decimate(const TriangleSoup& mesh, const DecimateOptions& options) {
  const auto t0 = std::chrono::steady_clock::now();
  check_options(options);
  Welded welded;
  if (options.rounding != CoordinateRounding::None) {
    TriangleSoup rounded = mesh;
    round_coordinates(options.rounding, rounded);
    welded = weld(rounded);
  } else {
    welded = weld(mesh);
  }
  const ValidationReport before = validate_mesh(welded.mesh, round_validation(options, false));
  if (!before.valid()) {
    std::string why;
    for (const std::string& p : before.problems()) why += (why.empty() ? "" : "; ") + p;
    throw InputError(
        "decimate needs a closed, outward 2-manifold without degenerate faces or "
        "self-intersections: " +
        why);
  }
  DecimateResult result;
  DecimateReport& r = result.report;
  r.tolerance = options.tolerance;
  r.target_triangles = options.target_triangles;
  r.triangles_before = before.triangles;
  r.vertices_before = before.vertices;
  r.merged_points = welded.merged;
  r.volume_before = before.volume;
  r.area_before = before.area;

  RoundsOutcome outcome = run_rounds(welded.mesh, options, r);
  if (outcome.valid) {
    result.mesh = std::move(outcome.mesh);
    r.stop = outcome.target_reached ? DecimateStop::Target : DecimateStop::Tolerance;
    r.bound_to_input = options.tolerance;
    const detail::DistanceStats to = detail::surface_distances(result.mesh, welded.mesh);
    const detail::DistanceStats from = detail::surface_distances(welded.mesh, result.mesh);
    r.distance = {to.max, to.p95, from.max, from.p95};
  } else {
    std::string why;
    for (const std::string& p : r.validation.problems()) why += (why.empty() ? "" : "; ") + p;
    r.warnings.push_back(
        format("decimation gave no valid mesh in %g round(s) (the last: ", r.rounds) + why +
        "); the input is returned unchanged");
    result.mesh = std::move(welded.mesh);
    r.validation = before;
    r.stop = DecimateStop::Unchanged;
  }
  r.triangles_after = r.validation.triangles;
  r.vertices_after = r.validation.vertices;
  r.volume_after = r.validation.volume;
  r.area_after = r.validation.area;
  add_warnings(r);
  r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  detail::report_or_cancel(options.progress, 1.0);
  return result;
}

}  // namespace tpmsfill
