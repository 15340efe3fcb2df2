#include <gtest/gtest.h>

#include "test_util.hpp"

using namespace tpmsfill;

TEST(Generators, ClosedSolidsHaveExpectedVolume) {
  EXPECT_DOUBLE_EQ(test::signed_volume(test::make_box({0, 0, 0}, {10, 20, 30})), 6000.0);
  EXPECT_NEAR(test::signed_volume(test::make_sphere({0, 0, 0}, 1.0, 4)), 4.18879, 0.02);
  EXPECT_NEAR(test::signed_volume(test::make_torus(3, 1, 64, 32)), 2 * 3.14159265 * 3.14159265 * 3,
              0.5);
  EXPECT_GT(test::signed_volume(test::make_bow_tie()), 0);
}
