#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

#include "odometry/estimator/visual/epipolar_check.h"
#include "odometry/types/se3.h"

namespace uf::estimator {
namespace {

// A camera translated along x with K = I: the fundamental matrix is the essential matrix [t]x with
// t = (1, 0, 0), so x2^T F x1 = y1 - y2 (the pair's vertical disparity), and both gradient terms are 1:
// the Sampson distance is |y1 - y2| / sqrt(2).
TEST(EpipolarCheck, SampsonDistanceOfASidewaysTranslationIsTheVerticalDisparityOverRootTwo) {
  Eigen::Matrix3d F;
  F << 0, 0, 0,  //
      0, 0, -1,  //
      0, 1, 0;
  EXPECT_NEAR(SampsonDistance(F, {0.3, 0.2}, {0.9, 0.2}), 0.0, 1e-15);
  EXPECT_NEAR(SampsonDistance(F, {0.3, 0.2}, {-0.4, 0.5}), 0.3 / std::sqrt(2.0), 1e-15);
}

TEST(EpipolarCheck, RansacFlagsTheGrossOutliersAndFitsTheRest) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> lateral(-4, 4), depth(4, 20);
  std::normal_distribution<double> noise(0, 0.2);  // px
  const double f = 400, c = 320;
  const SE3 T_2_1(SO3::Exp(Eigen::Vector3d(0.02, -0.05, 0.01)), Eigen::Vector3d(0.4, 0.05, 0.6));
  std::vector<Eigen::Vector2d> from, to;
  std::vector<bool> corrupted;
  for (int i = 0; i < 120; ++i) {
    const Eigen::Vector3d p1(lateral(rng), lateral(rng) * 0.6, depth(rng));
    const Eigen::Vector3d p2 = T_2_1 * p1;
    from.emplace_back(f * p1.x() / p1.z() + c + noise(rng), f * p1.y() / p1.z() + c + noise(rng));
    to.emplace_back(f * p2.x() / p2.z() + c + noise(rng), f * p2.y() / p2.z() + c + noise(rng));
    corrupted.push_back(i % 10 == 3);
    if (corrupted.back()) to.back() += Eigen::Vector2d(15, -20);
  }
  const EpipolarFit fit = FitEpipolar(from, to, 1.0, 0.99);
  ASSERT_TRUE(fit.fitted);
  int wrong = 0;
  for (std::size_t i = 0; i < from.size(); ++i) wrong += corrupted[i] == fit.inlier[i];
  EXPECT_LE(wrong, 3);  // an outlier may fall on its epipolar line by chance; clean pairs may miss narrowly
  EXPECT_LT(fit.mean_sampson_px, 0.3);

  const std::vector<Eigen::Vector2d> few(from.begin(), from.begin() + 7), few_to(to.begin(), to.begin() + 7);
  const EpipolarFit none = FitEpipolar(few, few_to, 1.0, 0.99);
  EXPECT_FALSE(none.fitted);
  EXPECT_EQ(none.inlier, std::vector<bool>(7, true));
}

}  // namespace
}  // namespace uf::estimator
