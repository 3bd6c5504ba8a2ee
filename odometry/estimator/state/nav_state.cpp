#include "odometry/estimator/state/nav_state.h"

#include <Eigen/Geometry>

namespace uf::estimator {

std::array<double, kPoseSize> PoseBlock(const SE3& T) {
  const Eigen::Quaterniond q(T.rotation());
  const Eigen::Vector3d& t = T.translation();
  return {t.x(), t.y(), t.z(), q.x(), q.y(), q.z(), q.w()};
}

SE3 PoseFromBlock(const double* pose) {
  const Eigen::Quaterniond q(pose[6], pose[3], pose[4], pose[5]);
  return SE3(SO3(q), Eigen::Vector3d(pose[0], pose[1], pose[2]));
}

std::array<double, kSpeedBiasSize> SpeedBiasBlock(const NavState& state) {
  const Eigen::Vector3d& v = state.velocity;
  const Eigen::Vector3d& a = state.accel_bias;
  const Eigen::Vector3d& g = state.gyro_bias;
  return {v.x(), v.y(), v.z(), a.x(), a.y(), a.z(), g.x(), g.y(), g.z()};
}

void SetSpeedBias(const double* speed_bias, NavState& state) {
  state.velocity = Eigen::Vector3d(speed_bias[0], speed_bias[1], speed_bias[2]);
  state.accel_bias = Eigen::Vector3d(speed_bias[3], speed_bias[4], speed_bias[5]);
  state.gyro_bias = Eigen::Vector3d(speed_bias[6], speed_bias[7], speed_bias[8]);
}

}  // namespace uf::estimator
