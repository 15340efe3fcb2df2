/// @file box_samples.hpp
/// @brief Points spread through a box, for reviews that judge a field over a model's box.
#pragma once

#include "tpmsfill/types.hpp"

namespace tpmsfill::detail {

/// (n + 1)³ points spread through the box, its corners included.
template <class F>
void for_each_box_sample(const Box3& box, int n, F&& f) {
  const Vec3 s = box.size();
  for (int k = 0; k <= n; ++k)
    for (int j = 0; j <= n; ++j)
      for (int i = 0; i <= n; ++i) f(box.min + Vec3{s.x * i / n, s.y * j / n, s.z * k / n});
}

}  // namespace tpmsfill::detail
