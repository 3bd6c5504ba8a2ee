#include "odometry/estimator/lidar_odometry/sweep_poses.h"

#include <cmath>

#include "odometry/types/so3.h"

namespace uf::estimator {

SE3 PoseAt(const SE3& begin, const SE3& end, double alpha) {
  const Eigen::Vector3d d = (begin.so3().inverse() * end.so3()).Log();
  return SE3(begin.so3() * SO3::Exp(alpha * d),
             (1.0 - alpha) * begin.translation() + alpha * end.translation());
}

SweepPoses::SweepPoses(const SE3& begin, const SE3& end, const SE3& T_body_lidar, bool single) {
  if (single) {
    poses_.push_back(begin * T_body_lidar);
    return;
  }
  poses_.reserve(kSteps + 1);
  const Eigen::Vector3d d = (begin.so3().inverse() * end.so3()).Log();
  for (int i = 0; i <= kSteps; ++i) {
    const double alpha = static_cast<double>(i) / kSteps;
    poses_.push_back(SE3(begin.so3() * SO3::Exp(alpha * d),
                         (1.0 - alpha) * begin.translation() + alpha * end.translation()) *
                     T_body_lidar);
  }
}

const SE3& SweepPoses::At(double alpha) const {
  if (poses_.size() == 1) return poses_.front();
  return poses_[static_cast<std::size_t>(std::lround(alpha * kSteps))];
}

}  // namespace uf::estimator
