// Same input, same facts, whatever the thread count: check_mesh at one thread and at all cores
// must give byte-identical JSON (self-intersection pairs and examples included).
#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <tpmsfill/check.hpp>

#include "test_util.hpp"

using namespace tpmsfill;

TEST(Determinism, CheckMeshIsIndependentOfThreadCount) {
  // Overlapping, partly flipped, unshared shells: every fact and example list is non-trivial.
  TriangleSoup soup =
      test::concat(test::make_sphere({0, 0, 0}, 5, 4), test::make_torus(5, 1.5, 64, 32));
  soup = test::unshare_points(test::flip(soup, 7));
  MeshCheck serial_check;
  {
    tbb::global_control one(tbb::global_control::max_allowed_parallelism, 1);
    serial_check = check_mesh(soup);
  }
  const std::string serial = to_json(serial_check);
  {
    tbb::global_control many(tbb::global_control::max_allowed_parallelism, 8);
    EXPECT_EQ(to_json(check_mesh(soup)), serial);
  }
  EXPECT_GT(serial_check.self_intersecting_pairs.value_or(0), 0u);
  EXPECT_GT(serial_check.inconsistent_edges, 0u);
}
