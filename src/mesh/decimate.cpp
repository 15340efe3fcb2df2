// Stage "decimate": CGAL edge collapse held within a distance of the input both ways, validated,
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
#include <CGAL/Surface_mesh_simplification/edge_collapse.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <limits>
#include <string>
#include <utility>
#include <vector>

#include "core/disjoint_sets.hpp"
#include "core/format_numbers.hpp"
#include "core/stage_progress.hpp"
#include "mesh/cgal_types.hpp"
#include "mesh/internal/self_intersections.hpp"
#include "mesh/internal/tolerance_cover.hpp"
#include "mesh/soup_topology.hpp"
#include "mesh/surface_deviation.hpp"
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
constexpr std::uint32_t kNone = std::numeric_limits<std::uint32_t>::max();

using detail::format;

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
/// so the filters judge the point that will be written.
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

// --- the two-sided distance check ------------------------------------------------------------

using FaceIndex = SurfaceMesh::Face_index;
using HalfedgeIndex = SurfaceMesh::Halfedge_index;

Vec3 vec(const Point3& p) {
  return {p.x(), p.y(), p.z()};
}

using detail::Corners;

/// Per-index marks that are all cleared at once: next() starts a fresh set in O(1) (a stamp per
/// index, compared with the current one; the stamps are reset when the counter wraps).
class Marks {
 public:
  explicit Marks(std::size_t n = 0) : stamp_(n, 0) {}
  void next() {
    if (++current_ == 0) {
      std::fill(stamp_.begin(), stamp_.end(), 0);
      current_ = 1;
    }
  }
  bool marked(std::size_t i) const { return stamp_[i] == current_; }
  void mark(std::size_t i) { stamp_[i] = current_; }
  /// Marks `i`; false when it was marked already.
  bool mark_once(std::size_t i) {
    if (marked(i)) return false;
    mark(i);
    return true;
  }

 private:
  std::vector<std::uint32_t> stamp_;
  std::uint32_t current_ = 0;
};

/// The faces a collapse of halfedge `h` changes: the two it removes, and every other face
/// around its two ends, each by its halfedge that ends at v0 or v1 (its corners: that end, then
/// the next two). Both filters (DistanceBound, IntersectionGuard) read it.
struct CollapseRegion {
  VertexIndex v0, v1;
  std::array<FaceIndex, 2> removed;
  std::vector<HalfedgeIndex> kept;

  void of(const SurfaceMesh& sm, HalfedgeIndex h) {
    v0 = sm.source(h);
    v1 = sm.target(h);
    removed = {sm.face(h), sm.face(sm.opposite(h))};
    kept.clear();
    for (VertexIndex v : {v0, v1})
      for (HalfedgeIndex g : sm.halfedges_around_target(sm.halfedge(v)))
        if (sm.face(g) != removed[0] && sm.face(g) != removed[1]) kept.push_back(g);
  }
};

/// Holds the simplified surface and the input within the tolerance of each other, both ways,
/// at every point (decimate.hpp, "The distance bound").
///
/// Input → result: every input triangle is proven to lie within the tolerance of a few faces
/// of the result (detail::ToleranceCover, piece by piece); it remembers those faces, and each
/// of them keeps it in its list of dependants. A collapse changes the faces around its edge
/// (the region), so it is accepted only if every dependant of the region is proven again,
/// against the region's new triangles, the unchanged faces across its outer edges and the
/// unchanged faces its last proof used; it then depends on the faces its new proof used. At
/// first face i of the Surface_mesh is input triangle i (the distance is 0).
///
/// Result → input: every new triangle of the region is proven to lie within the tolerance of
/// the input triangles depending on the region and on the faces across its outer edges (the
/// input never moves, so an old proof stays true).
///
/// Both proofs only look near the collapse, so they may refuse a collapse that a global search
/// would allow, never the other way round. The Surface_mesh keeps face indices while
/// collapsing (a removed face is only marked), so the lists are indexed by face.
class DistanceBound {
 public:
  DistanceBound(const TriangleSoup& input, double tolerance)
      : mesh_(input),
        dependants_(input.triangles.size()),
        depends_on_(input.triangles.size()),
        seen_(input.triangles.size()),
        slot_(input.triangles.size(), 0),
        slotted_(input.triangles.size()),
        cover_(tolerance) {
    for (std::uint32_t t = 0; t < dependants_.size(); ++t) dependants_[t] = depends_on_[t] = {t};
  }

  /// Whether collapsing halfedge `h` (source into target) with the kept vertex at `p` keeps
  /// both surfaces within the tolerance; if so, what the proofs used is kept for commit().
  bool accepts(const SurfaceMesh& sm, const CollapseRegion& region, HalfedgeIndex h, Vec3 p) {
    gather_region(sm, region, p);
    if (news_ == 0) return false;
    uses_.clear();
    use_begin_.assign(1, 0);
    owner_.clear();
    for (std::uint32_t t : inputs_)
      if (!input_within_result(sm, t)) return false;
    // Each new triangle against the dependants (those nearest to it first) and the input
    // triangles of the outer faces.
    input_.resize(inputs_.size() + around_.size());
    for (std::size_t i = 0; i < inputs_.size(); ++i) input_[i] = input_corners(inputs_[i]);
    for (std::size_t i = 0; i < around_.size(); ++i)
      input_[inputs_.size() + i] = input_corners(around_[i]);
    for (std::uint32_t k = 0; k < news_; ++k) {
      candidates_.clear();
      for (std::uint32_t i = 0; i < inputs_.size(); ++i)
        if (owner_[i] == k) candidates_.push_back(i);
      for (std::uint32_t i = 0; i < input_.size(); ++i)
        if (i >= inputs_.size() || owner_[i] != k) candidates_.push_back(i);
      unused_.clear();  // the input never moves: nothing to remember
      if (!cover_.within(result_[k], input_, candidates_, unused_)) return false;
    }
    planned_ = h;
    return true;
  }

  /// Moves the dependants to the faces their new proofs used; `h` is the halfedge the last
  /// accepts() accepted, now collapsed.
  void commit(HalfedgeIndex h) {
    if (h != planned_) throw Error("decimate: a collapse nobody checked (internal)");
    for (FaceIndex f : removed_) std::vector<std::uint32_t>().swap(dependants_[f]);
    for (std::uint32_t k = 0; k < news_; ++k) dependants_[result_face_[k]].clear();
    for (std::size_t i = 0; i < inputs_.size(); ++i) {
      const std::uint32_t t = inputs_[i];
      std::vector<std::uint32_t>& uses = depends_on_[t];
      // Unchanged faces the old proof used and the new one does not: t leaves their lists.
      for (std::uint32_t f : uses) {
        if (changes(f)) continue;
        bool kept = false;
        for (std::uint32_t u = use_begin_[i]; u < use_begin_[i + 1] && !kept; ++u)
          kept = result_face_[uses_[u]] == f;
        if (!kept) std::erase(dependants_[f], t);
      }
      uses.clear();
      for (std::uint32_t u = use_begin_[i]; u < use_begin_[i + 1]; ++u) {
        const std::uint32_t f = result_face_[uses_[u]];
        std::vector<std::uint32_t>& list = dependants_[f];
        // A region face's list was emptied above; an unchanged face's may hold t already.
        if (uses_[u] < news_ || std::find(list.begin(), list.end(), t) == list.end())
          list.push_back(t);
        uses.push_back(f);
      }
    }
    planned_ = HalfedgeIndex();
  }

 private:
  static double squared(Vec3 q, const Corners& t) {
    return detail::squared_distance_to_triangle(q, t[0], t[1], t[2]);
  }

  Corners input_corners(std::uint32_t t) const {
    const Triangle& tri = mesh_.triangles[t];
    return {mesh_.points[tri[0]], mesh_.points[tri[1]], mesh_.points[tri[2]]};
  }

  static Corners face_corners(const SurfaceMesh& sm, HalfedgeIndex g) {  // g's target first
    const HalfedgeIndex n = sm.next(g);
    return {vec(sm.point(sm.target(g))), vec(sm.point(sm.target(n))),
            vec(sm.point(sm.target(sm.next(n))))};
  }

  /// Whether face `f` is removed or moved by the collapse being checked.
  bool changes(std::uint32_t f) const {
    return f == static_cast<std::uint32_t>(removed_[0]) ||
           f == static_cast<std::uint32_t>(removed_[1]) || (slotted_.marked(f) && slot_[f] < news_);
  }

  /// Adds face `f`'s triangle (as it is now) to the result triangles of this collapse, once.
  std::uint32_t slot(std::uint32_t f, const Corners& corners) {
    if (slotted_.mark_once(f)) {
      slot_[f] = static_cast<std::uint32_t>(result_.size());
      result_.push_back(corners);
      result_face_.push_back(f);
    }
    return slot_[f];
  }

  /// The new triangle nearest to `c`'s centroid.
  std::uint32_t nearest(const Corners& c) const {
    const Vec3 g = (1.0 / 3.0) * (c[0] + c[1] + c[2]);
    std::uint32_t best_k = 0;
    double best = squared(g, result_[0]);
    for (std::uint32_t k = 1; k < news_ && best > 0; ++k) {
      const double d = squared(g, result_[k]);
      if (d < best) best = d, best_k = k;
    }
    return best_k;
  }

  /// Proves input triangle `t` within the tolerance of the region's new triangles (the nearest
  /// first), the outer faces and the unchanged faces its last proof used; records the
  /// triangles the proof used (uses_, use_begin_) and the nearest new one (owner_).
  bool input_within_result(const SurfaceMesh& sm, std::uint32_t t) {
    const Corners c = input_corners(t);
    const std::uint32_t owner = nearest(c);
    owner_.push_back(owner);
    candidates_.assign(1, owner);
    for (std::uint32_t k = 0; k < around_begin_; ++k)
      if (k != owner) candidates_.push_back(k);
    for (std::uint32_t f : depends_on_[t])
      if (!changes(f)) {
        const std::uint32_t k = slot(f, face_corners(sm, sm.halfedge(FaceIndex(f))));
        if (k >= around_begin_) candidates_.push_back(k);  // not an outer face, listed above
      }
    const std::size_t first = uses_.size();
    if (!cover_.within(c, result_, candidates_, uses_)) return false;
    const auto begin = uses_.begin() + static_cast<std::ptrdiff_t>(first);
    std::sort(begin, uses_.end());
    uses_.erase(std::unique(begin, uses_.end()), uses_.end());
    use_begin_.push_back(static_cast<std::uint32_t>(uses_.size()));
    return true;
  }

  /// Adds the dependants of face `f` not yet seen in this collapse to `out`.
  void gather(FaceIndex f, std::vector<std::uint32_t>& out) {
    for (std::uint32_t t : dependants_[f])
      if (seen_.mark_once(t)) out.push_back(t);
  }

  /// The region's faces after the collapse (their moved corner at `p`) and the dependants of
  /// them and of the removed faces; then the faces across the region's outer edges (unchanged)
  /// and their dependants.
  void gather_region(const SurfaceMesh& sm, const CollapseRegion& region, Vec3 p) {
    seen_.next();
    slotted_.next();
    removed_ = region.removed;
    result_.clear();
    result_face_.clear();
    inputs_.clear();
    around_.clear();
    for (FaceIndex f : removed_) gather(f, inputs_);
    for (HalfedgeIndex g : region.kept) {
      Corners c = face_corners(sm, g);
      c[0] = p;
      slot(sm.face(g), c);
      gather(sm.face(g), inputs_);
    }
    news_ = static_cast<std::uint32_t>(result_.size());
    for (HalfedgeIndex g : region.kept) {
      const HalfedgeIndex across = sm.opposite(sm.next(sm.next(g)));  // the edge away from v
      const FaceIndex f = sm.face(across);
      if (changes(f) || slotted_.marked(f)) continue;
      slot(f, face_corners(sm, across));
      gather(f, around_);
    }
    around_begin_ = static_cast<std::uint32_t>(result_.size());
  }

  const TriangleSoup& mesh_;  ///< the input
  /// Per face: the input triangles whose proof uses it.
  std::vector<std::vector<std::uint32_t>> dependants_;
  /// Per input triangle: the faces its proof uses.
  std::vector<std::vector<std::uint32_t>> depends_on_;
  Marks seen_;                       ///< input triangles gathered in this collapse
  std::vector<std::uint32_t> slot_;  ///< per face: its index in result_ (when slotted_)
  Marks slotted_;                    ///< faces in result_ in this collapse
  // The collapse being checked:
  std::array<FaceIndex, 2> removed_;
  std::uint32_t news_ = 0;                  ///< result_[0, news_): the region's faces after it
  std::uint32_t around_begin_ = 0;          ///< result_[news_, around_begin_): the outer faces
  std::vector<Corners> result_;             ///< then the other unchanged faces that proofs use
  std::vector<std::uint32_t> result_face_;  ///< the face of each result_
  std::vector<std::uint32_t> inputs_;       ///< the dependants of the region and the removed faces
  std::vector<std::uint32_t> around_;       ///< the dependants of the outer faces not in inputs_
  std::vector<Corners> input_;              ///< the corners of inputs_, then of around_
  std::vector<std::uint32_t> owner_;        ///< per inputs_: the new triangle nearest to it
  std::vector<std::uint32_t> uses_;         ///< per inputs_ (use_begin_): result_ its proof used
  std::vector<std::uint32_t> use_begin_;
  std::vector<std::uint32_t> candidates_;
  std::vector<std::uint32_t> unused_;
  detail::ToleranceCover cover_;
  HalfedgeIndex planned_;
};

/// Keeps the simplified surface free of self-intersections: a collapse is refused when one of
/// the triangles it makes meets another triangle of the mesh, decided as validation decides
/// it (detail::triangle_pair_intersects: exact predicates, shared corners by index). The other
/// triangles are found through a uniform grid of cells, each listing the faces whose bounding
/// box met it when they were last moved (an entry can be stale: every candidate's current
/// box is tested).
class IntersectionGuard {
 public:
  IntersectionGuard(const SurfaceMesh& sm, const TriangleSoup& input) {
    Vec3 lo = input.points.front(), hi = lo;
    double edges = 0;
    for (const Vec3& p : input.points) {
      lo = {std::min(lo.x, p.x), std::min(lo.y, p.y), std::min(lo.z, p.z)};
      hi = {std::max(hi.x, p.x), std::max(hi.y, p.y), std::max(hi.z, p.z)};
    }
    for (const Triangle& t : input.triangles)
      edges += norm(input.points[t[1]] - input.points[t[0]]);
    // Cells of about 4 mean edges (a decimated face spans a few), at most 2^23 of them.
    cell_ = std::max(4 * edges / static_cast<double>(input.triangles.size()), 1e-300);
    const Vec3 size = hi - lo;
    while ((size.x / cell_ + 1) * (size.y / cell_ + 1) * (size.z / cell_ + 1) > 8388608.0)
      cell_ *= 1.25;
    origin_ = lo;
    for (int a = 0; a < 3; ++a) dim_[a] = static_cast<std::int64_t>(size[a] / cell_) + 1;
    cells_.resize(static_cast<std::size_t>(dim_[0] * dim_[1] * dim_[2]));
    changing_ = Marks(sm.number_of_faces());
    visited_ = Marks(sm.number_of_faces());
    for (FaceIndex f : sm.faces()) insert(sm, f);
  }

  /// Whether collapsing halfedge `h` with the kept vertex at `p` leaves the mesh free of
  /// self-intersections (given it was before).
  bool accepts(const SurfaceMesh& sm, const CollapseRegion& region, Vec3 p) {
    // The new triangles, by vertex index with v0 and v1 both named v1, at `p`.
    const std::uint32_t kept = static_cast<std::uint32_t>(region.v1);
    news_.clear();
    for (HalfedgeIndex g : region.kept) {
      const HalfedgeIndex n = sm.next(g);
      news_.push_back({kept, static_cast<std::uint32_t>(sm.target(n)),
                       static_cast<std::uint32_t>(sm.target(sm.next(n)))});
    }
    auto point = [&](std::uint32_t v) { return v == kept ? p : vec(sm.point(VertexIndex(v))); };
    // The new triangles against each other.
    for (std::size_t i = 0; i < news_.size(); ++i)
      for (std::size_t j = i + 1; j < news_.size(); ++j)
        if (meet(news_[i], news_[j], point)) return false;
    // Against every other face near them (none holds v0 or v1: those all change or go).
    changing_.next();
    for (FaceIndex f : region.removed) changing_.mark(f);
    for (HalfedgeIndex g : region.kept) changing_.mark(sm.face(g));
    for (const Triangle& t : news_) {
      const Box b = box(Corners{point(t[0]), point(t[1]), point(t[2])});
      visited_.next();
      for_cells(b, [&](std::vector<std::uint32_t>& cell) {
        for (std::uint32_t f : cell) {
          const FaceIndex face(f);
          // Once per new triangle (a face can be filed under several cells).
          if (changing_.marked(f) || sm.is_removed(face) || !visited_.mark_once(f)) continue;
          const Triangle other = face_vertices(sm, face);
          if (!overlap(b, box(Corners{point(other[0]), point(other[1]), point(other[2])})))
            continue;
          if (meet(t, other, point)) return false;
        }
        return true;
      });
      if (found_) {
        found_ = false;
        return false;
      }
    }
    return true;
  }

  /// Files the faces around the kept vertex `v` under the cells their new boxes meet.
  void commit(const SurfaceMesh& sm, VertexIndex v) {
    for (FaceIndex f : sm.faces_around_target(sm.halfedge(v))) insert(sm, f);
  }

 private:
  struct Box {
    Vec3 lo, hi;
  };

  static Box box(const Corners& t) {
    Box b{t[0], t[0]};
    for (const Vec3& p : t) {
      b.lo = {std::min(b.lo.x, p.x), std::min(b.lo.y, p.y), std::min(b.lo.z, p.z)};
      b.hi = {std::max(b.hi.x, p.x), std::max(b.hi.y, p.y), std::max(b.hi.z, p.z)};
    }
    return b;
  }

  static bool overlap(const Box& a, const Box& b) {
    return a.lo.x <= b.hi.x && b.lo.x <= a.hi.x && a.lo.y <= b.hi.y && b.lo.y <= a.hi.y &&
           a.lo.z <= b.hi.z && b.lo.z <= a.hi.z;
  }

  static Triangle face_vertices(const SurfaceMesh& sm, FaceIndex f) {
    const HalfedgeIndex h = sm.halfedge(f);
    return {static_cast<std::uint32_t>(sm.target(h)),
            static_cast<std::uint32_t>(sm.target(sm.next(h))),
            static_cast<std::uint32_t>(sm.target(sm.next(sm.next(h))))};
  }

  /// Whether triangles `a` and `b` (vertex indices; `point` gives their places) meet.
  template <class Point>
  bool meet(const Triangle& a, const Triangle& b, const Point& point) {
    // Local indices: shared corners stay shared.
    ids_.clear();
    local_.clear();
    auto local = [&](std::uint32_t v) {
      for (std::uint32_t i = 0; i < ids_.size(); ++i)
        if (ids_[i] == v) return i;
      ids_.push_back(v);
      local_.push_back(point(v));
      return static_cast<std::uint32_t>(ids_.size() - 1);
    };
    const Triangle la{local(a[0]), local(a[1]), local(a[2])};
    const Triangle lb{local(b[0]), local(b[1]), local(b[2])};
    return detail::triangle_pair_intersects(la, lb, local_);
  }

  /// Calls `visit(cell)` for every cell `b` meets while it returns true; found_ is set when a
  /// visit returned false.
  template <class Visit>
  void for_cells(const Box& b, const Visit& visit) {
    std::int64_t lo[3], hi[3];
    for (int a = 0; a < 3; ++a) {
      lo[a] = std::clamp(static_cast<std::int64_t>(std::floor((b.lo[a] - origin_[a]) / cell_)),
                         std::int64_t{0}, dim_[a] - 1);
      hi[a] = std::clamp(static_cast<std::int64_t>(std::floor((b.hi[a] - origin_[a]) / cell_)),
                         std::int64_t{0}, dim_[a] - 1);
    }
    for (std::int64_t z = lo[2]; z <= hi[2]; ++z)
      for (std::int64_t y = lo[1]; y <= hi[1]; ++y)
        for (std::int64_t x = lo[0]; x <= hi[0]; ++x)
          if (!visit(cells_[static_cast<std::size_t>((z * dim_[1] + y) * dim_[0] + x)])) {
            found_ = true;
            return;
          }
  }

  void insert(const SurfaceMesh& sm, FaceIndex f) {
    const Triangle t = face_vertices(sm, f);
    const Box b = box(Corners{vec(sm.point(VertexIndex(t[0]))), vec(sm.point(VertexIndex(t[1]))),
                              vec(sm.point(VertexIndex(t[2])))});
    const std::uint32_t id = static_cast<std::uint32_t>(f);
    for_cells(b, [&](std::vector<std::uint32_t>& cell) {
      // Drop removed faces while here; file f once.
      std::erase_if(cell, [&](std::uint32_t g) { return sm.is_removed(FaceIndex(g)); });
      if (std::find(cell.begin(), cell.end(), id) == cell.end()) cell.push_back(id);
      return true;
    });
  }

  double cell_ = 1;
  Vec3 origin_;
  std::int64_t dim_[3] = {1, 1, 1};
  std::vector<std::vector<std::uint32_t>> cells_;
  Marks changing_;  ///< faces the collapse being checked removes or moves
  Marks visited_;   ///< faces met by the new triangle being checked
  bool found_ = false;
  std::vector<Triangle> news_;
  std::vector<std::uint32_t> ids_;
  std::vector<Vec3> local_;
};

/// CGAL's filter: no edge the collapse makes is longer than the limit, no face around it
/// turns over (Bounded_normal_change_filter), and the DistanceBound holds.
struct BoundFilter {
  DistanceBound* bound;
  IntersectionGuard* guard;
  CollapseRegion* region;       ///< scratch, reused from collapse to collapse
  double max_edge_squared = 0;  ///< 0: no limit
  template <class Profile>
  boost::optional<typename Profile::Point> operator()(
      const Profile& profile, boost::optional<typename Profile::Point> p) const {
    if (p && max_edge_squared > 0)
      for (auto v : profile.link())
        if (CGAL::squared_distance(get(profile.vertex_point_map(), v), *p) > max_edge_squared)
          return {};
    p = SMS::Bounded_normal_change_filter<>()(profile, p);
    if (!p) return p;
    const SurfaceMesh& sm = profile.surface_mesh();
    region->of(sm, profile.v0_v1());
    if (!bound->accepts(sm, *region, profile.v0_v1(), vec(*p)) ||
        !guard->accepts(sm, *region, vec(*p)))
      return {};
    return p;
  }
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
  DistanceBound* bound;
  IntersectionGuard* guard;
  Visitor(RoundState* s, DistanceBound* b, IntersectionGuard* g) : state(s), bound(b), guard(g) {}
  template <class Profile>
  void OnCollapsed(const Profile& profile, VertexIndex kept) const {
    state->absorbed.unite(static_cast<std::uint32_t>(profile.v0()),
                          static_cast<std::uint32_t>(profile.v1()));
    bound->commit(profile.v0_v1());
    guard->commit(profile.surface_mesh(), kept);
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
  DistanceBound bound(input, options.tolerance);
  IntersectionGuard guard(sm, input);
  CollapseRegion region;
  SMS::edge_collapse(sm, StopPredicate{&state},
                     CGAL::parameters::get_cost(SMS::LindstromTurk_cost<SurfaceMesh>())
                         .get_placement(placement)
                         .filter(BoundFilter{&bound, &guard, &region,
                                             options.max_edge_length * options.max_edge_length})
                         .edge_is_constrained_map(lock)
                         .visitor(Visitor(&state, &bound, &guard)));
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
std::vector<std::uint32_t> offending_points(const TriangleSoup& mesh, const MeshValidity& v) {
  std::vector<std::uint32_t> points;
  const bool topology = v.border_edges > 0 || !v.manifold() || v.inconsistent_edges > 0 ||
                        v.outward != true || v.triangles == 0;
  if (topology) return points;
  for (const auto& pair : v.self_intersection_examples)
    for (std::uint32_t t : pair)
      for (std::uint32_t p : mesh.triangles[t]) points.push_back(p);
  for (std::uint32_t t : v.degenerate_triangle_examples)
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
  if (!(o.max_edge_length >= 0) || !std::isfinite(o.max_edge_length))
    throw InputError(
        format("decimate: the longest edge must be a length in mm (0: no limit), not %g",
               o.max_edge_length));
}

void add_warnings(DecimateReport& r) {
  if (r.stop == DecimateStop::Unchanged) return;  // warned where it was decided
  // The bound is proven; a measurement beyond it (more than round-off) would be a defect.
  const double excess = r.distance.hausdorff();
  if (excess > r.tolerance * (1 + 1e-9))
    r.warnings.push_back(format(
        "the measured distance between the result and the input, %.9g mm, exceeds the proven "
        "bound of %g mm: please report this mesh",
        excess, r.tolerance));
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
  const MeshValidity before = validate_mesh(welded.mesh, round_validation(options, false));
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
  r.volume_before = before.volume.value_or(0);
  r.area_before = before.area;

  RoundsOutcome outcome = run_rounds(welded.mesh, options, r);
  if (outcome.valid) {
    result.mesh = std::move(outcome.mesh);
    r.stop = outcome.target_reached ? DecimateStop::Target : DecimateStop::Tolerance;
    r.hausdorff_bound = options.tolerance;
    constexpr int kGrid = 4;
    constexpr std::size_t kSamples = 2000000;
    const detail::DistanceStats to =
        detail::surface_distances(result.mesh, welded.mesh, false, kGrid, kSamples);
    const detail::DistanceStats from =
        detail::surface_distances(welded.mesh, result.mesh, false, kGrid, kSamples);
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
  r.volume_after = r.validation.volume.value_or(0);
  r.area_after = r.validation.area;
  add_warnings(r);
  r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  detail::report_or_cancel(options.progress, 1.0);
  return result;
}

}  // namespace tpmsfill
