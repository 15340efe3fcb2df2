// Stage "measure": sub-voxel distances to the other phase sampled on their ridge (pore and wall
// sizes), and 6-connected run labelling of the void (labyrinths).
#include "tpmsfill/lattice/measure.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

#include "core/parallel.hpp"
#include "core/stage_progress.hpp"
#include "sampling/distance_transform.hpp"
#include "tpmsfill/error.hpp"
#include "tpmsfill/sampling/voxel.hpp"

namespace tpmsfill {
namespace {

constexpr float kInfinity = std::numeric_limits<float>::infinity();
// Added to every diameter, in voxels. A ridge node misses the medial axis (where the largest
// sphere is centred) by up to half a voxel along each axis crossing it, so twice its distance
// reads low. Measured means (DISABLED_AccuracySurvey): 0.5a where the ridge is a sheet across
// grid planes (between flat walls), about 0.45a on a curve (a channel), 0.9a at a point (a round
// pore), under 0.1a on an oblique sheet (which the 26 directions sample finely). a/2 centres
// the first two and keeps every kind within about a voxel.
constexpr double kRidgeBias = 0.5;
// Ridge nodes are local maxima of the distance up to this many voxels (see ridge_diameters).
constexpr double kRidgeTolerance = 0.05;

void require_valid(const Field& phi, const Mask& inside, const MeasureOptions& options) {
  if (inside.values.size() != inside.grid.node_count())
    throw InputError("inside mask size does not match its grid");
  if (!(phi.grid == inside.grid) || phi.values.size() != inside.values.size())
    throw InputError("the field and the inside mask are not on the same grid");
  if (options.histogram_bins < 1) throw InputError("histogram_bins must be at least 1");
  if (options.smallest < 0) throw InputError("smallest must not be negative");
  for (const double limit : {options.min_wall, options.min_pore})
    if (!(limit >= 0 && std::isfinite(limit)))
      throw InputError("min_wall and min_pore must be finite and not negative (0: no limit)");
  if (!(options.min_labyrinth_fraction >= 0 && options.min_labyrinth_fraction <= 1))
    throw InputError("min_labyrinth_fraction must lie in [0, 1]");
}

// Distance, mm, from a node p to the surface near a node q of the other phase: φ places that
// surface to first order. It lies h = side·φ(q) >= 0 from q, across the plane with normal
// n = −side·∇φ(q)/|∇φ(q)| (pointing from q towards p's side), so p is n·(p − q) − h from the
// plane. That is at most upper = |p − q| − h, which bounds the distance to the surface when q
// is p's nearest node of the other phase (the segment p–q crosses the surface at least h from
// q). A plane estimate more than half a voxel below that bound comes from a gradient across a
// kink of φ (the model's surface) and is not trusted: upper is returned instead. h is clamped
// to [0, a]: q has a 6-neighbour of p's phase (else that one would be nearer to p), so on a
// distance field h <= a, and the clamp bounds the damage where φ is no distance.
struct SurfaceEstimate {
  using Coords = std::array<std::uint32_t, 3>;
  const Grid& grid;
  const Field& phi;
  double side;  // −1: p is in the void and q solid (pores); +1: p solid, q not (walls)

  // 32-bit divisions: node indices fit (the transform checks).
  Coords coords(std::size_t n) const {
    const auto m = static_cast<std::uint32_t>(n);
    const auto nx = static_cast<std::uint32_t>(grid.dims[0]);
    const auto ny = static_cast<std::uint32_t>(grid.dims[1]);
    return {m % nx, m / nx % ny, m / nx / ny};
  }
  double h(std::size_t q) const {
    return std::clamp(side * static_cast<double>(phi.values[q]), 0.0, grid.spacing);
  }
  double upper(double d2_voxels, std::size_t q) const {
    return std::sqrt(d2_voxels) * grid.spacing - h(q);
  }

  double operator()(const Coords& p, std::size_t q) const {
    const Coords c = coords(q);
    std::size_t stride = 1;
    double along = 0, length = 0, d2 = 0;
    for (int axis = 0; axis < 3; ++axis) {
      const float* f = phi.values.data() + q;
      const bool low = c[axis] > 0;
      const bool high = c[axis] + 1 < static_cast<std::uint32_t>(grid.dims[axis]);
      const double grad = (high ? f[stride] : f[0]) - (low ? *(f - stride) : f[0]);
      const double step = static_cast<double>(p[axis]) - static_cast<double>(c[axis]);
      length += grad * grad;
      along += grad * step;
      d2 += step * step;
      stride *= static_cast<std::size_t>(grid.dims[axis]);
    }
    const double bound = upper(d2, q);
    if (!(length > 0)) return bound;
    const double plane = -side * along / std::sqrt(length) * grid.spacing - h(q);
    return plane >= bound - grid.spacing / 2 ? std::min(plane, bound) : bound;
  }
};

// For every node, the nearest unset node q of `set` (detail::kBeyondGrid: beyond the grid,
// where the surface is taken to lie) and r = upper(p, q), mm, the cheap upper bound of the
// distance to the surface bounding the set nodes (the plane estimate is left to the ridge,
// where it matters). +infinity where no node is unset; −h at unset nodes.
struct SurfaceDistance {
  std::vector<float> r;
  std::vector<std::uint32_t> nearest;
};

SurfaceDistance surface_distance(const Mask& set, bool beyond_grid_set,
                                 const SurfaceEstimate& estimate) {
  SurfaceDistance out{std::vector<float>(set.values.size()),
                      std::vector<std::uint32_t>(set.values.size())};
  const double a = set.grid.spacing;
  detail::squared_distance_transform<true>(
      set, beyond_grid_set, [&](std::size_t node, std::uint32_t d2, std::uint32_t nearest) {
        out.nearest[node] = nearest;
        if (d2 == detail::kNoUnset)
          out.r[node] = kInfinity;
        else if (nearest == detail::kBeyondGrid)
          out.r[node] = static_cast<float>(std::sqrt(static_cast<double>(d2)) * a);
        else
          out.r[node] = static_cast<float>(estimate.upper(d2, nearest));
      });
  return out;
}

// Diameters at the ridge of the distance among the nodes where sample(node) holds, in node
// order.
//
// The ridge lies where the nearest node of the other phase switches from one side to the
// other, so there a node's nearest node may belong to the farther side and r overstate its
// distance to the nearer one by up to about a voxel. The refined distance of a node is
// therefore the least of the estimates from the nearest nodes of the node and of its 26
// neighbours (one of which lies on the nearer side); it is at most r. Ridge nodes are the
// local maxima of the refined distance: no 26-neighbour larger by more than kRidgeTolerance
// voxels. (Without the tolerance a flat ridge on a plane nearly containing a lattice direction,
// e.g. (−1, 1, 1), has its exact maxima hundreds of nodes apart.) Computing the refined
// distance everywhere would cost 27 estimates a node, so the search starts from the local
// maxima of r and climbs to the largest refined neighbour while one is larger, computing a
// neighbour's refined distance only where r, its upper bound, is larger. A climb that leaves
// the sampled nodes (a pore whose centre lies outside the model) samples nothing. A diameter is
// twice the refined distance plus `bias`.
// A phase's ridge samples: node indices ascending, and their diameters.
struct Ridge {
  std::vector<std::size_t> nodes;
  std::vector<double> diameters;
};

template <class Sample>
Ridge ridge_diameters(const SurfaceDistance& d, const SurfaceEstimate& estimate, double bias,
                      const Sample& sample) {
  const Grid& g = estimate.grid;
  const std::vector<float>& r = d.r;
  const int nx = g.dims[0], ny = g.dims[1], nz = g.dims[2];
  const std::ptrdiff_t sy = nx, sz = static_cast<std::ptrdiff_t>(nx) * ny;
  // The 6 face neighbours first: on a slope one of them is usually the larger.
  std::array<std::array<int, 3>, 26> steps;
  int s = 0;
  for (int pass = 0; pass < 2; ++pass)
    for (int dk = -1; dk <= 1; ++dk)
      for (int dj = -1; dj <= 1; ++dj)
        for (int di = -1; di <= 1; ++di) {
          const int nonzero = (di != 0) + (dj != 0) + (dk != 0);
          if (nonzero != 0 && (nonzero == 1) == (pass == 0)) steps[s++] = {di, dj, dk};
        }
  // Calls visit(neighbour index) for the 26-neighbours in the grid of node n = (i, j, k) until
  // it returns false; returns whether all returned true.
  auto neighbours_of = [&](int i, int j, int k, std::size_t n, auto&& visit) {
    const bool interior = i > 0 && j > 0 && k > 0 && i + 1 < nx && j + 1 < ny && k + 1 < nz;
    for (const auto& step : steps) {
      if (!interior) {
        const int a = i + step[0], b = j + step[1], c = k + step[2];
        if (a < 0 || b < 0 || c < 0 || a >= nx || b >= ny || c >= nz) continue;
      }
      if (!visit(static_cast<std::size_t>(static_cast<std::ptrdiff_t>(n) + step[0] + step[1] * sy +
                                          step[2] * sz)))
        return false;
    }
    return true;
  };
  auto neighbours = [&](std::size_t n, auto&& visit) {
    const SurfaceEstimate::Coords c = estimate.coords(n);
    return neighbours_of(static_cast<int>(c[0]), static_cast<int>(c[1]), static_cast<int>(c[2]), n,
                         visit);
  };
  auto refined = [&](std::size_t n) {
    const SurfaceEstimate::Coords p = estimate.coords(n);
    double best = r[n];
    std::array<std::uint32_t, 27> seen;
    int count = 0;
    auto consider = [&](std::size_t m) {
      const std::uint32_t q = d.nearest[m];
      if (q != detail::kBeyondGrid &&
          std::find(seen.begin(), seen.begin() + count, q) == seen.begin() + count) {
        seen[count++] = q;
        best = std::min(best, estimate(p, q));
      }
      return true;
    };
    consider(n);
    neighbours(n, consider);
    return best;
  };
  const double tolerance = kRidgeTolerance * g.spacing;
  auto is_candidate = [&](int i, int j, int k, std::size_t n) {
    const double v = r[n];
    return v > 0 && v != kInfinity && sample(n) &&
           neighbours_of(i, j, k, n, [&](std::size_t m) { return r[m] <= v + tolerance; });
  };
  struct Peak {
    std::size_t node;
    double value;
  };
  // Climbs by the largest refined neighbour while one beats the current node by more than
  // `tolerance` (ties: the smaller index).
  auto climb = [&](std::size_t n) {
    Peak at{n, refined(n)};
    for (;;) {
      Peak next = at;
      const double beat = at.value + tolerance;
      neighbours(at.node, [&](std::size_t m) {
        if (r[m] > beat && r[m] != kInfinity) {
          const double v = refined(m);
          if (v > beat &&
              (next.node == at.node || v > next.value || (v == next.value && m < next.node)))
            next = {m, v};
        }
        return true;
      });
      if (next.node == at.node) return at;
      at = next;
    }
  };
  // Fixed chunks of rows, each filling its own list, joined in chunk order, then sorted by node
  // and made unique (climbs from several starts may reach one peak).
  const std::size_t rows = g.row_count(), chunk = 64, chunks = (rows + chunk - 1) / chunk;
  std::vector<std::vector<Peak>> found(chunks);
  detail::parallel_for(chunks, 1, [&](std::size_t begin, std::size_t end) {
    for (std::size_t c = begin; c < end; ++c)
      for (std::size_t row = c * chunk; row < std::min(rows, (c + 1) * chunk); ++row) {
        const int j = static_cast<int>(row % ny), k = static_cast<int>(row / ny);
        for (int i = 0; i < nx; ++i) {
          const std::size_t n = row * nx + i;
          if (!is_candidate(i, j, k, n)) continue;
          const Peak peak = climb(n);
          if (peak.value > 0 && sample(peak.node)) found[c].push_back(peak);
        }
      }
  });
  std::vector<Peak> peaks;
  for (const auto& f : found) peaks.insert(peaks.end(), f.begin(), f.end());
  std::sort(peaks.begin(), peaks.end(),
            [](const Peak& x, const Peak& y) { return x.node < y.node; });
  peaks.erase(std::unique(peaks.begin(), peaks.end(),
                          [](const Peak& x, const Peak& y) { return x.node == y.node; }),
              peaks.end());
  Ridge ridge;
  ridge.nodes.resize(peaks.size());
  ridge.diameters.resize(peaks.size());
  for (std::size_t p = 0; p < peaks.size(); ++p) {
    ridge.nodes[p] = peaks[p].node;
    ridge.diameters[p] = 2 * peaks[p].value + bias;
  }
  return ridge;
}

// The summary's printability part: the smallest samples away from the model's surface, and
// the samples below `limit` (0: none), in node order so any thread count gives the same. A
// sample is at the model's surface when the sphere that measured it comes within a voxel of
// the surface (`to_outside`: each node's distance to the nearest node outside the model):
// there the surface cuts the lattice, and the size is the cut's, not the design's.
void add_smallest(SizeDistribution& s, const Ridge& ridge, const Field& to_outside, double limit,
                  int count) {
  const Grid& g = to_outside.grid;
  std::vector<std::size_t> away;  // indices into ridge, away from the model's surface
  for (std::size_t p = 0; p < ridge.nodes.size(); ++p) {
    const bool surface = to_outside.values[ridge.nodes[p]] < ridge.diameters[p] / 2 + g.spacing;
    if (!surface) away.push_back(p);
    if (limit > 0 && ridge.diameters[p] < limit)
      ++(surface ? s.below_limit_at_surface : s.below_limit);
  }
  const auto by_size = [&](std::size_t a, std::size_t b) {
    return ridge.diameters[a] < ridge.diameters[b] ||
           (ridge.diameters[a] == ridge.diameters[b] && a < b);
  };
  const std::size_t keep = std::min(away.size(), static_cast<std::size_t>(count));
  std::partial_sort(away.begin(), away.begin() + static_cast<std::ptrdiff_t>(keep), away.end(),
                    by_size);
  for (std::size_t q = 0; q < keep; ++q) {
    const std::size_t p = away[q];
    const std::size_t n = ridge.nodes[p], nx = static_cast<std::size_t>(g.dims[0]),
                      ny = static_cast<std::size_t>(g.dims[1]);
    s.smallest.push_back(
        {ridge.diameters[p], g.node(static_cast<int>(n % nx), static_cast<int>(n / nx % ny),
                                    static_cast<int>(n / (nx * ny)))});
  }
}

// Linear interpolation between order statistics (R's type 7) of the partially ordered d.
double percentile(std::vector<double>& d, double p) {
  const double at = p * static_cast<double>(d.size() - 1);
  const auto lo = static_cast<std::size_t>(std::floor(at));
  std::nth_element(d.begin(), d.begin() + static_cast<std::ptrdiff_t>(lo), d.end());
  const double low = d[lo];
  if (lo + 1 >= d.size()) return low;
  const double high = *std::min_element(d.begin() + static_cast<std::ptrdiff_t>(lo) + 1, d.end());
  return low + (at - static_cast<double>(lo)) * (high - low);
}

SizeDistribution summarize(std::vector<double> d, int bins, double voxel) {
  SizeDistribution s;
  s.samples = d.size();
  if (d.empty()) return s;
  double sum = 0;  // in node order: the same rounding for every thread count
  for (double v : d) sum += v;
  const auto [lo, hi] = std::minmax_element(d.begin(), d.end());
  s.min = *lo;
  s.max = *hi;
  s.mean = std::clamp(sum / static_cast<double>(d.size()), s.min, s.max);  // rounding
  const double top = s.max > s.min ? s.max : s.min + voxel;
  s.bin_edges.resize(static_cast<std::size_t>(bins) + 1);
  for (int b = 0; b <= bins; ++b) s.bin_edges[b] = s.min + (top - s.min) * b / bins;
  s.bin_edges[bins] = top;
  s.counts.assign(static_cast<std::size_t>(bins), 0);
  for (double v : d) {
    const int b = static_cast<int>((v - s.min) / (top - s.min) * bins);
    ++s.counts[static_cast<std::size_t>(std::clamp(b, 0, bins - 1))];
  }
  s.p10 = percentile(d, 0.1);
  s.p50 = percentile(d, 0.5);
  s.p90 = percentile(d, 0.9);
  return s;
}

}  // namespace

LatticeMeasures measure_lattice(const Field& phi, const Mask& inside,
                                const MeasureOptions& options) {
  require_valid(phi, inside, options);
  const Grid& g = inside.grid;
  const std::size_t n = g.node_count();
  detail::ProgressCounter progress(options.progress, "measure", 5);
  Mask solid{g, std::vector<std::uint8_t>(n)}, not_solid{g, std::vector<std::uint8_t>(n)};
  detail::parallel_for(n, 1 << 16, [&](std::size_t b, std::size_t e) {
    for (std::size_t i = b; i < e; ++i) {
      solid.values[i] = inside.values[i] && phi.values[i] < 0;
      not_solid.values[i] = !solid.values[i];
    }
  });
  // A node at the smallest positive float lies on a surface (compose moves exact zeros
  // there): neither solid nor void. On a model face that lies on a grid plane, such nodes
  // would otherwise join a sheet's two labyrinths along the face.
  auto is_void = [&](std::size_t i) {
    return inside.values[i] && !solid.values[i] &&
           phi.values[i] != std::numeric_limits<float>::min();
  };
  LatticeMeasures m;
  const Field to_outside = distance_transform(inside);  // beyond the grid is outside
  {
    const SurfaceEstimate estimate{g, phi, -1.0};
    const SurfaceDistance d = surface_distance(not_solid, true, estimate);
    progress.add(1);
    Ridge ridge = ridge_diameters(d, estimate, kRidgeBias * g.spacing, is_void);
    m.pore = summarize(ridge.diameters, options.histogram_bins, g.spacing);
    add_smallest(m.pore, ridge, to_outside, options.min_pore, options.smallest);
    progress.add(1);
  }
  {
    const SurfaceEstimate estimate{g, phi, 1.0};
    const SurfaceDistance d = surface_distance(solid, false, estimate);
    progress.add(1);
    const Ridge ridge = ridge_diameters(d, estimate, kRidgeBias * g.spacing,
                                        [&](std::size_t i) { return solid.values[i] != 0; });
    m.wall = summarize(ridge.diameters, options.histogram_bins, g.spacing);
    add_smallest(m.wall, ridge, to_outside, options.min_wall, options.smallest);
    progress.add(1);
  }
  // The void inside the model, reusing not_solid's bytes.
  Mask& void_inside = not_solid;
  detail::parallel_for(n, 1 << 16, [&](std::size_t b, std::size_t e) {
    for (std::size_t i = b; i < e; ++i) void_inside.values[i] = is_void(i);
  });
  // 6-connected: two void nodes touching only at an edge or corner are apart.
  const Regions regions = label_regions(void_inside, Connectivity::Face);
  std::vector<std::uint64_t> sizes(regions.count, 0);
  for (const Regions::Run& run : regions.runs)
    sizes[run.region] += static_cast<std::uint64_t>(run.end - run.begin);
  std::uint64_t total = 0, largest = 0;
  for (std::uint64_t s : sizes) total += s, largest = std::max(largest, s);
  m.void_components = sizes.size();
  for (std::uint64_t s : sizes)
    m.labyrinths +=
        static_cast<double>(s) >= options.min_labyrinth_fraction * static_cast<double>(total);
  m.largest_void_fraction = total ? static_cast<double>(largest) / static_cast<double>(total) : 0.0;
  progress.add(1);
  progress.finish();
  return m;
}

}  // namespace tpmsfill
