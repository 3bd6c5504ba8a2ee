// Constant-velocity motion prior of LiDAR-only odometry (LO mode, no IMU): three consecutive pose nodes
// a, b, c (T_world_body at times t_a < t_b < t_c, nav_state.h layout) should move with the same body-frame
// twist over [t_a, t_b] and [t_b, t_c]. Non-uniform gaps (keyframe data) are handled by dividing each
// segment's motion by its own duration.
//
//   v_ab = R_a^T (t_b - t_a) / dt_ab,        w_ab = Log(R_a^T R_b) / dt_ab      (body frame of a)
//   v_bc = R_b^T (t_c - t_b) / dt_bc,        w_bc = Log(R_b^T R_c) / dt_bc      (body frame of b)
//   r    = [ (v_ab - v_bc) / sigma_v ; (w_ab - w_bc) / sigma_w ]                 (6 residuals)
// The twist changes between the segment middles, dt_mid = (dt_ab + dt_bc) / 2 apart. With white-noise
// acceleration of density q (a random walk of velocity) Var(v_bc - v_ab) = q^2 dt_mid, hence
//   sigma_v = acc_density * sqrt(dt_mid),   sigma_w = angular_acc_density * sqrt(dt_mid).
// (Comparing body-frame velocities of a and b ignores the rotation between a and b: second order.)
// Jacobians by Ceres automatic differentiation in the ambient {t, q} blocks; with PoseManifold they give the
// tangent [dt; dtheta] Jacobians.
#pragma once

#include <ceres/cost_function.h>

#include <memory>

#include "odometry/estimator/config/constant_velocity_noise.h"

namespace uf::estimator {

// dt_ab, dt_bc > 0 seconds and noise densities > 0 (asserted). Blocks: pose_a, pose_b, pose_c (7 each).
std::unique_ptr<ceres::CostFunction> MakeConstantVelocityFactor(double dt_ab, double dt_bc,
                                                                const ConstantVelocityNoise& noise);

}  // namespace uf::estimator
