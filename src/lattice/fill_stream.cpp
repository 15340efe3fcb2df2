// fill() streamed into a file: the slab path (fill_slabs.cpp) without ever holding the mesh.
// Three passes, so that the file holds exactly what write_mesh of fill()'s mesh would:
// 1. slabs: each slab's finished cell layers spill to a temporary file as records of a few
//    layers: points, triangles, and a component label for each. Labels come from a union-find
//    over the record's points; a record's first node layer, shared with the record below,
//    joins their labels in one union-find over labels (small: a few per component per record).
// 2. islands: one read of the records gives every component's figures in triangle order, with
//    mesh_components' arithmetic, so islands are judged exactly as fill() judges them.
// 3. validate and write: each record is validated as a window (mesh/validate_window) with
//    the layers of its neighbours that its items touch, its kept points and triangles written
//    by MeshWriter as they pass. Validation's sums run in fill()'s triangle order and chunks.
// A record's triangles read the next record's first node layer, so passes 2 and 3 hold three
// records: the one at work and its two neighbours.
// A job split among processes (fill_parts_to_file, mpirun) spills each part's layers as the
// part arrives, the same way; then the same passes 2 and 3.
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <concepts>
#include <cstdio>
#include <cstring>
#include <functional>
#include <optional>
#include <string>

#include "core/disjoint_sets.hpp"
#include "core/index_limits.hpp"
#include "core/stage_progress.hpp"
#include "io/file_bytes.hpp"
#include "lattice/field_job.hpp"
#include "lattice/fill_job.hpp"
#include "mesh/mesh_measures.hpp"
#include "mesh/validate_window.hpp"
#include "tpmsfill/error.hpp"
#include "tpmsfill/mesh/validate.hpp"

namespace tpmsfill::detail {
namespace {

constexpr std::uint32_t kNone = kNoIndex;
// Triangles a record holds at most (beyond its first layer): small enough that three records
// are a small buffer, large enough that their windows' fixed costs do not matter.
constexpr std::uint64_t kRecordTriangles = std::uint64_t{1} << 18;
constexpr std::size_t kSumChunk = 4096;  // validate_mesh()'s chunk for its sums

// The spill: a scratch file beside the output (io/file_bytes), buffered.
class SpillFile {
 public:
  explicit SpillFile(const std::filesystem::path& output) : output_(output) {
    const int fd = open_scratch_file(output, "spill");
    file_ = ::fdopen(fd, "w+b");
    if (!file_) {
      const int e = errno;
      ::close(fd);
      errno = e;
      fail("cannot open its temporary file");
    }
    std::setvbuf(file_, nullptr, _IOFBF, std::size_t{1} << 20);
  }
  SpillFile(const SpillFile&) = delete;
  SpillFile& operator=(const SpillFile&) = delete;
  ~SpillFile() { std::fclose(file_); }

  template <class T>
  void put(const T* data, std::size_t n) {
    if (n && std::fwrite(data, sizeof(T), n, file_) != n) fail("cannot write its temporary file");
  }
  template <class T>
  void get(T* data, std::size_t n) {
    if (n && std::fread(data, sizeof(T), n, file_) != n) fail("cannot read its temporary file");
  }
  void rewind() {
    if (std::fflush(file_) != 0 || std::fseek(file_, 0, SEEK_SET) != 0)
      fail("cannot read its temporary file");
  }

 private:
  [[noreturn]] void fail(const std::string& what) const {
    std::string message = "cannot write ";
    message += output_.string();
    message += ": ";
    message += what;
    message += ": ";
    message += errno ? std::strerror(errno) : "unexpected end";
    throw IoError(message);
  }
  std::filesystem::path output_;
  std::FILE* file_ = nullptr;
};

// Cell layers [r0, r1) of the lattice: their triangles, and the points of node layers [r0, r1)
// (the last record: up to the grid's top), each with a component label.
struct Record {
  std::uint64_t first_point = 0;          // id of points[0]
  std::uint64_t second_layer_point = 0;   // first id of node layer r0 + 1
  std::uint64_t last_layer_point = 0;     // first id of node layer r1 - 1
  std::uint64_t first_triangle = 0;       // index of triangles[0] in the lattice before islands
  std::uint64_t last_layer_triangle = 0;  // index of cell layer r1 - 1's first triangle
  std::vector<Vec3> points;
  std::vector<std::uint32_t> point_label;  // kNone: used by no triangle
  std::vector<Triangle> triangles;
  std::vector<std::uint32_t> triangle_label;
  // Pass 3 only, not spilled: each point's id in the output (kNone: dropped with an island).
  std::vector<std::uint32_t> new_id;

  std::uint64_t end_point() const { return first_point + points.size(); }

  void put(SpillFile& f) const {
    const std::uint64_t head[7] = {first_point,     second_layer_point,  last_layer_point,
                                   first_triangle,  last_layer_triangle, points.size(),
                                   triangles.size()};
    f.put(head, 7);
    f.put(points.data(), points.size());
    f.put(point_label.data(), point_label.size());
    f.put(triangles.data(), triangles.size());
    f.put(triangle_label.data(), triangle_label.size());
  }
  void get(SpillFile& f) {
    std::uint64_t head[7];
    f.get(head, 7);
    first_point = head[0];
    second_layer_point = head[1];
    last_layer_point = head[2];
    first_triangle = head[3];
    last_layer_triangle = head[4];
    points.resize(head[5]);
    point_label.resize(head[5]);
    triangles.resize(head[6]);
    triangle_label.resize(head[6]);
    f.get(points.data(), points.size());
    f.get(point_label.data(), point_label.size());
    f.get(triangles.data(), triangles.size());
    f.get(triangle_label.data(), triangle_label.size());
  }
};

// The layers of the mesh made so far: node layers below next_plane with their points and cell
// layers below next_plane with their triangles, where each starts (the whole mesh's ids).
// SlabMarchingCubes says it of one process's slabs; fill parts say it of theirs.
template <class Layers>
concept MadeLayers = requires(const Layers& l, int k) {
  { l.next_plane() } -> std::convertible_to<int>;
  { l.first_point(k) } -> std::convertible_to<std::uint64_t>;
  { l.first_triangle(k) } -> std::convertible_to<std::uint64_t>;
};

// Pass 1, called as layers are made: records the cell layers whose points all exist, then lets
// go of what no later layer reads.
class Spiller {
 public:
  Spiller(SpillFile& file, int nz) : file_(file), nz_(nz) {}

  // After each slab's marching cubes.
  void operator()(SlabMarchingCubes& mc, TriangleSoup& mesh) {
    mc.drop_points(mesh, consume(mc, mesh));
  }

  // Records what `made` finished of `mesh`, which holds the triangles from the first not yet
  // recorded and the points from the first a later layer reads; takes the recorded triangles
  // out and returns the first point id still needed (the caller drops those below it).
  template <MadeLayers Layers>
  std::uint64_t consume(const Layers& made, TriangleSoup& mesh) {
    const bool done = made.next_plane() == nz_;
    // Cell layer k reads node layers k and k + 1: those below `complete` are finished.
    const int complete = done ? nz_ - 1 : made.next_plane() - 1;
    while (next_layer_ < complete) {
      int r1 = next_layer_ + 1;
      while (r1 < complete &&
             made.first_triangle(r1 + 1) - made.first_triangle(next_layer_) <= kRecordTriangles)
        ++r1;
      record(made, mesh, next_layer_, r1, done && r1 == complete);
      next_layer_ = r1;
    }
    const std::uint64_t keep_triangle = made.first_triangle(complete);
    mesh.triangles.erase(
        mesh.triangles.begin(),
        mesh.triangles.begin() + static_cast<std::ptrdiff_t>(keep_triangle - held_triangle_));
    held_triangle_ = keep_triangle;
    held_point_ = done ? made.first_point(nz_) : made.first_point(complete);
    return held_point_;
  }

  DisjointSets labels{0};
  Box3 box;  // of the points some triangle uses, as marching cubes made them
  std::uint64_t records = 0;

 private:
  template <MadeLayers Layers>
  void record(const Layers& mc, const TriangleSoup& mesh, int r0, int r1, bool last) {
    Record rec;
    const std::uint64_t p0 = mc.first_point(r0), p1 = mc.first_point(last ? nz_ : r1);
    const std::uint64_t reach = last ? p1 : mc.first_point(r1 + 1);  // what its triangles read
    const std::uint64_t t0 = mc.first_triangle(r0), t1 = mc.first_triangle(r1);
    rec.first_point = p0;
    rec.second_layer_point = mc.first_point(r0 + 1);
    rec.last_layer_point = mc.first_point(r1 - 1);
    rec.first_triangle = t0;
    rec.last_layer_triangle = mc.first_triangle(r1 - 1);
    auto points_at = [&](std::uint64_t id) {
      return mesh.points.begin() + static_cast<std::ptrdiff_t>(id - held_point_);
    };
    rec.points.assign(points_at(p0), points_at(p1));
    rec.triangles.assign(mesh.triangles.begin() + static_cast<std::ptrdiff_t>(t0 - held_triangle_),
                         mesh.triangles.begin() + static_cast<std::ptrdiff_t>(t1 - held_triangle_));

    // Components within the record, through its points and the next layer's.
    const std::size_t n = reach - p0;
    DisjointSets local(n);
    std::vector<std::uint8_t> used(n, 0);
    for (const Triangle& t : rec.triangles) {
      const std::uint32_t a = static_cast<std::uint32_t>(t[0] - p0),
                          b = static_cast<std::uint32_t>(t[1] - p0),
                          c = static_cast<std::uint32_t>(t[2] - p0);
      local.unite(a, b);
      local.unite(a, c);
      used[a] = used[b] = used[c] = 1;
    }
    std::vector<std::uint32_t> root_label(n, kNone);
    auto label_of = [&](std::size_t p) {
      std::uint32_t& l = root_label[local.find(static_cast<std::uint32_t>(p))];
      if (l == kNone) l = labels.add();
      return l;
    };
    rec.triangle_label.reserve(rec.triangles.size());
    for (const Triangle& t : rec.triangles) rec.triangle_label.push_back(label_of(t[0] - p0));
    // The record below labelled this record's first node layer: the same components.
    const std::size_t first_layer = std::min<std::size_t>(seam_.size(), n);
    for (std::size_t p = 0; p < first_layer; ++p)
      if (seam_[p] != kNone && used[p]) labels.unite(seam_[p], label_of(p));
    rec.point_label.resize(rec.points.size());
    for (std::size_t p = 0; p < rec.points.size(); ++p) {
      rec.point_label[p] = used[p] ? label_of(p) : p < first_layer ? seam_[p] : kNone;
      if (rec.point_label[p] != kNone) box.extend(rec.points[p]);
    }
    seam_.assign(n - (p1 - p0), kNone);
    for (std::size_t p = p1 - p0; p < n; ++p)
      if (used[p]) seam_[p - (p1 - p0)] = label_of(p);
    rec.put(file_);
    ++records;
  }

  SpillFile& file_;
  int nz_;
  int next_layer_ = 0;                                // the first cell layer not yet recorded
  std::uint64_t held_point_ = 0, held_triangle_ = 0;  // ids of mesh.points[0], triangles[0]
  std::vector<std::uint32_t> seam_;  // labels of the next record's first node layer's points
};

// Reads the spilled records in order; calls prepare(record) on each as it is read, then
// visit(previous, record, next) with its neighbours (null at the ends).
template <class Prepare, class Visit>
void for_each_record(SpillFile& file, std::uint64_t count, Progress* progress,
                     const Prepare& prepare, const Visit& visit) {
  file.rewind();
  // The record leaving the three is read into again: its storage is reused, not faulted in
  // afresh for each record (under --memory every large block is a fresh mapping).
  std::optional<Record> prev, cur, next, spare;
  auto read = [&](std::optional<Record>& into) {
    if (spare)
      into = std::move(spare);
    else
      into.emplace();
    spare.reset();
    into->get(file);
    prepare(*into);
  };
  if (count) read(next);
  for (std::uint64_t i = 0; i < count; ++i) {
    spare = std::move(prev);
    prev = std::move(cur);
    cur = std::move(next);
    next.reset();
    if (i + 1 < count) read(next);
    visit(prev ? &*prev : nullptr, *cur, next ? &*next : nullptr);
    report_or_cancel(progress, static_cast<double>(i + 1) / static_cast<double>(count));
  }
}

// The record holding point `id` among a record and its neighbours.
const Record& holder(std::uint64_t id, const Record* prev, const Record& cur, const Record* next) {
  if (id < cur.first_point) return *prev;
  return id < cur.end_point() ? cur : *next;
}

struct Tally {
  ComponentFacts facts;
  std::vector<std::uint32_t> of_label;  // per label: its component
  std::vector<Box3> box;                // per component, as marching cubes made its points
  std::vector<std::uint64_t> points;    // per component
};

// Pass 2: every component's figures as mesh_components() computes them on fill()'s mesh (in
// triangle order, about the centre of its points' box).
Tally tally_components(SpillFile& file, Spiller& spill, Progress* progress) {
  Tally t;
  std::vector<std::uint32_t> of_root(spill.labels.size(), kNone);
  const Vec3 centre = spill.box.centre();
  auto component = [&](std::uint32_t label) {
    std::uint32_t& c = of_root[spill.labels.find(label)];
    if (c == kNone) {
      c = static_cast<std::uint32_t>(t.facts.info.size());
      t.facts.info.emplace_back();
      t.facts.first_centroid.emplace_back();
      t.box.emplace_back();
      t.points.push_back(0);
    }
    return c;
  };
  for_each_record(
      file, spill.records, progress, [](Record&) {},
      [&](const Record* prev, const Record& cur, const Record* next) {
        auto at = [&](std::uint32_t id) -> const Vec3& {
          const Record& r = holder(id, prev, cur, next);
          return r.points[id - r.first_point];
        };
        for (std::size_t i = 0; i < cur.triangles.size(); ++i) {
          const Triangle& tri = cur.triangles[i];
          const std::uint32_t c = component(cur.triangle_label[i]);
          Components::Info& info = t.facts.info[c];
          const Vec3 a = at(tri[0]), b = at(tri[1]), d = at(tri[2]);
          if (info.triangles++ == 0) {
            info.first_triangle = static_cast<std::uint32_t>(cur.first_triangle + i);
            t.facts.first_centroid[c] = (1.0 / 3.0) * (a + b + d);
          }
          info.volume += six_volume(centre, a, b, d) / 6;
          info.area += double_area(a, b, d) / 2;
        }
        for (std::size_t p = 0; p < cur.points.size(); ++p) {
          if (cur.point_label[p] == kNone) continue;
          const std::uint32_t c = component(cur.point_label[p]);
          const Vec3 q = cur.points[p];
          ++t.points[c];
          t.box[c].extend(q);
        }
      });
  // Every label's component once, so the next pass looks them up instead of finding roots.
  t.of_label.resize(spill.labels.size());
  for (std::uint32_t l = 0; l < t.of_label.size(); ++l)
    t.of_label[l] = of_root[spill.labels.find(l)];
  return t;
}

// What the windows found, summed in the order validate_mesh() reports it.
struct WindowSums {
  MeshValidity r;
  std::vector<std::array<std::uint32_t, 2>> pairs;
  bool by_cells = true;
  void add(const WindowValidation& w, const std::vector<std::uint32_t>& final_index,
           std::size_t max_examples, bool searched) {
    r.vertices += w.vertices;
    r.border_edges += w.border;
    r.non_manifold_edges += w.non_manifold;
    r.inconsistent_edges += w.inconsistent;
    r.non_manifold_vertices += w.pinched;
    r.duplicate_points += w.duplicates;
    for (std::uint32_t t : w.degenerate_examples)
      if (r.degenerate_triangle_examples.size() < max_examples)
        r.degenerate_triangle_examples.push_back(final_index[t]);
    r.degenerate_triangles += w.degenerate;
    auto append = [&](auto& to, const auto& from) {
      for (const auto& e : from)
        if (to.size() < max_examples) to.push_back(e);
    };
    auto append_edges = [&](std::vector<EdgeLocation>& to, const std::vector<EdgeLocation>& from) {
      for (const EdgeLocation& e : from)
        if (to.size() < max_examples) to.push_back({e.ends, final_index[e.triangle]});
    };
    append_edges(r.border_edge_examples, w.border_examples);
    append_edges(r.non_manifold_edge_examples, w.non_manifold_examples);
    append_edges(r.inconsistent_edge_examples, w.inconsistent_examples);
    append(r.non_manifold_vertex_examples, w.pinched_examples);
    if (searched) {
      r.self_intersecting_pairs = r.self_intersecting_pairs.value_or(0) + w.intersecting_pairs;
      by_cells = by_cells && w.searched_by_cells;
      for (const TrianglePair& p : w.intersection_examples)
        pairs.push_back({final_index[p[0]], final_index[p[1]]});
    }
  }
};

// Pass 3: the kept mesh validated a window at a time and written as it passes, with the sums
// validate_mesh() makes (volume and area in its triangle order and chunks, per component too).
class ValidatingWriter {
 public:
  ValidatingWriter(const Job& job, const Tally& tally, const std::vector<bool>& keep,
                   MeshWriter& writer, Vec3 centre)
      : job_(job),
        tally_(tally),
        keep_(keep),
        writer_(writer),
        centre_(centre),
        component_volume_(keep.size(), 0.0) {}

  // As a record is read: its points rounded as fill() rounds them, the kept ones numbered and
  // written.
  void prepare(Record& rec) {
    std::vector<Vec3>& out = points_out_;
    out.clear();
    rec.new_id.assign(rec.points.size(), kNone);
    for (std::size_t p = 0; p < rec.points.size(); ++p) {
      Vec3& q = rec.points[p];
      q = round_coordinates(job_.options.rounding, q);
      if (kept(rec.point_label[p])) {
        rec.new_id[p] = static_cast<std::uint32_t>(next_id_++);
        out.push_back(q);
      }
    }
    writer_.add_points(out);
  }

  // The record's window: its points and its neighbours' that its items touch, the kept
  // triangles of the record below's last cell layer (carried) and of its own.
  void visit(const Record* prev, const Record& cur, const Record* next) {
    const std::uint64_t first = prev ? prev->last_layer_point : cur.first_point;
    const std::uint64_t end = next ? next->second_layer_point : cur.end_point();
    // Buffers kept from record to record (cleared, their storage reused).
    TriangleSoup& window = window_;
    window.points.clear();
    window.triangles.clear();
    std::vector<Vec3>& kept_points = kept_points_;  // the writer's window: ids from first_new on
    kept_points.clear();
    std::uint32_t first_new = kNone;
    window.points.reserve(end - first);
    for (std::uint64_t id = first; id < end; ++id) {
      const Record& h = holder(id, prev, cur, next);
      const std::size_t p = id - h.first_point;
      window.points.push_back(h.points[p]);
      if (h.new_id[p] != kNone) {
        if (first_new == kNone) first_new = h.new_id[p];
        kept_points.push_back(h.points[p]);
      }
    }
    auto local = [&](const Triangle& t) {
      return Triangle{static_cast<std::uint32_t>(t[0] - first),
                      static_cast<std::uint32_t>(t[1] - first),
                      static_cast<std::uint32_t>(t[2] - first)};
    };
    std::vector<std::uint32_t>& final_index = final_index_;
    final_index = carried_final_;
    if (prev)
      for (std::size_t i = prev->last_layer_triangle - prev->first_triangle;
           i < prev->triangles.size(); ++i)
        if (kept(prev->triangle_label[i])) window.triangles.push_back(local(prev->triangles[i]));
    const std::size_t carried = window.triangles.size();
    std::vector<Triangle>& out = triangles_out_;
    out.clear();
    carried_final_.clear();
    for (std::size_t i = 0; i < cur.triangles.size(); ++i) {
      if (!kept(cur.triangle_label[i])) continue;
      const Triangle& t = cur.triangles[i];
      const Triangle l = local(t);
      window.triangles.push_back(l);
      const auto index = static_cast<std::uint32_t>(written_++);
      final_index.push_back(index);
      if (i >= cur.last_layer_triangle - cur.first_triangle) carried_final_.push_back(index);
      add_sums(window.points[l[0]], window.points[l[1]], window.points[l[2]],
               component(cur.triangle_label[i]));
      Triangle renumbered;
      for (int k = 0; k < 3; ++k) {
        const Record& h = holder(t[k], prev, cur, next);
        renumbered[k] = h.new_id[t[k] - h.first_point];
      }
      out.push_back(renumbered);
    }
    // Proved slabs are only measured, as validate_mesh() measures a proved mesh.
    if (!job_.slabs_proved) {
      const bool search = searched();
      const WindowValidation w =
          validate_window(window, {cur.first_point - first, cur.end_point() - first}, carried,
                          job_.grid, max_examples_, search);
      sums_.add(w, final_index, max_examples_, search);
    }
    writer_.add_triangles(out, kept_points, first_new == kNone ? 0 : first_new);
  }

  // The whole mesh's report, once every record was visited.
  MeshValidity report() {
    MeshValidity v = std::move(sums_.r);
    v.triangles = written_;
    const double volume = (volume_ + chunk_volume_) / 6;
    v.volume = volume;
    v.area = (area_ + chunk_area_) / 2;
    for (std::size_t c = 0; c < keep_.size(); ++c) v.components += keep_[c];
    v.outward = v.components > 0 && volume > 0;
    for (std::size_t c = 0; c < keep_.size(); ++c)
      if (keep_[c] && component_volume_[c] == 0) v.outward = false;
    if (job_.slabs_proved) {
      // Every point marching cubes makes is a corner of the triangles around its edge.
      v.vertices = next_id_;
      v.validated_by = ValidatedBy::Construction;
      if (job_.options.check_self_intersections) v.self_intersecting_pairs = 0;
    }
    if (searched()) {
      v.searched_by_cells = sums_.by_cells;
      std::sort(sums_.pairs.begin(), sums_.pairs.end());
      if (sums_.pairs.size() > max_examples_) sums_.pairs.resize(max_examples_);
      v.self_intersection_examples = std::move(sums_.pairs);
    }
    return v;
  }

 private:
  // Slabs proved by construction (and islands only drop whole components) need no search.
  bool searched() const { return job_.options.check_self_intersections && !job_.slabs_proved; }
  std::uint32_t component(std::uint32_t label) const { return tally_.of_label[label]; }
  bool kept(std::uint32_t label) const { return label != kNone && keep_[component(label)]; }
  void add_sums(Vec3 a, Vec3 b, Vec3 c, std::uint32_t comp) {
    const double six = six_volume(centre_, a, b, c);
    chunk_volume_ += six;
    chunk_area_ += double_area(a, b, c);
    component_volume_[comp] += six;
    if (written_ % kSumChunk == 0) {
      volume_ += chunk_volume_;
      area_ += chunk_area_;
      chunk_volume_ = chunk_area_ = 0;
    }
  }

  const Job& job_;
  const Tally& tally_;
  const std::vector<bool>& keep_;
  MeshWriter& writer_;
  Vec3 centre_;
  std::size_t max_examples_ = ValidateOptions{}.max_examples;
  WindowSums sums_;
  std::vector<double> component_volume_;
  double volume_ = 0, area_ = 0, chunk_volume_ = 0, chunk_area_ = 0;
  std::uint64_t next_id_ = 0, written_ = 0;
  std::vector<std::uint32_t> carried_final_;  // output indices of the carried triangles
  std::vector<Vec3> points_out_, kept_points_;
  std::vector<std::uint32_t> final_index_;
  TriangleSoup window_;
  std::vector<Triangle> triangles_out_;
};

// Islands, validation and writing once every layer is spilled and the parts joined; the job
// finished as fill() finishes it.
void finish_streamed(Job& job, SpillFile& file, Spiller& spill, const std::filesystem::path& path,
                     const WriteOptions& write) {
  // Islands, judged on every component's figures.
  Tally tally;
  std::vector<bool> keep;
  job.stage("islands", [&] {
    tally = tally_components(file, spill, job.progress);
    tally.facts.boxes = [&tally](const std::vector<bool>&) { return tally.box; };
    keep = judge_islands(job, tally.facts);
  });
  job.inside_runs = job.solid_runs = Regions{};
  std::uint64_t points = 0, triangles = 0;
  Box3 box;  // of the kept points as written (rounding is monotone: the box's corners)

  for (std::size_t c = 0; c < keep.size(); ++c)
    if (keep[c]) {
      points += tally.points[c];
      triangles += tally.facts.info[c].triangles;
      for (const Vec3& corner : {tally.box[c].min, tally.box[c].max})
        box.extend(round_coordinates(job.options.rounding, corner));
    }
  if (triangles == 0) throw InputError(kEmptyLattice);
  if (!fits_32bit_ids(points) || !fits_32bit_ids(triangles))
    throw InputError("the lattice has more than 2^32 - 1 points or triangles; use a coarser grid");

  MeshWriter writer(path, points, triangles, write);
  ValidatingWriter out(job, tally, keep, writer, box.centre());
  job.stage(kValidateAndWrite, [&] {
    for_each_record(
        file, spill.records, job.progress, [&](Record& rec) { out.prepare(rec); },
        [&](const Record* prev, const Record& cur, const Record* next) {
          out.visit(prev, cur, next);
        });
  });
  job.report.validation = out.report();
  require_valid_lattice(job.report.validation);
  writer.set_metadata(lattice_metadata(job.report, write.metadata));
  writer.commit();
  warn_porosity(job.result.resolved.design, job.report.porosity(), job.report);
  job.job_progress.finish();
}

// The layers the parts received so far made, in the joined mesh's ids.
struct JoinedLayers {
  int next = 0;
  std::vector<std::uint64_t> points, triangles;  // per plane
  int next_plane() const { return next; }
  std::uint64_t first_point(int k) const { return points[static_cast<std::size_t>(k)]; }
  std::uint64_t first_triangle(int k) const { return triangles[static_cast<std::size_t>(k)]; }
};

// Part p appended to the joined layers and to `window` (ids shifted by the points before it, as
// join_parts shifts them).
void append_part(FillPart& p, int nz, JoinedLayers& made, TriangleSoup& window,
                 std::uint64_t& points, std::uint64_t& triangles) {
  const std::size_t planes = static_cast<std::size_t>(p.end_plane - p.first_plane);
  if (p.first_plane != made.next || p.end_plane <= p.first_plane || p.end_plane > nz ||
      p.layer_points.size() != planes + 1 || p.layer_triangles.size() != planes + 1 ||
      p.layer_points.back() != p.mesh.points.size() ||
      p.layer_triangles.back() != p.mesh.triangles.size())
    throw InputError("fill_parts: the parts do not cover the grid's planes in order");
  if (!fits_32bit_ids(points + p.mesh.points.size()))
    throw InputError("fill_parts: more than 2^32 - 1 points; use a coarser grid");
  for (std::size_t k = 0; k <= planes; ++k) {
    made.points[static_cast<std::size_t>(p.first_plane) + k] = points + p.layer_points[k];
    made.triangles[static_cast<std::size_t>(p.first_plane) + k] = triangles + p.layer_triangles[k];
  }
  window.points.insert(window.points.end(), p.mesh.points.begin(), p.mesh.points.end());
  for (Triangle t : p.mesh.triangles) {
    for (std::uint32_t& v : t) v += static_cast<std::uint32_t>(points);
    window.triangles.push_back(t);
  }
  points += p.mesh.points.size();
  triangles += p.mesh.triangles.size();
  made.next = p.end_plane;
  p.mesh = {};
}

}  // namespace

void fill_streamed(Job& job, const std::filesystem::path& path, const WriteOptions& write) {
  SpillFile file(path);
  Spiller spill(file, job.grid.dims[2]);
  std::vector<FillPart> parts;
  parts.push_back(mesh_planes(job, 0, job.grid.dims[2], {}, std::ref(spill)));
  join_parts(job, std::move(parts));
  finish_streamed(job, file, spill, path, write);
}

void fill_parts_streamed(Job& job, int count, const std::function<FillPart()>& next_part,
                         const std::filesystem::path& path, const WriteOptions& write) {
  const int nz = job.grid.dims[2];
  SpillFile file(path);
  Spiller spill(file, nz);
  const std::size_t planes = static_cast<std::size_t>(nz) + 1;
  JoinedLayers made{0, std::vector<std::uint64_t>(planes), std::vector<std::uint64_t>(planes)};
  TriangleSoup window;  // points from id `held` on; the triangles not yet recorded
  std::uint64_t held = 0, points = 0, triangles = 0;
  std::vector<FillPart> parts;  // their meshes spilled: runs and counts for join_parts
  job.stage("join", [&] {
    for (int i = 0; i < count; ++i) {
      parts.push_back(next_part());
      append_part(parts.back(), nz, made, window, points, triangles);
      const std::uint64_t keep = spill.consume(made, window);
      window.points.erase(window.points.begin(),
                          window.points.begin() + static_cast<std::ptrdiff_t>(keep - held));
      held = keep;
    }
    join_parts(job, std::move(parts));
  });
  finish_streamed(job, file, spill, path, write);
}

}  // namespace tpmsfill::detail
