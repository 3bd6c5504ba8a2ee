// Error statistics against hand-computed values.
#include <gtest/gtest.h>

#include <cmath>

#include "odometry/eval/statistics.h"

namespace uf {
namespace {

TEST(Statistics, EvenCountHandComputed) {
  const ErrorStats s = ComputeStats({4, 1, 3, 2});
  EXPECT_EQ(s.n, 4u);
  EXPECT_DOUBLE_EQ(s.mean, 2.5);
  EXPECT_DOUBLE_EQ(s.median, 2.5);                // mean of the two middle values
  EXPECT_DOUBLE_EQ(s.rmse, std::sqrt(30.0 / 4));  // (16 + 1 + 9 + 4) / 4
  EXPECT_DOUBLE_EQ(s.std, std::sqrt(1.25));       // population: (2.25 + 0.25 + 0.25 + 2.25) / 4
  EXPECT_DOUBLE_EQ(s.min, 1);
  EXPECT_DOUBLE_EQ(s.max, 4);
}

TEST(Statistics, OddCountAndSingleValue) {
  EXPECT_DOUBLE_EQ(ComputeStats({5, 1, 9}).median, 5);
  const ErrorStats one = ComputeStats({0.25});
  EXPECT_DOUBLE_EQ(one.rmse, 0.25);
  EXPECT_DOUBLE_EQ(one.std, 0);
}

}  // namespace
}  // namespace uf
