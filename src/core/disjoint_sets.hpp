/// @file disjoint_sets.hpp
/// @brief Union-find over 0..n-1, shared by the stages that label connected pieces (soup
/// topology, voxel regions, cap patches).
#pragma once

#include <cstddef>
#include <cstdint>
#include <numeric>
#include <vector>

namespace tpmsfill::detail {

/// Union-find with path halving and union by index: the smaller root wins, so the result
/// never depends on the order of calls for the same set of unions.
class DisjointSets {
 public:
  explicit DisjointSets(std::size_t n) : parent_(n) {
    std::iota(parent_.begin(), parent_.end(), 0u);
  }
  /// A new singleton set; its index.
  std::uint32_t add() {
    parent_.push_back(static_cast<std::uint32_t>(parent_.size()));
    return parent_.back();
  }
  std::size_t size() const { return parent_.size(); }
  std::uint32_t find(std::uint32_t i) {
    while (parent_[i] != i) {
      parent_[i] = parent_[parent_[i]];
      i = parent_[i];
    }
    return i;
  }
  void unite(std::uint32_t a, std::uint32_t b) {
    a = find(a);
    b = find(b);
    if (a < b)
      parent_[b] = a;
    else if (b < a)
      parent_[a] = b;
  }

 private:
  std::vector<std::uint32_t> parent_;
};

}  // namespace tpmsfill::detail
