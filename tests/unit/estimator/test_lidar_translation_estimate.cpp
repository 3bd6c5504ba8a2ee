// The LiDAR extrinsic's translation estimated in the LIO window (lio.estimate_lidar_translation), against
// the simulator's true mount: a handheld device given a translation 9 cm off ends within 1 cm of the truth,
// and its whole run (the keyframes held until the estimate settled) is as accurate as with the true mount;
// a vehicle that only turns about the vertical never frees it (the excitation gate) and gets every keyframe
// by the end; without the IMU's sweep correction the configuration is refused.
#include <gtest/gtest.h>

#include <filesystem>

#include "odometry/estimator/lidar_odometry/lidar_odometry.h"
#include "tests/support/temp_dir.h"
#include "tests/unit/estimator/lio_sequence_run.h"
#include "tests/unit/estimator/lio_test_support.h"

namespace uf::estimator {
namespace {

const Eigen::Vector3d kTranslationError(0.06, -0.04, -0.05);  // m, 8.8 cm

// LIO given the translation off by kTranslationError, estimating it or not.
testing::LioRun RunGivenWrongTranslation(const std::filesystem::path& folder, bool estimate,
                                         bool evaluate = true) {
  return testing::RunLio(
      folder, [](ImuSample&) { return true; }, nullptr, evaluate,
      [estimate](LidarOdometryConfig& config) {
        config.T_body_lidar =
            SE3(testing::kSimImuFromLidar.so3(), testing::kSimImuFromLidar.translation() + kTranslationError);
        config.imu_deskew = true;
        config.estimate_lidar_translation = estimate;
      });
}

TEST(LidarTranslationEstimate, AHandheldRunFindsTheTrueMount) {
  const uf::testing::TempDir dir;
  const std::filesystem::path folder = testing::SimulateHandheld(dir, 20, "warehouse");
  const testing::LioRun estimated = RunGivenWrongTranslation(folder, true);
  ASSERT_TRUE(estimated.factors.lidar_extrinsic.has_value());
  const Eigen::Vector3d t = estimated.factors.lidar_extrinsic->translation();
  const Eigen::Vector3d error = t - testing::kSimImuFromLidar.translation();
  EXPECT_LT(error.cwiseAbs().maxCoeff(), 0.01) << "estimated " << t.transpose();
  // Only the translation is estimated: the rotation stays the given one.
  EXPECT_LT((estimated.factors.lidar_extrinsic->so3().inverse() * testing::kSimImuFromLidar.so3()).angle(),
            1e-12);
  EXPECT_GT(estimated.factors.lidar_translation_free_solves, estimated.factors.lidar_translation_solves / 2);
  const testing::LioRun held = RunGivenWrongTranslation(folder, false);
  EXPECT_FALSE(held.factors.lidar_extrinsic.has_value());
  const testing::LioRun truth = testing::RunLio(
      folder, [](ImuSample&) { return true; }, nullptr, true,
      [](LidarOdometryConfig& config) { config.imu_deskew = true; });
  // The keyframes that left before the estimate settled were held and moved to it: the whole run is as
  // accurate as with the true mount.
  EXPECT_LT(estimated.ate_m, 0.5 * held.ate_m)
      << "estimated " << estimated.ate_m << " m, held " << held.ate_m;
  EXPECT_LT(estimated.ate_m, 1.5 * truth.ate_m)
      << "estimated " << estimated.ate_m << " m, true " << truth.ate_m;
  EXPECT_EQ(estimated.estimate.size(), truth.estimate.size());
}

TEST(LidarTranslationEstimate, TurnsAboutOneAxisLeaveItAsGiven) {
  const uf::testing::TempDir dir;
  // Urban driving: 1 s at rest, then off along the street; roll and pitch stay far below 1 deg.
  const std::filesystem::path folder = testing::Simulate(dir, 6);
  const testing::LioRun run = RunGivenWrongTranslation(folder, true, /*evaluate=*/false);
  ASSERT_TRUE(run.factors.lidar_extrinsic.has_value());
  EXPECT_GT(run.factors.lidar_translation_solves, 20);
  EXPECT_EQ(run.factors.lidar_translation_free_solves, 0);
  EXPECT_EQ(run.factors.lidar_extrinsic->translation(),
            testing::kSimImuFromLidar.translation() + kTranslationError);
  // Held while it might still move (at most 50), every keyframe is out by the end of the run.
  EXPECT_GE(run.estimate.size(), 58u);
}

TEST(LidarTranslationEstimate, NeedsTheImuSweepCorrection) {
  LidarOdometryConfig config = testing::SimulatedLioConfig();
  config.estimate_lidar_translation = true;
  const Status status = config.Validate();
  EXPECT_NE(status.message().find("lio.estimate_lidar_translation: needs lio.imu_deskew"), std::string::npos)
      << status.message();
  config.imu_deskew = true;
  EXPECT_TRUE(config.Validate().ok());
  config.lidar_translation_sigma_m = 0;
  EXPECT_NE(config.Validate().message().find("lio.lidar_translation_sigma_m"), std::string::npos);
}

}  // namespace
}  // namespace uf::estimator
