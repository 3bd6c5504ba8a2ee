// DeskewWithTrajectory against hand-computed points: a constant-velocity trajectory (10 m/s along x, yaw rate
// 0.2 rad/s) gives each point the pose at its own time; the keyframe sits at the middle of the sweep; points
// outside the trajectory's time span and outside the range limits are dropped; without point times every
// point takes the middle pose.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "mapping/deskew_with_trajectory.h"

namespace uf::mapping {
namespace {

// T_world_est from t = 0 to 1 s: 10 m/s along x and 0.2 rad/s about z, so at t the pose is
// (Rz(0.2 t), (10 t, 0, 0)) (slerp about a fixed axis and lerp are exact for this motion).
Trajectory ConstantVelocity() {
  Trajectory trajectory;
  trajectory.stamps = {0, FromSeconds(1.0)};
  trajectory.poses = {SE3(), SE3(SO3::Exp(Eigen::Vector3d(0, 0, 0.2)), Eigen::Vector3d(10, 0, 0))};
  return trajectory;
}

// The LiDAR 0.5 m ahead of and 1 m above the estimator's body, axes aligned.
SE3 EstFromLidar() { return SE3(SO3(), Eigen::Vector3d(0.5, 0, 1)); }

// The hand-computed world point of LiDAR point p measured at t seconds.
Eigen::Vector3d WorldPoint(const Eigen::Vector3d& p, double t) {
  const double yaw = 0.2 * t, x = p.x() + 0.5, y = p.y(), z = p.z() + 1;
  return {10 * t + std::cos(yaw) * x - std::sin(yaw) * y, std::sin(yaw) * x + std::cos(yaw) * y, z};
}

LidarPoint Point(float x, float y, float z, double offset_s, float intensity = 0) {
  LidarPoint point;
  point.x = x, point.y = y, point.z = z;
  point.offset_ns = static_cast<std::int32_t>(FromSeconds(offset_s));
  point.intensity = intensity;
  return point;
}

void ExpectPoint(const Eigen::Vector3f& actual, const Eigen::Vector3d& expected) {
  EXPECT_NEAR(actual.x(), expected.x(), 1e-5);
  EXPECT_NEAR(actual.y(), expected.y(), 1e-5);
  EXPECT_NEAR(actual.z(), expected.z(), 1e-5);
}

TEST(DeskewWithTrajectory, EachPointTakesThePoseAtItsOwnTime) {
  LidarScan scan;
  scan.stamp = FromSeconds(0.2);
  scan.end = FromSeconds(0.6);
  scan.has_point_times = true;
  scan.points = {Point(10, 0, 0, 0.0, 7), Point(0, 5, 2, 0.2, 8), Point(-3, 4, 0, 0.4, 9)};
  const std::optional<Keyframe> keyframe =
      DeskewWithTrajectory(scan, ConstantVelocity(), EstFromLidar(), 1, 100);
  ASSERT_TRUE(keyframe.has_value());
  // The keyframe at the middle of the sweep, t = 0.4 s: (Rz(0.08), (4, 0, 0)).
  EXPECT_EQ(keyframe->stamp, FromSeconds(0.4));
  EXPECT_NEAR(keyframe->T_world_body.translation().x(), 4.0, 1e-12);
  EXPECT_NEAR(keyframe->T_world_body.so3().angle(), 0.08, 1e-12);
  ASSERT_EQ(keyframe->scan_world.size(), 3u);
  ExpectPoint(keyframe->scan_world[0], WorldPoint({10, 0, 0}, 0.2));
  ExpectPoint(keyframe->scan_world[1], WorldPoint({0, 5, 2}, 0.4));
  ExpectPoint(keyframe->scan_world[2], WorldPoint({-3, 4, 0}, 0.6));
  EXPECT_EQ(keyframe->scan_intensity, (std::vector<float>{7, 8, 9}));
}

TEST(DeskewWithTrajectory, WithoutPointTimesTheWholeScanTakesTheMiddlePose) {
  LidarScan scan;
  scan.stamp = FromSeconds(0.2);
  scan.end = FromSeconds(0.6);
  scan.has_point_times = false;  // the offsets below are meaningless
  scan.points = {Point(10, 0, 0, 0.0), Point(0, 5, 2, 0.4)};
  const std::optional<Keyframe> keyframe =
      DeskewWithTrajectory(scan, ConstantVelocity(), EstFromLidar(), 1, 100);
  ASSERT_TRUE(keyframe.has_value());
  ASSERT_EQ(keyframe->scan_world.size(), 2u);
  ExpectPoint(keyframe->scan_world[0], WorldPoint({10, 0, 0}, 0.4));
  ExpectPoint(keyframe->scan_world[1], WorldPoint({0, 5, 2}, 0.4));
}

TEST(DeskewWithTrajectory, PointsOutsideTheTrajectorysTimeSpanAreDropped) {
  // The sweep from 0.8 to 1.2 s: its middle (1.0 s, the last pose) is covered, its end is not.
  LidarScan scan;
  scan.stamp = FromSeconds(0.8);
  scan.end = FromSeconds(1.2);
  scan.has_point_times = true;
  scan.points = {Point(10, 0, 0, 0.1, 1), Point(10, 0, 0, 0.2, 2), Point(10, 0, 0, 0.3, 3)};
  const std::optional<Keyframe> keyframe =
      DeskewWithTrajectory(scan, ConstantVelocity(), EstFromLidar(), 1, 100);
  ASSERT_TRUE(keyframe.has_value());
  ASSERT_EQ(keyframe->scan_world.size(), 2u);  // at 0.9 s and 1.0 s; 1.1 s is beyond the last pose
  ExpectPoint(keyframe->scan_world[0], WorldPoint({10, 0, 0}, 0.9));
  ExpectPoint(keyframe->scan_world[1], WorldPoint({10, 0, 0}, 1.0));
  EXPECT_EQ(keyframe->scan_intensity, (std::vector<float>{1, 2}));

  // A sweep whose middle lies after the last pose gives no keyframe at all.
  scan.stamp = FromSeconds(1.0);
  scan.end = FromSeconds(1.4);
  EXPECT_FALSE(DeskewWithTrajectory(scan, ConstantVelocity(), EstFromLidar(), 1, 100).has_value());
  // Nor does a trajectory without stamps.
  Trajectory unstamped = ConstantVelocity();
  unstamped.stamps.clear();
  scan.stamp = FromSeconds(0.2);
  scan.end = FromSeconds(0.6);
  EXPECT_FALSE(DeskewWithTrajectory(scan, unstamped, EstFromLidar(), 1, 100).has_value());
}

TEST(DeskewWithTrajectory, KeepsOnlyFinitePointsWithinTheRangeLimits) {
  LidarScan scan;
  scan.stamp = 0;
  scan.end = FromSeconds(0.2);
  scan.has_point_times = true;
  const float nan = std::numeric_limits<float>::quiet_NaN();
  scan.points = {Point(0.5f, 0, 0, 0.1, 1),  // range 0.5 < 2: too close
                 Point(2, 0, 0, 0.1, 2),     // range 2: the lower limit is kept
                 Point(0, 3, 4, 0.1, 3),     // range 5
                 Point(0, 0, 10, 0.1, 4),    // range 10: the upper limit is kept
                 Point(0, 6, 8.5f, 0.1, 5),  // range ~10.4 > 10: too far
                 Point(nan, 0, 0, 0.1, 6)};  // not finite
  const std::optional<Keyframe> keyframe =
      DeskewWithTrajectory(scan, ConstantVelocity(), EstFromLidar(), 2, 10);
  ASSERT_TRUE(keyframe.has_value());
  EXPECT_EQ(keyframe->scan_intensity, (std::vector<float>{2, 3, 4}));
  ASSERT_EQ(keyframe->scan_world.size(), 3u);
  ExpectPoint(keyframe->scan_world[1], WorldPoint({0, 3, 4}, 0.1));
}

}  // namespace
}  // namespace uf::mapping
