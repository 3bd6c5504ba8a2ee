// Poses along one LiDAR sweep, interpolated between its begin and end poses exactly as PointToPlaneFactor
// does (slerp of rotation, lerp of translation), for deskewing points into the world frame.
#pragma once

#include <vector>

#include "odometry/types/se3.h"

namespace uf::estimator {

// The pose at fraction alpha in [0, 1] between begin and end:
//   R(a) = R_b Exp(a Log(R_b^T R_e)),   t(a) = (1 - a) t_b + a t_e.
SE3 PoseAt(const SE3& begin, const SE3& end, double alpha);

// T_world_lidar = PoseAt(begin, end, alpha) * T_body_lidar over one sweep, tabulated at alpha = i / kSteps
// and looked up at the nearest step: saves an SO3 Exp (and Log) per point. The error is at most half a
// step of the sweep's motion, 1/2048 of it (< 3 mm at 100 m range for a 0.1 rad sweep rotation).
// single: the sweep has one pose (begin), alpha is ignored.
class SweepPoses {
 public:
  static constexpr int kSteps = 1024;
  SweepPoses(const SE3& begin, const SE3& end, const SE3& T_body_lidar, bool single);
  const SE3& At(double alpha) const;

 private:
  std::vector<SE3> poses_;
};

}  // namespace uf::estimator
