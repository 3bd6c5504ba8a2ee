// LiDAR-only odometry: bad input is skipped with a warning (no NaN out), configuration errors name the
// field, results do not depend on the number of threads, and on the recorded KITTI 00 keyframes (skipped
// without /work/shared/data) the trajectory stays within a bound of the ground truth.
#include <gtest/gtest.h>
#include <tbb/global_control.h>
#include <tbb/info.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <iostream>
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
  std::cout << "worst keyframe position error " << worst << " m\n";
  // Measured 0.008 m; 0.013 m while the first sweep stayed mapped as if at rest (up to 0.05 m off at its
  // ends, the later sweeps registered against it), before it was deskewed once the next scans gave its
  // motion.
  EXPECT_LT(worst, 0.02);
}

// Distance from p to the nearest face of the box room [lo, hi] (a point inside it; the pillar's faces are
// not counted, so the few points on them stay far).
double DistanceToRoom(const Eigen::Vector3d& p, const Eigen::Vector3d& lo, const Eigen::Vector3d& hi) {
  return std::min((p - lo).cwiseAbs().minCoeff(), (hi - p).cwiseAbs().minCoeff());
}

// The first sweep of a map has one node and no known motion when it is mapped; once the next scan gives its
// motion, it is deskewed by it (extrapolated at constant velocity) and the map rebuilt. At 3 m/s the sweep
// moves 0.3 m: mapped as if at rest, its points lie up to 0.15 m off the walls. The first keyframe's points
// against the true room (the world is the body at the first sweep's middle): the 90th percentile of their
// distances to a wall measured 3.7 mm (34 mm without the deskew; floor and ceiling are right either way,
// the motion being level, so the median says little: 0.6 mm, 0 without).
TEST(LidarOdometry, TheFirstSweepIsDeskewedOnceTheNextGivesItsMotion) {
  const Eigen::Vector3d v(3.0, 1.0, 0.0), start(-3, -1, 0);
  auto lo = LidarOdometry::Create({});
  ASSERT_TRUE(lo.ok());
  for (int k = 0; k < 6; ++k)
    ASSERT_TRUE(lo->AddScan(BoxRoomScan(k * 100'000'000LL, start + v * (0.1 * k), v)).ok());
  lo->Finish();
  const std::vector<Keyframe> keyframes = lo->TakeFinished();
  ASSERT_EQ(keyframes.size(), 6u);
  const Eigen::Vector3d origin = start + v * 0.05;  // the world's origin in the room
  const Eigen::Vector3d lo_corner = Eigen::Vector3d(-10, -6, -1.5) - origin;
  const Eigen::Vector3d hi_corner = Eigen::Vector3d(10, 6, 2.5) - origin;
  std::vector<double> distances;
  for (const Eigen::Vector3f& p : keyframes[0].scan_world)
    distances.push_back(DistanceToRoom(p.cast<double>(), lo_corner, hi_corner));
  ASSERT_GT(distances.size(), 1000u);
  std::sort(distances.begin(), distances.end());
  const double p90 = distances[distances.size() * 9 / 10];
  std::cout << "first keyframe: 90th percentile of the distances to the room's walls " << p90 * 1000
            << " mm\n";
  EXPECT_LT(p90, 0.01);
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
