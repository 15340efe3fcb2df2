// fill and slice split among the ranks of one run (ranks.hpp): each rank takes its share of
// the z range, rank 0 gathers in rank order and finishes. With one rank they are fill() and
// slice() themselves.
#pragma once

#include <cstdint>
#include <filesystem>
#include <optional>
#include <tpmsfill/fill.hpp>
#include <tpmsfill/io.hpp>
#include <tpmsfill/slice.hpp>

namespace tpmsfill::cli {

/// fill_to_file() across the ranks: each fills its share of the grid's node planes
/// (fill_part), rank 0 joins the parts (fill_parts) and writes `path`: the same file as one
/// process (which streams it when the job is over the memory budget; the join holds the mesh).
/// Rank 0 gets the result (its mesh left empty), the others nothing.
std::optional<FillResult> fill_on_ranks(const TriangleSoup& model, const FillOptions& options,
                                        const std::filesystem::path& path,
                                        const WriteOptions& write);

/// slice() across the ranks, each slicing its share of the `count` layers. `sink` receives
/// layers on rank 0, every layer in order (other ranks send theirs, without their planes'
/// fields); with `sink_everywhere` each rank sinks its own layers instead (folder formats,
/// written by every rank into one shared folder). Rank 0 gets the merged report.
std::optional<SliceReport> slice_on_ranks(const TriangleSoup& model, const FillOptions& options,
                                          SliceOptions slice_options, std::uint64_t count,
                                          const LayerSink& sink, bool sink_everywhere);

}  // namespace tpmsfill::cli
