// Registration acceptance and recovery of the LiDAR window (docs/METHOD.md "Registration, acceptance and
// recovery") on synthetic box-room scans with exact geometry: scans that no longer match the map are rejected
// (predicted pose kept, no points), repeated rejections restart the local map, the constant-velocity guess
// is bounded in time, and every such event is reported.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "odometry/estimator/lidar_odometry/lidar_odometry.h"
#include "tests/unit/estimator/box_room_scan.h"

namespace uf::estimator {
namespace {

constexpr Stamp kScan = 100'000'000;  // 0.1 s sweeps

struct Tracked {
  std::vector<Keyframe> keyframes;
  std::vector<TrackEvent> events;
};

Tracked Finish(LidarOdometry& lo, Tracked tracked) {
  lo.Finish();
  for (Keyframe& k : lo.TakeFinished()) tracked.keyframes.push_back(std::move(k));
  for (TrackEvent& e : lo.TakeEvents()) tracked.events.push_back(std::move(e));
  return tracked;
}

int Count(const std::vector<TrackEvent>& events, TrackEvent::Kind kind) {
  return static_cast<int>(
      std::count_if(events.begin(), events.end(), [&](const TrackEvent& e) { return e.kind == kind; }));
}

// The sensor stands still for 6 scans, then (between two scans, as if in a gap of the data) turns by 90 deg
// in the room, which is 20 x 12 m: the map no longer fits any guess near the last pose, so the next scans are
// rejected; after max_rejected_scans of them the local map restarts, and the scans after that register
// against the new map. No pose is ever non-finite, and the rejected scans bring no points.
TEST(LidarOdometryRecovery, RepeatedRejectionsRestartTheLocalMap) {
  LidarOdometryConfig config;
  config.max_solver_time_s = 10;  // only the iteration budget: the result does not depend on the load
  auto lo = LidarOdometry::Create(config);
  ASSERT_TRUE(lo.ok());
  const Eigen::Vector3d at(-3, -1, 0);
  for (int k = 0; k < 12; ++k)
    ASSERT_TRUE(lo->AddScan(BoxRoomScan(k * kScan, at, Eigen::Vector3d::Zero(), 0, k >= 6)).ok());
  const Tracked tracked = Finish(*lo, {});
  const std::vector<TrackEvent>& events = tracked.events;
  ASSERT_EQ(Count(events, TrackEvent::Kind::kRejected), config.max_rejected_scans);
  ASSERT_EQ(Count(events, TrackEvent::Kind::kRestarted), 1);
  EXPECT_EQ(events.front().stamp, 6 * kScan);  // the first turned scan
  EXPECT_EQ(events.back().kind, TrackEvent::Kind::kRestarted);
  EXPECT_EQ(events.back().stamp, (6 + config.max_rejected_scans - 1) * kScan);
  EXPECT_NE(events.back().detail.find("discontinuity"), std::string::npos) << events.back().detail;

  ASSERT_EQ(tracked.keyframes.size(), 12u);
  for (std::size_t k = 0; k < tracked.keyframes.size(); ++k) {
    const Keyframe& keyframe = tracked.keyframes[k];
    EXPECT_TRUE(keyframe.T_world_body.matrix().allFinite()) << k;
    const bool rejected = k >= 6 && k < 6u + config.max_rejected_scans - 1;  // the last one starts the map
    EXPECT_EQ(keyframe.scan_world.empty(), rejected) << k;
  }
  // After the restart the scans register against the new map: the sensor stands still, so they keep the
  // restart scan's pose.
  const SE3& anchor = tracked.keyframes[6 + config.max_rejected_scans - 1].T_world_body;
  for (std::size_t k = 6 + config.max_rejected_scans; k < 12; ++k) {
    const SE3 step = anchor.inverse() * tracked.keyframes[k].T_world_body;
    EXPECT_LT(step.translation().norm(), 0.02) << k;
    EXPECT_LT(step.so3().angle(), 0.002) << k;
  }
}

// A LiDAR stream that stops for 5 s: the sensor moved at 1 m/s and then stood still 0.3 m further on. The
// constant-velocity guess extrapolates at most max_prediction_s (0.5 m at 1 m/s), close enough for the
// registration; unbounded it would guess 5 m ahead, outside the plane association's reach.
TEST(LidarOdometryRecovery, ConstantVelocityGuessIsBoundedInTime) {
  LidarOdometryConfig config;
  config.max_solver_time_s = 10;
  auto lo = LidarOdometry::Create(config);
  ASSERT_TRUE(lo.ok());
  const Eigen::Vector3d start(-5, -1, 0), v(1, 0, 0);
  for (int k = 0; k < 8; ++k) ASSERT_TRUE(lo->AddScan(BoxRoomScan(k * kScan, start + v * (0.1 * k), v)).ok());
  const Eigen::Vector3d stopped = start + v * 1.1;
  for (int k = 0; k < 4; ++k) ASSERT_TRUE(lo->AddScan(BoxRoomScan(6'000'000'000 + k * kScan, stopped)).ok());
  const Tracked tracked = Finish(*lo, {});
  EXPECT_EQ(Count(tracked.events, TrackEvent::Kind::kRejected), 0);
  EXPECT_EQ(Count(tracked.events, TrackEvent::Kind::kRestarted), 0);
  ASSERT_EQ(tracked.keyframes.size(), 12u);
  // The world is the body at the first sweep's middle (t = 0.05 s, start + 0.05 v).
  const Eigen::Vector3d truth = stopped - (start + v * 0.05);
  for (std::size_t k = 8; k < 12; ++k)
    EXPECT_LT((tracked.keyframes[k].T_world_body.translation() - truth).norm(), 0.03) << k;
}

TEST(LidarOdometryRecovery, ConfigNamesTheRecoveryFields) {
  LidarOdometryConfig config;
  config.min_match_ratio = 1.5;
  EXPECT_EQ(config.Validate().message(), "lo.min_match_ratio: must be in [0, 1], got 1.5");
  config = {};
  config.max_rejected_scans = 0;
  EXPECT_EQ(config.Validate().message(), "lo.max_rejected_scans: must be >= 1, got 0");
  config = {};
  config.max_prediction_s = 0;
  EXPECT_EQ(config.Validate().message(), "lo.max_prediction_s: must be > 0, got 0");
  config = {};
  config.max_angular_rate_rad_s = -1;
  EXPECT_EQ(config.Validate().message(), "lo.max_angular_rate_rad_s: must be > 0, got -1");
}

}  // namespace
}  // namespace uf::estimator
