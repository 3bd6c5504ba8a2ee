// Trajectory::PoseAt against hand-computed poses: stored poses returned as they are at their stamps, slerp
// and lerp between them, nothing outside the stamps' span.
#include <gtest/gtest.h>

#include <numbers>

#include "odometry/types/trajectory.h"

namespace uf {
namespace {

constexpr double kPi = std::numbers::pi;

SO3 Yaw(double rad) { return SO3::Exp(Eigen::Vector3d(0, 0, rad)); }

// Stamps 0, 1 s, 3 s: identity; yaw 90 deg at (1, 0, 0); yaw 90 deg at (1, 2, 0).
Trajectory ThreePoses() {
  Trajectory trajectory;
  trajectory.stamps = {0, 1'000'000'000, 3'000'000'000};
  trajectory.poses = {SE3(), SE3(Yaw(kPi / 2), Eigen::Vector3d(1, 0, 0)),
                      SE3(Yaw(kPi / 2), Eigen::Vector3d(1, 2, 0))};
  return trajectory;
}

TEST(TrajectoryPoseAt, StoredPosesAtTheirStampsExactly) {
  const Trajectory trajectory = ThreePoses();
  for (std::size_t i = 0; i < trajectory.size(); ++i) {
    const std::optional<SE3> pose = trajectory.PoseAt(trajectory.stamps[i]);
    ASSERT_TRUE(pose) << i;
    EXPECT_EQ(pose->matrix(), trajectory.poses[i].matrix()) << i;  // bit for bit, also at the last stamp
  }
}

TEST(TrajectoryPoseAt, SlerpAndLerpBetweenTheBracketingPoses) {
  const Trajectory trajectory = ThreePoses();
  // 0.5 s: halfway from the identity to yaw 90 deg at (1, 0, 0): yaw 45 deg at (0.5, 0, 0).
  std::optional<SE3> pose = trajectory.PoseAt(500'000'000);
  ASSERT_TRUE(pose);
  EXPECT_TRUE(pose->rotation().isApprox(Yaw(kPi / 4).matrix(), 1e-12));
  EXPECT_TRUE(pose->translation().isApprox(Eigen::Vector3d(0.5, 0, 0), 1e-12));
  // 2.5 s: three quarters of the 2 s step from (1, 0, 0) to (1, 2, 0), same yaw.
  pose = trajectory.PoseAt(2'500'000'000);
  ASSERT_TRUE(pose);
  EXPECT_TRUE(pose->rotation().isApprox(Yaw(kPi / 2).matrix(), 1e-12));
  EXPECT_TRUE(pose->translation().isApprox(Eigen::Vector3d(1, 1.5, 0), 1e-12));
  // One nanosecond after a stamp: s = 1e-9 of the 1 s step.
  pose = trajectory.PoseAt(1);
  ASSERT_TRUE(pose);
  EXPECT_NEAR(pose->translation().x(), 1e-9, 1e-18);
}

TEST(TrajectoryPoseAt, NoneOutsideTheSpanOrWithoutStamps) {
  const Trajectory trajectory = ThreePoses();
  EXPECT_FALSE(trajectory.PoseAt(-1));
  EXPECT_FALSE(trajectory.PoseAt(3'000'000'001));
  Trajectory stampless;
  stampless.poses = {SE3()};
  EXPECT_FALSE(stampless.PoseAt(0));
  EXPECT_FALSE(Trajectory().PoseAt(0));
}

}  // namespace
}  // namespace uf
