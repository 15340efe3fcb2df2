/// @file lattice_rows.hpp
/// @brief Evaluates a lattice design along grid rows: what lattice_field and compose share.
#pragma once

#include <cstdint>
#include <memory>

#include "tpmsfill/lattice.hpp"

namespace tpmsfill::detail {

class LatticeRows {
 public:
  /// @param design  resolved (resolve_design) and valid
  /// @param depth   depth below the model's surface on `grid` (Depth ramps only)
  LatticeRows(const LatticeDesign& design, const Grid& grid, const Field* depth);
  ~LatticeRows();
  LatticeRows(const LatticeRows&) = delete;
  LatticeRows& operator=(const LatticeRows&) = delete;

  /// φ_L at the nodes i of row (j, k) where need[i] != 0 (every node when need is null); the
  /// other entries of out are left as they are. Safe to call from several threads.
  void row(int j, int k, float* out, const std::uint8_t* need = nullptr) const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace tpmsfill::detail
