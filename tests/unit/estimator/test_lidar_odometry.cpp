// LiDAR-only odometry: bad input is skipped with a warning (no NaN out), configuration errors name the
// field, results do not depend on the number of threads, and on the recorded KITTI 00 keyframes (skipped
// without /work/shared/data) the trajectory stays within a bound of the ground truth.
#include <gtest/gtest.h>
#include <tbb/global_control.h>
#include <tbb/info.h>

#include <cmath>
#include <filesystem>
#include <limits>

#include "odometry/estimator/lidar_odometry/lidar_odometry.h"
#include "odometry/eval/evaluation.h"
#include "odometry/io/dataset_reader.h"
#include "odometry/io/trajectory_file.h"
#include "tests/unit/estimator/box_room_scan.h"

namespace uf::estimator {
namespace {

bool AllFinite(const std::vector<Keyframe>& keyframes) {
  for (const Keyframe& k : keyframes)
    if (!k.T_world_body.matrix().allFinite()) return false;
  return true;
}

TEST(LidarOdometryConfig, ValidateNamesField) {
  LidarOdometryConfig config;
  EXPECT_TRUE(config.Validate().ok());
  config.window_size = 1;
  EXPECT_EQ(config.Validate().message(), "lo.window_size: must be >= 2, got 1");
  config = {};
  config.huber_m = -1;
  EXPECT_EQ(config.Validate().message(), "lo.huber_m: must be > 0, got -1");
  EXPECT_FALSE(LidarOdometry::Create(config).ok());
}

TEST(LidarOdometry, SkipsBadScansWithWarnings) {
  auto lo = LidarOdometry::Create({});
  ASSERT_TRUE(lo.ok());
  ASSERT_TRUE(lo->AddScan(BoxRoomScan(1'000'000'000, Eigen::Vector3d::Zero())).ok());
  EXPECT_TRUE(lo->warnings().empty());
  LidarScan empty;  // no points
  empty.stamp = 1'100'000'000;
  empty.end = 1'200'000'000;
  ASSERT_TRUE(lo->AddScan(empty).ok());
  EXPECT_EQ(lo->warnings().size(), 1u);
  LidarScan nans = BoxRoomScan(1'100'000'000, Eigen::Vector3d::Zero());
  for (LidarPoint& p : nans.points) p.x = std::numeric_limits<float>::quiet_NaN();
  ASSERT_TRUE(lo->AddScan(nans).ok());
  EXPECT_EQ(lo->warnings().size(), 2u);
  ASSERT_TRUE(lo->AddScan(BoxRoomScan(500'000'000, Eigen::Vector3d::Zero())).ok());  // earlier
  EXPECT_EQ(lo->warnings().size(), 3u);
  ASSERT_TRUE(lo->AddScan(BoxRoomScan(1'100'000'000, Eigen::Vector3d(0.3, 0, 0))).ok());
  lo->Finish();
  const std::vector<Keyframe> keyframes = lo->TakeFinished();
  ASSERT_EQ(keyframes.size(), 2u);
  EXPECT_TRUE(AllFinite(keyframes));
  EXPECT_EQ(keyframes[0].stamp, 1'050'000'000);
  EXPECT_EQ(keyframes[0].scan_world.size(), keyframes[0].scan_intensity.size());
  EXPECT_FALSE(keyframes[0].scan_world.empty());
}

TEST(LidarOdometry, TracksContinuousSweepsInABoxRoom) {
  // 10 Hz sweeps back to back (shared nodes), moving at (1.0, 0.4, 0) m/s. The world frame is the body at
  // the first sweep's middle (t = 0.05 s), so the keyframe at the middle of sweep k is at v * 0.1 k.
  const Eigen::Vector3d v(1.0, 0.4, 0.0), start(-3, -1, 0);
  auto lo = LidarOdometry::Create({});
  ASSERT_TRUE(lo.ok());
  EXPECT_EQ(lo->map_point_count(), 0u);
  std::vector<Keyframe> keyframes;
  std::size_t points_fed = 0;
  for (int k = 0; k < 20; ++k) {
    const LidarScan scan = BoxRoomScan(k * 100'000'000LL, start + v * (0.1 * k), v);
    ASSERT_TRUE(lo->AddScan(scan).ok());
    points_fed += scan.points.size();
    for (Keyframe& f : lo->TakeFinished()) keyframes.push_back(std::move(f));
  }
  // The map holds a share of the points fed (downsampled, at most max_points_per_voxel per voxel).
  EXPECT_GT(lo->map_point_count(), 0u);
  EXPECT_LT(lo->map_point_count(), points_fed);
  lo->Finish();
  for (Keyframe& f : lo->TakeFinished()) keyframes.push_back(std::move(f));
  ASSERT_EQ(keyframes.size(), 20u);
  EXPECT_TRUE(lo->warnings().empty()) << lo->warnings().front();
  double worst = 0;
  for (int k = 0; k < 20; ++k) {
    const Eigen::Vector3d truth = v * (0.1 * k);
    worst = std::max(worst, (keyframes[k].T_world_body.translation() - truth).norm());
    EXPECT_LT(keyframes[k].T_world_body.so3().angle(), 0.01) << k;
  }
  // Measured 0.013 m: the first sweep is mapped as if at rest (its motion is unknown then, up to 0.05 m
  // off at its ends) and the later sweeps register against that map.
  EXPECT_LT(worst, 0.03);
}

// The plane association and the solver's evaluation run on all cores; the residuals are taken in visiting
// order and the solver's partial sums added in a fixed order, so one thread gives bit-identical keyframes
// (poses and deskewed points).
TEST(LidarOdometry, KeyframesDoNotDependOnTheNumberOfThreads) {
  const Eigen::Vector3d v(1.0, 0.4, 0.0), start(-3, -1, 0);
  auto run = [&](std::size_t threads) {
    const tbb::global_control limit(tbb::global_control::max_allowed_parallelism, threads);
    auto lo = LidarOdometry::Create({});
    EXPECT_TRUE(lo.ok());
    for (int k = 0; k < 8; ++k)
      EXPECT_TRUE(lo->AddScan(BoxRoomScan(k * 100'000'000LL, start + v * (0.1 * k), v)).ok());
    lo->Finish();
    return lo->TakeFinished();
  };
  const std::vector<Keyframe> one = run(1), all = run(tbb::info::default_concurrency());
  ASSERT_EQ(one.size(), 8u);
  ASSERT_EQ(all.size(), one.size());
  for (std::size_t k = 0; k < one.size(); ++k) {
    EXPECT_TRUE(one[k].T_world_body.matrix() == all[k].T_world_body.matrix()) << k;
    EXPECT_TRUE(one[k].scan_world == all[k].scan_world) << k;
  }
}

TEST(LidarOdometry, EndBeforeStampIsMisuse) {
  auto lo = LidarOdometry::Create({});
  ASSERT_TRUE(lo.ok());
  LidarScan scan = BoxRoomScan(2'000'000'000, Eigen::Vector3d::Zero());
  scan.end = scan.stamp - 1;
  EXPECT_FALSE(lo->AddScan(scan).ok());
}

// The first 20 recorded KITTI 00 keyframes (~35 m): ATE well under a bound a broken estimator misses
// (bench_lidar_odometry reports the real figure over all 80).
TEST(LidarOdometry, Kitti00FirstKeyframes) {
  const std::filesystem::path folder = std::filesystem::path(UF_SHARED_DATA) / "kitti00-keyframes";
  if (!std::filesystem::exists(folder)) GTEST_SKIP() << "no recorded data at " << folder;
  auto reader = OpenDataset(folder.string());
  ASSERT_TRUE(reader.ok()) << reader.error();
  auto truth = ReadTrajectory((*reader)->description().ground_truth->string());
  ASSERT_TRUE(truth.ok());
  auto lo = LidarOdometry::Create({});
  ASSERT_TRUE(lo.ok());
  int scans = 0;
  while (scans < 20) {
    auto next = (*reader)->Next();
    ASSERT_TRUE(next.ok());
    if (!*next) break;
    if (const auto* scan = std::get_if<LidarScan>(&(*next)->data)) {
      ASSERT_TRUE(lo->AddScan(*scan).ok());
      ++scans;
    }
  }
  lo->Finish();
  Trajectory estimate;
  for (const Keyframe& k : lo->TakeFinished()) {
    estimate.stamps.push_back(k.stamp);
    estimate.poses.push_back(k.T_world_body);
  }
  auto result = Evaluate(*truth, estimate, EvalOptions{});
  ASSERT_TRUE(result.ok()) << result.error();
  EXPECT_EQ(result->ape_errors.size(), 20u);
  EXPECT_LT(result->ape.rmse, 0.3);
}

}  // namespace
}  // namespace uf::estimator
