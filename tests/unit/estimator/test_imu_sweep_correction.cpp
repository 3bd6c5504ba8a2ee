// ImuSweepCorrection against a constructed sweep: a body that accelerates and changes its turn rate within
// the sweep measures a fixed world point from a mounted LiDAR; after the correction the window's
// interpolation between the sweep's ends (PoseAt, the constant velocity) puts every measurement back on that
// point. A sweep at constant velocity needs no correction.
#include <gtest/gtest.h>

#include <vector>

#include "odometry/estimator/lidar_odometry/imu_sweep_correction.h"
#include "odometry/estimator/lidar_odometry/sweep_poses.h"
#include "odometry/types/so3.h"

namespace uf::estimator {
namespace {

// The body at fraction a of a 0.1 s sweep: 10 m/s forward braking at 6 m/s^2, a vertical shake of 5 mm at
// 40 Hz, and a yaw rate rising from 0.5 to 2.5 rad/s with a roll oscillation of 0.5 deg.
SE3 Body(double a, bool accelerating) {
  const double t = 0.1 * a;
  if (!accelerating) return SE3(SO3::Exp(Eigen::Vector3d(0, 0, 0.5 * t)), Eigen::Vector3d(10 * t, 1, 0.5));
  const Eigen::Vector3d rotation(0.0087 * std::sin(2 * 3.14159265 * 25 * t), 0, 0.5 * t + 10 * t * t);
  return SE3(SO3::Exp(rotation),
             Eigen::Vector3d(10 * t - 3 * t * t, 1, 0.5 + 0.005 * std::sin(2 * 3.14159265 * 40 * t)));
}

std::vector<SE3> Predicted(bool accelerating) {
  std::vector<SE3> poses;
  for (int i = 0; i <= ImuSweepCorrection::kSteps; ++i)
    poses.push_back(Body(static_cast<double>(i) / ImuSweepCorrection::kSteps, accelerating));
  return poses;
}

const SE3 kBodyLidar(SO3::Exp(Eigen::Vector3d(0.01, -0.02, 0.3)), Eigen::Vector3d(0.4, -0.1, 0.3));

TEST(ImuSweepCorrection, PutsEveryMeasurementOfAWorldPointBackOnItUnderTheInterpolation) {
  const std::vector<SE3> predicted = Predicted(true);
  const ImuSweepCorrection correction(predicted, kBodyLidar);
  const Eigen::Vector3d world_point(25, -8, 2);
  double worst_uncorrected = 0;
  for (int i = 0; i <= ImuSweepCorrection::kSteps; i += 8) {
    const double a = static_cast<double>(i) / ImuSweepCorrection::kSteps;
    const Eigen::Vector3d measured = (predicted[i] * kBodyLidar).inverse() * world_point;
    const SE3 interpolated = PoseAt(predicted.front(), predicted.back(), a) * kBodyLidar;
    EXPECT_LT((interpolated * correction.Apply(measured, a) - world_point).norm(), 1e-9) << a;
    worst_uncorrected = std::max(worst_uncorrected, (interpolated * measured - world_point).norm());
  }
  // Without it the interpolation misplaces the point by cm (the braking and the yaw rate's change).
  EXPECT_GT(worst_uncorrected, 0.01);
  EXPECT_GT(correction.max_translation_m(), 1e-3);
  EXPECT_GT(correction.max_rotation_rad(), 1e-3);
}

TEST(ImuSweepCorrection, IsTheIdentityAtConstantVelocity) {
  const ImuSweepCorrection correction(Predicted(false), kBodyLidar);
  EXPECT_LT(correction.max_translation_m(), 1e-12);
  EXPECT_LT(correction.max_rotation_rad(), 1e-12);
  const Eigen::Vector3d p(12, 3, -1);
  EXPECT_LT((correction.Apply(p, 0.37) - p).norm(), 1e-12);
}

}  // namespace
}  // namespace uf::estimator
