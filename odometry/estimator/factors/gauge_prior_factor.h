// The gauge prior of a window whose factors are all relative motion (IMU, wheel): it holds the position and
// the yaw of one pose (T_world_imu, nav_state.h layout) at given values and leaves roll and pitch free.
//
// Why those four directions: IMU preintegration and wheel factors are unchanged when the whole trajectory
// moves by a rigid motion that keeps gravity, p_k -> Rz(a) p_k + t, R_k -> Rz(a) R_k (Rz a rotation about
// the world's z axis, the direction of gravity): the IMU factor sees the world only through
// g = (0, 0, -gravity), which Rz(a) leaves alone, and the wheel factor only relative poses. So the cost has
// a 4-dimensional null space (translation t, yaw a), and nothing else fixes it; roll and pitch are observed
// (the accelerometer measures gravity in the body frame) and must not be held. The prior fixes exactly the
// null space:
//   r = [ (p - p0) / sigma_p ;  wrap(yaw(R) - yaw0) / sigma_yaw ],   yaw(R) = atan2(R_10, R_00),
// the heading of the body x axis projected on the level plane. Under the null-space motion p moves by t
// and yaw(R) by a exactly (for any roll and pitch, away from pitch +-90 degrees), so the prior selects one
// point of the null space and changes nothing else: its sigmas set only how firmly, not the solution.
// Marked anchoring in the graph, it is folded into the marginalization prior when its node leaves, so the
// prior keeps the gauge and carries the velocity, bias and scale information of the leaving states.
//
// Jacobians by Ceres automatic differentiation in the ambient {t, q} block (PoseManifold gives the tangent).
#pragma once

#include <ceres/cost_function.h>

#include <memory>

#include "odometry/types/se3.h"

namespace uf::estimator {

// sigma_position_m, sigma_yaw_rad finite and > 0 (asserted). One block: the pose (7).
std::unique_ptr<ceres::CostFunction> MakeGaugePriorFactor(const SE3& T_world_imu, double sigma_position_m,
                                                          double sigma_yaw_rad);

// yaw(R) = atan2(R_10, R_00) of the rotation, rad.
double Yaw(const SO3& R);

}  // namespace uf::estimator
