/// @file distance_transform.hpp
/// @brief The separable squared Euclidean distance transform behind voxel.hpp's
/// distance_transform() and measure.hpp's pore and wall sizes, with the nearest unset node
/// (a feature transform) when the caller asks for it, so it can place the surface between
/// nodes.
///
/// Felzenszwalb & Huttenlocher (2012), "Distance transforms of sampled functions": a pass along
/// x on the mask (distance to the nearest unset node of the row), then along y and along z the
/// lower envelope of the parabolas (q − v)² + f(v). Squared distances are integers in voxel²
/// and the envelope's breakpoints are compared as fractions, so the result is exact on the
/// nodes and no division is done. Every line is computed by one task from its own input, so
/// the result is the same for any thread count.
///
/// Lines along y and z are processed in blocks of kBlock neighbours in x, interleaved: a
/// gathered cache line then serves kBlock lines instead of one, which keeps the z pass (stride
/// nx·ny) from being memory bound. Where a block's samples are small (distances under 90
/// voxels, as in a lattice) its minimum is found by brute force over a window, all kBlock lines
/// at once in 16-bit lanes (window_block): exact as well, and about twice as fast as the
/// envelope, whose data-dependent branches mispredict. Ties between equally near unset nodes
/// may be broken differently by the two, but each block's choice depends only on its data.
#pragma once

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <memory>
#include <vector>

#include "core/parallel.hpp"
#include "tpmsfill/error.hpp"
#include "tpmsfill/types.hpp"

namespace tpmsfill::detail {

/// Squared distance of a node with no unset node anywhere (beyond_grid_set and a full mask).
inline constexpr std::uint32_t kNoUnset = std::numeric_limits<std::uint32_t>::max();
/// Nearest unset node of a node whose nearest one lies beyond the grid (or that has none).
inline constexpr std::uint32_t kBeyondGrid = std::numeric_limits<std::uint32_t>::max();

/// Lower envelope of the parabolas y = (x − v)² + f(v) of one line (F&H Algorithm 1).
class ParabolaEnvelope {
 public:
  /// @param f       n samples f[q·stride]; kNoUnset means "no sample here"
  /// @param stride  distance between consecutive samples in f, d2 and arg
  /// @param edges   add zero samples at −1 and n (unset nodes just beyond the grid)
  /// @param d2      out: min over samples of (q − v)² + f(v) at q = 0..n−1 (kNoUnset if none)
  /// @param arg     out, when not null: the minimising v (−1 or n for the edges; −1 if none)
  void run(const std::uint32_t* f, int n, std::ptrdiff_t stride, bool edges, std::uint32_t* d2,
           int* arg) {
    const std::size_t cap = static_cast<std::size_t>(n) + 2;
    if (v_.size() < cap) v_.resize(cap), g_.resize(cap), zn_.resize(cap), zd_.resize(cap);
    int k = 0;  // parabolas on the envelope; parabola i is lowest on [z_i, z_{i+1}]
    auto push = [&](std::int64_t q, std::int64_t fq) {
      // Breakpoint with the top parabola: s = (fq + q² − f_v − v²) / (2(q − v)), 2(q − v) > 0.
      // The top is hidden when s <= its own left breakpoint (z_0 = −∞ never hides).
      const std::int64_t gq = fq + q * q;
      std::int64_t sn = 0, sd = 1;
      while (k > 0) {
        sn = gq - g_[k - 1];
        sd = 2 * (q - v_[k - 1]);
        if (k == 1 || sn * zd_[k - 1] > zn_[k - 1] * sd) break;
        --k;
      }
      v_[k] = q, g_[k] = gq, zn_[k] = sn, zd_[k] = sd;
      ++k;
    };
    // A zero between two zeros is nowhere else the least (a neighbour is nearer): skipped.
    auto inner_zero = [&](int q) {
      return f[q * stride] == 0 && q > 0 && q + 1 < n && f[(q - 1) * stride] == 0 &&
             f[(q + 1) * stride] == 0;
    };
    if (edges) push(-1, 0);
    for (int q = 0; q < n; ++q)
      if (f[q * stride] != kNoUnset && !inner_zero(q)) push(q, f[q * stride]);
    if (edges) push(n, 0);
    if (k == 0) {
      for (int q = 0; q < n; ++q) {
        d2[q * stride] = kNoUnset;
        if (arg) arg[q * stride] = -1;
      }
      return;
    }
    int j = 0;
    for (std::int64_t q = 0; q < n; ++q) {
      if (f[q * stride] == 0) {
        d2[q * stride] = 0;
        if (arg) arg[q * stride] = static_cast<int>(q);
        continue;
      }
      while (j + 1 < k && zn_[j + 1] < q * zd_[j + 1]) ++j;  // z_{j+1} < q
      d2[q * stride] = static_cast<std::uint32_t>(q * q - 2 * q * v_[j] + g_[j]);
      if (arg) arg[q * stride] = static_cast<int>(v_[j]);
    }
  }

 private:
  std::vector<std::int64_t> v_, g_, zn_, zd_;  // position v, f(v) + v², left breakpoint zn/zd
};

inline constexpr int kBlock = 16;  // lines per gathered block (64 bytes of uint32)

/// Largest sample for which window_block runs: its sums stay below 2^15 (16-bit lanes).
inline constexpr std::uint32_t kWindowLimit = 90 * 90;

/// What ParabolaEnvelope computes, for a block of kBlock interleaved lines (node q of line b at
/// [q·kBlock + b]) whose samples are all at most kWindowLimit, by brute force over a window:
/// the sample δ away adds δ², so once δ² reaches every line's best no farther sample can win,
/// and δ stays below 90. The loops run over the kBlock lines at once in 16-bit lanes, which
/// compilers vectorise (SSE2 has a 16-bit min): a few operations a node where distances are a
/// few voxels, as in a lattice, against some 60 and a branch misprediction for the envelope.
/// @param f16  workspace of len·kBlock values
template <bool kNearest>
void window_block(const std::uint32_t* in, int len, bool edges, std::uint32_t* out, int* arg,
                  std::int16_t* f16) {
  for (int i = 0; i < len * kBlock; ++i) f16[i] = static_cast<std::int16_t>(in[i]);
  for (int q = 0; q < len; ++q) {
    std::int16_t best[kBlock], from[kBlock];  // from: offset of the winning sample
    const std::int16_t* own = f16 + q * kBlock;
    std::int16_t most = 0;  // the largest best: farther samples than its root cannot win
    for (int b = 0; b < kBlock; ++b) {
      best[b] = own[b];
      from[b] = 0;
      most = std::max(most, own[b]);
    }
    for (int d = 1; d * d < most; ++d) {
      const auto dd = static_cast<std::int16_t>(d * d);
      for (const int side : {-d, d}) {
        const int at = q + side;
        const bool virtual_zero = edges && (at == -1 || at == len);
        if (!virtual_zero && (at < 0 || at >= len)) continue;
        static constexpr std::int16_t zeros[kBlock] = {};
        const std::int16_t* row = virtual_zero ? zeros : f16 + at * kBlock;
        const auto offset = static_cast<std::int16_t>(side);
        for (int b = 0; b < kBlock; ++b) {
          const auto c = static_cast<std::int16_t>(row[b] + dd);
          if constexpr (kNearest) from[b] = c < best[b] ? offset : from[b];
          best[b] = c < best[b] ? c : best[b];
        }
      }
      most = 0;
      for (int b = 0; b < kBlock; ++b) most = std::max(most, best[b]);
    }
    for (int b = 0; b < kBlock; ++b) {
      out[q * kBlock + b] = static_cast<std::uint32_t>(best[b]);
      if constexpr (kNearest) arg[q * kBlock + b] = q + from[b];
    }
  }
}

/// One envelope pass along `axis` (1 = y, 2 = z) over every line of the grid, reading d2 and
/// (kNearest) near, and handing each node's result to emit(node, d2, nearest). emit may write
/// back into d2/near: a block gathers all its lines before emitting, and no two blocks share a
/// node.
template <bool kNearest, class Emit>
void envelope_pass(const Grid& g, int axis, bool edges, const std::uint32_t* d2,
                   const std::uint32_t* near, const Emit& emit) {
  const std::size_t nx = static_cast<std::size_t>(g.dims[0]);
  const std::size_t stride = axis == 1 ? nx : nx * static_cast<std::size_t>(g.dims[1]);
  const std::size_t plane = axis == 1 ? nx * static_cast<std::size_t>(g.dims[1]) : nx;
  const int len = g.dims[axis], others = g.dims[axis == 1 ? 2 : 1];
  const std::size_t x_blocks = (nx + kBlock - 1) / kBlock;
  const std::size_t tasks = x_blocks * static_cast<std::size_t>(others);
  const std::size_t grain = std::max<std::size_t>(1, 4096 / (kBlock * std::max(len, 1)));
  parallel_for(tasks, grain, [&](std::size_t begin, std::size_t end) {
    const std::size_t block = static_cast<std::size_t>(kBlock) * len;
    std::vector<std::uint32_t> in(block), out(block), in_near(kNearest ? block : 0);
    std::vector<int> arg(kNearest ? block : 0);
    std::vector<std::int16_t> f16(block);
    ParabolaEnvelope envelope;
    for (std::size_t t = begin; t < end; ++t) {
      const std::size_t i0 = (t % x_blocks) * kBlock;
      const std::size_t base = i0 + (t / x_blocks) * plane;
      const int width = static_cast<int>(std::min<std::size_t>(kBlock, nx - i0));
      // Interleaved: node (b, q) of the block at [q·kBlock + b], so a gathered row is one copy.
      std::uint32_t top = 0;  // the largest sample (kNoUnset: none in some place)
      for (int q = 0; q < len; ++q) {
        const std::size_t at = base + q * stride;
        std::uint32_t* row = in.data() + q * kBlock;
        // Plain loops over at most kBlock values (std::copy would call memmove per row).
        for (int b = 0; b < kBlock; ++b) row[b] = b < width ? d2[at + b] : 0u;
        for (int b = 0; b < kBlock; ++b) top = std::max(top, row[b]);
        if constexpr (kNearest)
          for (int b = 0; b < width; ++b) in_near[q * kBlock + b] = near[at + b];
      }
      if (top <= kWindowLimit)
        window_block<kNearest>(in.data(), len, edges, out.data(), arg.data(), f16.data());
      else
        for (int b = 0; b < width; ++b)
          envelope.run(in.data() + b, len, kBlock, edges, out.data() + b,
                       kNearest ? arg.data() + b : nullptr);
      for (int q = 0; q < len; ++q) {
        const std::size_t at = base + q * stride;
        for (int b = 0; b < width; ++b) {
          std::uint32_t nearest = kBeyondGrid;
          if constexpr (kNearest) {
            const int v = arg[q * kBlock + b];
            if (v >= 0 && v < len) nearest = in_near[v * kBlock + b];
          }
          emit(at + b, out[q * kBlock + b], nearest);
        }
      }
    }
  });
}

/// Squared distance in voxel² from every node to the nearest unset node of `mask`, handed to
/// finish(node, d2, nearest) once per node from any thread. d2 is kNoUnset when no unset node
/// exists; nearest (kNearest only) is that node's index, or kBeyondGrid when it lies beyond
/// the grid. Nodes beyond the grid count as set when beyond_grid_set, else as unset.
/// @throws InputError  mask.values does not match mask.grid, or the grid is so large that a
///                     squared distance or a node index would not fit in 32 bits
template <bool kNearest, class Finish>
void squared_distance_transform(const Mask& mask, bool beyond_grid_set, const Finish& finish) {
  const Grid& g = mask.grid;
  if (mask.values.size() != g.node_count()) throw InputError("mask size does not match its grid");
  const std::size_t n = g.node_count();
  if (n == 0) return;
  std::uint64_t reach = 0;  // largest squared distance that can occur, plus slack
  for (int axis = 0; axis < 3; ++axis)
    reach += (static_cast<std::uint64_t>(g.dims[axis]) + 1) * (g.dims[axis] + 1);
  if (reach >= kNoUnset || (kNearest && n >= kBeyondGrid))
    throw InputError("grid too large for the distance transform");
  const int nx = g.dims[0];
  // Every node is written by the x pass before it is read: no need to zero 8 bytes a node.
  const std::unique_ptr<std::uint32_t[]> d2(new std::uint32_t[n]);
  const std::unique_ptr<std::uint32_t[]> near(new std::uint32_t[kNearest ? n : 1]);
  // x: distance along the row to the nearest unset node (ties go to the one on the left), in
  // branch-free sweeps. With beyond_grid_set a row without unset nodes starts from positions
  // kFar beyond its ends, so its distances exceed nx, which marks them kNoUnset.
  constexpr std::int64_t kFar = std::int64_t{1} << 30;  // > any nx, and fits 32 bits
  parallel_for(g.row_count(), 64, [&](std::size_t begin, std::size_t end) {
    for (std::size_t row = begin; row < end; ++row) {
      const std::uint8_t* a = mask.values.data() + row * nx;
      std::uint32_t* d = d2.get() + row * nx;
      std::uint32_t* f = kNearest ? near.get() + row * nx : nullptr;
      std::int64_t last = beyond_grid_set ? -kFar : -1;
      for (int i = 0; i < nx; ++i) {
        last = a[i] ? last : i;
        d[i] = static_cast<std::uint32_t>(i - last);
        if constexpr (kNearest)
          f[i] = last < 0 ? kBeyondGrid : static_cast<std::uint32_t>(row * nx + last);
      }
      std::int64_t next = beyond_grid_set ? nx + kFar : nx;
      for (int i = nx - 1; i >= 0; --i) {
        next = a[i] ? next : i;
        const auto right = static_cast<std::uint32_t>(next - i);
        if constexpr (kNearest)
          if (right < d[i])
            f[i] = next >= nx ? kBeyondGrid : static_cast<std::uint32_t>(row * nx + next);
        const std::uint32_t x = std::min(d[i], right);
        d[i] = x > static_cast<std::uint32_t>(nx) ? kNoUnset : x * x;
      }
    }
  });
  const bool edges = !beyond_grid_set;
  envelope_pass<kNearest>(g, 1, edges, d2.get(), near.get(),
                          [&](std::size_t node, std::uint32_t d, std::uint32_t nearest) {
                            d2[node] = d;
                            if constexpr (kNearest) near[node] = nearest;
                          });
  envelope_pass<kNearest>(g, 2, edges, d2.get(), near.get(), finish);
}

}  // namespace tpmsfill::detail
