#include "odometry/estimator/schedule/wheel_consistency.h"

#include <algorithm>
#include <cmath>

namespace uf::estimator {

WheelScore ScoreWheelMotion(const SE3& wheel_motion, const SE3& imu_motion, const SO3& R_body_wheel,
                            double dt, const Eigen::Vector2d& baseline, double change,
                            const WheelScoreWeights& weights) {
  WheelScore score;
  WheelConsistency& c = score.consistency;
  if (!(dt > 0)) {
    c.score = 1.0;
    return score;
  }
  const Eigen::Vector3d d = R_body_wheel.inverse() * (wheel_motion.translation() - imu_motion.translation());
  score.disagreement = d.head<2>() / dt;
  c.speed_error_mps = (score.disagreement - baseline).norm();
  c.speed_change_error_mps = change;
  const Eigen::Vector3d up = R_body_wheel.matrix().col(2);
  c.yaw_rate_error_rad_s = std::abs(up.dot(wheel_motion.so3().Log() - imu_motion.so3().Log())) / dt;
  const double speed =
      std::max(c.speed_error_mps / weights.speed_tolerance_mps, change / weights.change_tolerance_mps);
  c.score =
      weights.speed_weight * std::min(1.0, speed) +
      (1 - weights.speed_weight) * std::min(1.0, c.yaw_rate_error_rad_s / weights.yaw_rate_tolerance_rad_s);
  if (!std::isfinite(c.score)) c.score = 1.0;
  return score;
}

}  // namespace uf::estimator
