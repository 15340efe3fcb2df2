// Stage "voxel": separable byte-grid morphology, the distance band, and run-based labelling.
#include "tpmsfill/sampling/voxel.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>

#include "core/disjoint_sets.hpp"
#include "core/grid_buffer.hpp"
#include "core/index_limits.hpp"
#include "core/parallel.hpp"
#include "sampling/distance_transform.hpp"
#include "tpmsfill/error.hpp"

namespace tpmsfill {
namespace {

void require_consistent(const Mask& mask) {
  if (mask.values.size() != mask.grid.node_count())
    throw InputError("mask size does not match its grid");
}

// out = map(in) dilated by r along x: a node is set when a set node lies within r along its
// row. `map` turns each input byte into the bits dilated (the band maps a mask to classes).
template <class Map>
void dilate_x(const Grid& g, const std::uint8_t* in, std::uint8_t* out, int r, const Map& map) {
  const int nx = g.dims[0];
  detail::parallel_for(g.row_count(), 256, [&](std::size_t begin, std::size_t end) {
    for (std::size_t row = begin; row < end; ++row) {
      const std::uint8_t* a = in + row * nx;
      std::uint8_t* b = out + row * nx;
      if (r == 1) {  // the common case, as a loop the compiler vectorises
        b[0] = map(a[0]) | (nx > 1 ? map(a[1]) : 0);
        for (int i = 1; i + 1 < nx; ++i) b[i] = map(a[i - 1]) | map(a[i]) | map(a[i + 1]);
        if (nx > 1) b[nx - 1] = map(a[nx - 2]) | map(a[nx - 1]);
        continue;
      }
      // Per bit of the values (masks use bit 0, the band both bits): the last index at or
      // before i where it is set, then the next at or after i.
      constexpr int kFar = std::numeric_limits<int>::max() / 4;
      int last[2] = {-kFar, -kFar};
      for (int i = 0; i < nx; ++i) {
        std::uint8_t v = 0;
        for (int bit = 0; bit < 2; ++bit) {
          if (map(a[i]) >> bit & 1) last[bit] = i;
          v |= static_cast<std::uint8_t>((i - last[bit] <= r) << bit);
        }
        b[i] = v;
      }
      int next[2] = {kFar, kFar};
      for (int i = nx - 1; i >= 0; --i)
        for (int bit = 0; bit < 2; ++bit) {
          if (map(a[i]) >> bit & 1) next[bit] = i;
          b[i] |= static_cast<std::uint8_t>((next[bit] - i <= r) << bit);
        }
    }
  });
}

// out row (j, k) = OR of in rows within r along y (step 1 row) or z (step dims[1] rows).
void dilate_rows(const Grid& g, const std::uint8_t* in, std::uint8_t* out, int r, int axis) {
  const std::size_t nx = g.dims[0];
  const int n_axis = g.dims[axis];
  detail::parallel_for(g.row_count(), 64, [&](std::size_t begin, std::size_t end) {
    for (std::size_t row = begin; row < end; ++row) {
      const int j = static_cast<int>(row % g.dims[1]), k = static_cast<int>(row / g.dims[1]);
      const int at = axis == 1 ? j : k;
      const std::ptrdiff_t step = axis == 1 ? 1 : g.dims[1];
      std::uint8_t* b = out + row * nx;
      std::fill(b, b + nx, std::uint8_t{0});
      for (int d = std::max(-r, -at); d <= std::min(r, n_axis - 1 - at); ++d) {
        const std::uint8_t* a = in + (static_cast<std::ptrdiff_t>(row) + d * step) * nx;
        for (std::size_t i = 0; i < nx; ++i) b[i] |= a[i];
      }
    }
  });
}

}  // namespace

Mask dilate(const Mask& mask, int voxels) {
  require_consistent(mask);
  if (voxels < 0) throw InputError("dilation radius must not be negative");
  if (voxels == 0) return mask;
  Mask a{mask.grid, detail::grid_buffer<std::uint8_t>(mask.values.size())};
  Mask b{mask.grid, detail::grid_buffer<std::uint8_t>(mask.values.size())};
  dilate_x(mask.grid, mask.values.data(), a.values.data(), voxels,
           [](std::uint8_t x) { return x; });
  dilate_rows(mask.grid, a.values.data(), b.values.data(), voxels, 1);
  dilate_rows(mask.grid, b.values.data(), a.values.data(), voxels, 2);
  return a;
}

Band band_voxels(const Mask& inside, const BandOptions& options) {
  require_consistent(inside);
  if (options.width < 1) throw InputError("the band width must be at least 1 voxel");
  // Both dilations at once: bit 0 marks inside nodes, bit 1 outside ones, and one dilation ORs
  // them. A node is in the band when both classes lie within the width of it (its own counts),
  // nodes beyond the grid counting as outside: bit 1 is set within the width of its faces.
  // The dilation's buffers are written whole by each pass: left uninitialised until then.
  const Grid& g = inside.grid;
  const int v = options.width;
  const std::size_t nodes = inside.values.size();
  auto near = std::make_unique_for_overwrite<std::uint8_t[]>(nodes);
  {
    auto between = std::make_unique_for_overwrite<std::uint8_t[]>(nodes);
    dilate_x(g, inside.values.data(), near.get(), v,
             [](std::uint8_t x) { return static_cast<std::uint8_t>(x ? 1 : 2); });
    dilate_rows(g, near.get(), between.get(), v, 1);
    dilate_rows(g, between.get(), near.get(), v, 2);
  }
  const int nx = g.dims[0];
  detail::parallel_for(g.row_count(), 256, [&](std::size_t b, std::size_t e) {
    for (std::size_t row = b; row < e; ++row) {
      const int j = static_cast<int>(row % g.dims[1]), k = static_cast<int>(row / g.dims[1]);
      std::uint8_t* a = near.get() + row * nx;
      if (j < v || k < v || j >= g.dims[1] - v || k >= g.dims[2] - v) {
        for (int i = 0; i < nx; ++i) a[i] |= 2;
      } else {
        for (int i = 0; i < std::min(v, nx); ++i) a[i] |= 2;
        for (int i = std::max(v, nx - v); i < nx; ++i) a[i] |= 2;
      }
    }
  });
  auto in_band = [&](std::size_t n) { return near[n] == 3; };
  // Count per chunk, exclusive scan, fill: the order is the node order for any thread count.
  constexpr std::size_t kChunk = 1 << 16;
  const std::vector<std::size_t> at = detail::compaction_offsets(nodes, kChunk, in_band);
  Band band{inside.grid, std::vector<std::uint64_t>(at.back())};
  detail::for_each_kept(at, nodes, kChunk, in_band,
                        [&](std::size_t i, std::size_t place) { band.nodes[place] = i; });
  return band;
}

// --- labelling ------------------------------------------------------------------------

std::uint32_t Regions::region_at(int i, int j, int k) const {
  const std::size_t row = static_cast<std::size_t>(j) + static_cast<std::size_t>(grid.dims[1]) * k;
  const auto first = runs.begin() + static_cast<std::ptrdiff_t>(row_start[row]);
  const auto last = runs.begin() + static_cast<std::ptrdiff_t>(row_start[row + 1]);
  auto it = std::upper_bound(first, last, i, [](int x, const Run& r) { return x < r.begin; });
  if (it == first) return detail::kNoIndex;
  --it;
  return i < it->end ? it->region : detail::kNoIndex;
}

void append_runs(Regions& r, const Mask& planes) {
  require_consistent(planes);
  const Grid& g = planes.grid;
  const std::size_t ny = static_cast<std::size_t>(r.grid.dims[1]);
  if (r.row_start.empty()) r.row_start.push_back(0);
  if (g.dims[0] != r.grid.dims[0] || g.dims[1] != r.grid.dims[1] ||
      static_cast<std::size_t>(g.z_offset - r.grid.z_offset) * ny != r.row_start.size() - 1 ||
      g.z_offset + g.dims[2] > r.grid.z_offset + r.grid.dims[2])
    throw InputError("append_runs: the planes are not the next ones of the runs' grid");
  const std::size_t rows = g.row_count(), first_row = r.row_start.size() - 1;
  // Runs per row, counted then filled, so the run order is the node order.
  std::vector<std::uint64_t> counts(rows, 0);
  detail::parallel_for(rows, 256, [&](std::size_t b, std::size_t e) {
    for (std::size_t row = b; row < e; ++row) {
      const std::uint8_t* a = planes.values.data() + row * g.dims[0];
      std::uint64_t n = 0;
      for (int i = 0; i < g.dims[0]; ++i) n += a[i] && (i == 0 || !a[i - 1]);
      counts[row] = n;
    }
  });
  for (std::size_t row = 0; row < rows; ++row)
    r.row_start.push_back(r.row_start.back() + counts[row]);
  if (!detail::fits_32bit_ids(r.row_start.back())) throw InputError("too many runs to label");
  r.runs.resize(r.row_start.back());
  detail::parallel_for(rows, 256, [&](std::size_t b, std::size_t e) {
    for (std::size_t row = b; row < e; ++row) {
      const std::uint8_t* a = planes.values.data() + row * g.dims[0];
      std::uint64_t out = r.row_start[first_row + row];
      for (int i = 0; i < g.dims[0]; ++i)
        if (a[i] && (i == 0 || !a[i - 1])) {
          int end = i;
          while (end < g.dims[0] && a[end]) ++end;
          r.runs[out++] = {i, end, 0};
        }
    }
  });
}

Regions label_regions(const Mask& mask, Connectivity connectivity) {
  Regions r;
  r.grid = mask.grid;
  append_runs(r, mask);
  return label_runs(std::move(r), connectivity);
}

Regions label_runs(Regions r, Connectivity connectivity) {
  const Grid& g = r.grid;
  if (r.row_start.size() != g.row_count() + 1)
    throw InputError("label_runs: the runs do not cover every row of their grid");
  r.count = 0;
  // Union each run with the runs of the rows "before" it that touch it. 26-connectivity: the
  // 4 rows j−1..j+1 at k−1 and j−1 at k, overlapping when widened by one node. 6-connectivity:
  // the rows j−1 and k−1 only, overlapping in at least one x.
  const bool faces = connectivity == Connectivity::Face;
  const int widen = faces ? 0 : 1;
  detail::DisjointSets sets(r.runs.size());
  for (int k = 0; k < g.dims[2]; ++k)
    for (int j = 0; j < g.dims[1]; ++j) {
      const std::size_t row = static_cast<std::size_t>(j) + static_cast<std::size_t>(g.dims[1]) * k;
      for (std::uint64_t a = r.row_start[row]; a < r.row_start[row + 1]; ++a) {
        const Regions::Run& run = r.runs[a];
        for (int dk = -1; dk <= 0; ++dk)
          for (int dj = -1; dj <= 1; ++dj) {
            if ((dk == 0 && dj >= 0) || (faces && dj != 0 && dk != 0)) continue;
            const int jj = j + dj, kk = k + dk;
            if (jj < 0 || jj >= g.dims[1] || kk < 0) continue;
            const std::size_t other =
                static_cast<std::size_t>(jj) + static_cast<std::size_t>(g.dims[1]) * kk;
            for (std::uint64_t b = r.row_start[other]; b < r.row_start[other + 1]; ++b) {
              const Regions::Run& o = r.runs[b];
              if (o.begin >= run.end + widen) break;
              if (o.end + widen > run.begin)
                sets.unite(static_cast<std::uint32_t>(a), static_cast<std::uint32_t>(b));
            }
          }
      }
    }
  // Roots are the earliest run of each region; number regions in root order.
  std::vector<std::uint32_t> number(r.runs.size(), detail::kNoIndex);
  for (std::size_t a = 0; a < r.runs.size(); ++a) {
    const std::uint32_t root = sets.find(static_cast<std::uint32_t>(a));
    if (number[root] == detail::kNoIndex) number[root] = r.count++;
    r.runs[a].region = number[root];
  }
  return r;
}

// --- distance transform ------------------------------------------------------------------

Field distance_transform(const Mask& mask, bool beyond_grid_set) {
  Field out{mask.grid, detail::grid_buffer<float>(mask.values.size())};
  const double a = mask.grid.spacing;
  detail::squared_distance_transform<false>(
      mask, beyond_grid_set, [&](std::size_t node, std::uint32_t d2, std::uint32_t) {
        out.values[node] = d2 == detail::kNoUnset
                               ? std::numeric_limits<float>::infinity()
                               : static_cast<float>(std::sqrt(static_cast<double>(d2)) * a);
      });
  return out;
}

}  // namespace tpmsfill
