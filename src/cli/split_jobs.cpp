#include "cli/split_jobs.hpp"

#include <chrono>
#include <string>
#include <tpmsfill/error.hpp>
#include <tpmsfill/report.hpp>
#include <utility>
#include <vector>

#include "cli/ranks.hpp"
#include "cli/wire.hpp"

namespace tpmsfill::cli {
namespace {

void put_regions(std::string& out, const Regions& r) {
  wire::put(out, r.grid);
  wire::put(out, r.row_start);
  wire::put(out, r.runs);
}

void get_regions(wire::Reader& in, Regions& r) {
  in.get(r.grid);
  in.get(r.row_start);
  in.get(r.runs);
}

std::string part_bytes(const FillPart& p) {
  std::string out;
  wire::put(out, p.first_plane);
  wire::put(out, p.end_plane);
  wire::put(out, p.mesh.points);
  wire::put(out, p.mesh.triangles);
  wire::put(out, p.layer_points);
  wire::put(out, p.layer_triangles);
  put_regions(out, p.inside_runs);
  put_regions(out, p.solid_runs);
  wire::put(out, p.counts);
  wire::put(out, p.band_nodes);
  wire::put(out, p.clean);
  wire::put(out, p.seconds);
  wire::put(out, p.solved_porosity.has_value());
  if (const auto& s = p.solved_porosity) {
    wire::put(out, s->level);
    wire::put(out, s->thickness);
    wire::put(out, s->lattice_porosity);
    wire::put(out, static_cast<std::uint64_t>(s->warnings.size()));
    for (const std::string& w : s->warnings) wire::put(out, w);
  }
  return out;
}

FillPart part_from(const std::string& bytes) {
  wire::Reader in(bytes);
  FillPart p;
  in.get(p.first_plane);
  in.get(p.end_plane);
  in.get(p.mesh.points);
  in.get(p.mesh.triangles);
  in.get(p.layer_points);
  in.get(p.layer_triangles);
  get_regions(in, p.inside_runs);
  get_regions(in, p.solid_runs);
  in.get(p.counts);
  in.get(p.band_nodes);
  in.get(p.clean);
  in.get(p.seconds);
  bool solved = false;
  in.get(solved);
  if (solved) {
    FillPart::SolvedPorosity& s = p.solved_porosity.emplace();
    in.get(s.level);
    in.get(s.thickness);
    in.get(s.lattice_porosity);
    std::uint64_t n = 0;
    in.get(n);
    if (n > bytes.size()) throw std::runtime_error("wire: truncated message");
    s.warnings.resize(n);
    for (std::string& w : s.warnings) in.get(w);
  }
  return p;
}

// A layer without its plane's field: what rank 0 needs to write it.
void put_layer(std::string& out, const Layer& l) {
  wire::put(out, l.index);
  wire::put(out, l.bottom);
  wire::put(out, l.top);
  wire::put(out, l.z);
  wire::put(out, l.area);
  wire::put(out, static_cast<std::uint64_t>(l.contours.size()));
  for (const Contour& c : l.contours) {
    wire::put(out, c.area);
    wire::put(out, c.points);
  }
}

Layer get_layer(wire::Reader& in) {
  Layer l;
  in.get(l.index);
  in.get(l.bottom);
  in.get(l.top);
  in.get(l.z);
  in.get(l.area);
  std::uint64_t n = 0;
  in.get(n);
  l.contours.resize(n);
  for (Contour& c : l.contours) {
    in.get(c.area);
    in.get(c.points);
  }
  return l;
}

// The figures a share adds to the whole stack's report.
void put_report(std::string& out, const SliceReport& r) {
  wire::put(out, r.layers);
  for (std::uint64_t v :
       {r.contours, r.holes, r.points, r.segment_pairs_checked, r.job.band_nodes,
        r.job.distance_queries, r.job.rows, r.job.crossings, r.job.odd_rows, r.job.overlap_rows,
        r.job.parity_disagreements, r.job.cap_evaluations, r.job.samples})
    wire::put(out, v);
  wire::put(out, r.volume);
  wire::put(out, r.job.model_volume);
}

void add_report(wire::Reader& in, SliceReport& r) {
  std::vector<LayerSummary> layers;
  in.get(layers);
  r.layers.insert(r.layers.end(), layers.begin(), layers.end());
  for (std::uint64_t* v :
       {&r.contours, &r.holes, &r.points, &r.segment_pairs_checked, &r.job.band_nodes,
        &r.job.distance_queries, &r.job.rows, &r.job.crossings, &r.job.odd_rows,
        &r.job.overlap_rows, &r.job.parity_disagreements, &r.job.cap_evaluations, &r.job.samples}) {
    std::uint64_t add = 0;
    in.get(add);
    *v += add;
  }
  double volume = 0, model = 0;
  in.get(volume);
  in.get(model);
  r.volume += volume;
  r.job.model_volume += model;
}

}  // namespace

std::optional<FillResult> fill_on_ranks(const TriangleSoup& model, const FillOptions& options,
                                        const std::filesystem::path& path,
                                        const WriteOptions& write) {
  if (ranks() == 1) return fill_to_file(model, options, path, write);
  std::uint64_t first = 0, end = 0;
  share(static_cast<std::uint64_t>(fill_grid(model, options).dims[2]), first, end);
  FillPart part = fill_part(model, options,
                            {.first_plane = static_cast<int>(first),
                             .end_plane = static_cast<int>(end),
                             .any_unbalanced = [](bool mine) { return any(mine); }});
  if (rank() != 0) {
    send(0, part_bytes(part));
    return std::nullopt;
  }
  // Rank 0's own part first, then each rank's as it is needed: one part's mesh at a time when
  // the job streams.
  int next = 0;
  return fill_parts_to_file(
      model, options, ranks(),
      [&] { return next++ == 0 ? std::move(part) : part_from(receive(next - 1)); }, path, write);
}

std::optional<SliceReport> slice_on_ranks(const TriangleSoup& model, const FillOptions& options,
                                          SliceOptions so, std::uint64_t count,
                                          const LayerSink& sink, bool sink_everywhere) {
  if (ranks() == 1) return slice(model, options, so, sink);
  share(count, so.first_layer, so.end_layer);
  so.any_unbalanced = [](bool mine) { return any(mine); };
  std::string layers;
  std::uint64_t kept = 0;
  const bool root = rank() == 0;
  SliceReport report = slice(model, options, so, [&](const Layer& layer) {
    if (root || sink_everywhere) {
      sink(layer);
    } else {
      put_layer(layers, layer);
      ++kept;
    }
  });
  if (!root) {
    std::string bytes;
    put_report(bytes, report);
    wire::put(bytes, kept);
    wire::put(bytes, layers);
    send(0, bytes);
    return std::nullopt;
  }
  for (int r = 1; r < ranks(); ++r) {
    const std::string bytes = receive(r);
    wire::Reader in(bytes);
    add_report(in, report);
    std::uint64_t n = 0;
    std::string theirs;
    in.get(n);
    in.get(theirs);
    wire::Reader layer_in(theirs);
    for (std::uint64_t k = 0; k < n; ++k) sink(get_layer(layer_in));
  }
  if (!(report.job.model_volume > 0))
    throw InputError(
        "the mesh encloses no volume: no grid node is inside it (an open sheet, or a shell "
        "thinner than the voxel size)");
  report.job.ranks = ranks();
  return report;
}

}  // namespace tpmsfill::cli
