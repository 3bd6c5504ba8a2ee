#include "odometry/estimator/lidar_odometry/imu_sweep_correction.h"

#include <algorithm>
#include <cassert>
#include <cmath>

#include "odometry/estimator/lidar_odometry/sweep_poses.h"

namespace uf::estimator {

ImuSweepCorrection::ImuSweepCorrection(std::span<const SE3> predicted, const SE3& T_body_lidar) {
  assert(predicted.size() == kSteps + 1);
  const SE3 T_lidar_body = T_body_lidar.inverse();
  table_.reserve(kSteps + 1);
  for (int i = 0; i <= kSteps; ++i) {
    const double alpha = static_cast<double>(i) / kSteps;
    const SE3 D = PoseAt(predicted.front(), predicted.back(), alpha).inverse() * predicted[i];
    max_translation_m_ = std::max(max_translation_m_, D.translation().norm());
    max_rotation_rad_ = std::max(max_rotation_rad_, D.so3().Log().norm());
    table_.push_back(T_lidar_body * D * T_body_lidar);
  }
}

Eigen::Vector3d ImuSweepCorrection::Apply(const Eigen::Vector3d& point_lidar, double alpha) const {
  const long i = std::lround(std::clamp(alpha, 0.0, 1.0) * kSteps);
  return table_[static_cast<std::size_t>(i)] * point_lidar;
}

}  // namespace uf::estimator
