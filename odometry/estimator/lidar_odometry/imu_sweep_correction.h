// The IMU's motion within one LiDAR sweep beyond what the window models. The window poses a point at fraction
// alpha of its sweep by interpolating between the sweep's begin and end nodes (PoseAt: slerp and lerp, a
// constant velocity). Within the sweep the body accelerates and its turn rate changes (a hand-held sensor's
// shake, a car's centripetal acceleration); the IMU sees that. With T(alpha) the IMU's prediction of the body
// from the begin node's state, the departure from the interpolation of its own ends is
//   D(alpha) = PoseAt(T(0), T(1), alpha)^-1 T(alpha)      (D(0) = D(1) = identity),
// a body-frame correction that hardly depends on the state it was propagated from: the velocity's part is
// linear in time and cancels, and gravity's is a fixed parabola that the measured specific force cancels.
// A point p measured at alpha is re-expressed as T_lidar_body D(alpha) T_body_lidar p, so that the window's
// interpolation then puts it where the IMU's motion does (FAST-LIO's deskew, kept outside the factors).
#pragma once

#include <Eigen/Core>
#include <span>
#include <vector>

#include "odometry/types/se3.h"

namespace uf::estimator {

class ImuSweepCorrection {
 public:
  static constexpr int kSteps = 128;  // the table's steps over the sweep; a point takes the nearest one

  // predicted: T_world_body at alpha = i / kSteps, i = 0..kSteps (kSteps + 1 poses, asserted).
  ImuSweepCorrection(std::span<const SE3> predicted, const SE3& T_body_lidar);

  // The point (lidar frame, measured at alpha in [0, 1]) as the interpolating window must see it.
  Eigen::Vector3d Apply(const Eigen::Vector3d& point_lidar, double alpha) const;
  // The largest translation and rotation of D over the sweep (m, rad): how far the sweep departs from a
  // constant velocity (tests, diagnostics).
  double max_translation_m() const { return max_translation_m_; }
  double max_rotation_rad() const { return max_rotation_rad_; }

 private:
  std::vector<SE3> table_;  // T_lidar_body D(i / kSteps) T_body_lidar
  double max_translation_m_ = 0, max_rotation_rad_ = 0;
};

}  // namespace uf::estimator
