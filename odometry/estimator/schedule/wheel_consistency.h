// The wheel's score of the reliability scheduling (docs/METHOD.md "Factor-wise reliability scheduling";
// paper Sec. III-D, wheel slip consistency): the wheel's motion over a node interval against the IMU's
// prediction of it, which a slipping or lifted wheel does not share:
//   D = w_v min(1, max(e_v / tau_v, c / tau_c)) + (1 - w_v) min(1, e_psi / tau_psi),
//   u     = P (dp_wheel - dp_imu) / dt     (P: onto the wheel's x-y plane, the motion it measures),
//   e_v   = |u - u_0|,  c: the caller's disagreement of the speed changes over a short window,
//   e_psi = |z . (Log dR_wheel - Log dR_imu)| / dt   (z: the wheel's vertical axis in the body frame),
// both motions of the body over the interval, T_body(from)^-1 T_body(to). The IMU predicts from the
// window's velocity, which may itself be off (a LiDAR-degenerate corridor while the vehicle pulls away:
// 0.2-0.7 m/s); u_0, the speed disagreement the recent admitted intervals had (the caller's average),
// takes that out, so that what counts is a change of the wheel against the IMU: a slip's onset, and its end.
#pragma once

#include "odometry/types/keyframe.h"
#include "odometry/types/se3.h"

namespace uf::estimator {

struct WheelScoreWeights {
  double speed_tolerance_mps = 0.5;       // tau_v: the speed disagreement that saturates its term
  double yaw_rate_tolerance_rad_s = 1.0;  // tau_psi
  double speed_weight = 0.5;              // w_v
  double change_tolerance_mps = 1.0;      // tau_c
};

struct WheelScore {
  WheelConsistency consistency;                            // `active` left true (the gate decides it)
  Eigen::Vector2d disagreement = Eigen::Vector2d::Zero();  // u, m/s
};

// baseline: u_0 (m/s, the wheel's plane); change: c (m/s).
WheelScore ScoreWheelMotion(const SE3& wheel_motion, const SE3& imu_motion, const SO3& R_body_wheel,
                            double dt, const Eigen::Vector2d& baseline, double change,
                            const WheelScoreWeights& weights);

}  // namespace uf::estimator
