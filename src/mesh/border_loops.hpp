/// @file border_loops.hpp
/// @brief The border of a set of oriented triangles as a chain: darts (directed edges) whose
/// uses do not cancel, and the loops they form. Shared by clean (hole caps) and the spatial
/// index (the rims the winding number needs). Plain data, deterministic.
#pragma once

#include <algorithm>
#include <cstdint>
#include <cstdlib>
#include <tuple>
#include <utility>
#include <vector>

namespace tpmsfill::detail {

/// A directed edge between two vertex ids.
struct Dart {
  std::uint32_t from = 0, to = 0;
};

/// The darts' sum as a chain: per undirected edge, |net| darts in the net direction.
inline std::vector<Dart> net_darts(const std::vector<Dart>& darts) {
  std::vector<std::pair<std::uint64_t, int>> sums;
  sums.reserve(darts.size());
  for (const Dart& d : darts) {
    const bool fwd = d.from < d.to;
    const std::uint64_t key =
        fwd ? (std::uint64_t{d.from} << 32 | d.to) : (std::uint64_t{d.to} << 32 | d.from);
    sums.push_back({key, fwd ? 1 : -1});
  }
  std::sort(sums.begin(), sums.end());
  std::vector<Dart> net;
  for (std::size_t i = 0; i < sums.size();) {
    std::size_t j = i;
    int s = 0;
    while (j < sums.size() && sums[j].first == sums[i].first) s += sums[j++].second;
    const auto a = static_cast<std::uint32_t>(sums[i].first >> 32);
    const auto b = static_cast<std::uint32_t>(sums[i].first & 0xffffffffu);
    for (int m = 0; m < std::abs(s); ++m) net.push_back(s > 0 ? Dart{a, b} : Dart{b, a});
    i = j;
  }
  return net;
}

/// Distinct undirected edges among darts.
inline std::uint64_t count_edges(const std::vector<Dart>& darts) {
  std::vector<std::uint64_t> keys;
  for (const Dart& d : darts)
    keys.push_back(std::uint64_t{std::min(d.from, d.to)} << 32 | std::max(d.from, d.to));
  std::sort(keys.begin(), keys.end());
  return static_cast<std::uint64_t>(std::unique(keys.begin(), keys.end()) - keys.begin());
}

/// Splits a closed chain of darts into loops (vertex id sequences, each dart walked once).
/// Deterministic: darts are taken in (from, to) order.
inline std::vector<std::vector<std::uint32_t>> border_loops(std::vector<Dart> darts) {
  std::sort(darts.begin(), darts.end(), [](const Dart& a, const Dart& b) {
    return std::tie(a.from, a.to) < std::tie(b.from, b.to);
  });
  std::vector<bool> used(darts.size(), false);
  // cursor[i], for the first dart i of the run leaving one vertex: the run's first dart that
  // may still be unused.
  std::vector<std::size_t> cursor(darts.size());
  for (std::size_t i = 0; i < darts.size(); ++i) cursor[i] = i;
  auto take_from = [&](std::uint32_t v) -> std::size_t {
    auto it = std::lower_bound(darts.begin(), darts.end(), v,
                               [](const Dart& d, std::uint32_t x) { return d.from < x; });
    if (it == darts.end() || it->from != v) return darts.size();
    std::size_t& c = cursor[static_cast<std::size_t>(it - darts.begin())];
    while (c < darts.size() && darts[c].from == v && used[c]) ++c;
    return (c < darts.size() && darts[c].from == v) ? c : darts.size();
  };
  std::vector<std::vector<std::uint32_t>> loops;
  for (std::size_t first = 0; first < darts.size(); ++first) {
    if (used[first]) continue;
    std::vector<std::uint32_t> loop{darts[first].from};
    used[first] = true;
    std::uint32_t v = darts[first].to;
    while (v != loop.front()) {
      const std::size_t d = take_from(v);
      if (d == darts.size()) break;  // cannot happen for a closed chain; close the loop here
      used[d] = true;
      loop.push_back(v);
      v = darts[d].to;
    }
    loops.push_back(std::move(loop));
  }
  return loops;
}

/// Border darts of triangles given by corner ids (each triangle walks c0 → c1 → c2).
template <class Corners>
std::vector<Dart> triangle_border(const Corners& triangles) {
  std::vector<Dart> darts;
  darts.reserve(3 * triangles.size());
  for (const auto& t : triangles)
    for (int k = 0; k < 3; ++k) darts.push_back({t[k], t[(k + 1) % 3]});
  return net_darts(darts);
}

}  // namespace tpmsfill::detail
