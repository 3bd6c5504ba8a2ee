// The measurement and keyframe structs are plain data; these tests pin their documented defaults.
#include <gtest/gtest.h>

#include "odometry/types/keyframe.h"
#include "odometry/types/measurements.h"

namespace uf {
namespace {

TEST(KeyframeTest, DefaultsToIdentityPoseZeroStateAndNoScores) {
  const Keyframe keyframe;
  EXPECT_TRUE(keyframe.T_world_body.matrix().isIdentity());
  EXPECT_TRUE(keyframe.velocity.isZero());
  EXPECT_TRUE(keyframe.bias_acc.isZero());
  EXPECT_TRUE(keyframe.bias_gyro.isZero());
  EXPECT_TRUE(keyframe.scan_world.empty());
  EXPECT_FALSE(keyframe.lidar_degeneracy || keyframe.imu_reliability || keyframe.wheel_consistency);
  EXPECT_TRUE(keyframe.gnss_checks.empty());
}

TEST(MeasurementsTest, DefaultsAreEmptyAndInvalid) {
  const LidarScan scan;
  EXPECT_TRUE(scan.points.empty());
  EXPECT_FALSE(scan.has_point_times);
  EXPECT_FALSE(scan.has_ring);
  EXPECT_TRUE(CameraFrame().image.empty());
  EXPECT_EQ(GnssFix().status, GnssFixStatus::kNoFix);
  EXPECT_TRUE(ImuSample().acc.isZero());
  EXPECT_TRUE(WheelSample().angular_velocity.isZero());
}

}  // namespace
}  // namespace uf
