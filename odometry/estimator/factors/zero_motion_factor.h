// Zero motion between two nodes, the stationary branch's factor (a zero-velocity update, ZUPT): while the
// platform stands still (the wheels read no motion over the interval), node j's pose is node i's and both
// velocities are zero:
//   r = [ (t_j - t_i) / sigma_t ;  2 sgn(w) vec(q_i^-1 q_j) / sigma_r ;  v_i / sigma_v ;  v_j / sigma_v ]
//   (12)
// (2 sgn(w) vec(q_i^-1 q_j): the rotation vector of R_i^T R_j to first order). It keeps the LiDAR's noise
// at rest (a degenerate scene's registration wanders by centimetres from scan to scan) out of the
// velocity and the accelerometer bias, which the IMU would otherwise bend to explain it
// (docs/METHOD.md "Stationary branch").
//
// Blocks: pose_i, pose_j (7, pose layout t, q_x, q_y, q_z, q_w), speed_bias_i, speed_bias_j (9, [v, b_a,
// b_g]). Jacobians by Ceres automatic differentiation in the ambient blocks.
#pragma once

#include <ceres/cost_function.h>

#include <memory>

namespace uf::estimator {

struct ZeroMotionSigmas {
  double translation_m = 0.001;
  double rotation_rad = 0.0002;
  double velocity_mps = 0.005;
};

// sigmas finite and > 0 (asserted).
std::unique_ptr<ceres::CostFunction> MakeZeroMotionFactor(const ZeroMotionSigmas& sigmas);

}  // namespace uf::estimator
