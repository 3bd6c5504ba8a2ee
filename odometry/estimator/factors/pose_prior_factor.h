// A prior on a pose block (7, pose layout: t, q_x, q_y, q_z, q_w) about T0, e.g. a free extrinsic about the
// given calibration:
//   r = [ (t - t0) / sigma_t ;  2 sgn(w) vec(q0^-1 q) / sigma_r ]
// where 2 sgn(w) vec(q0^-1 q) is the rotation vector of R0^T R to first order (2 sin(angle / 2) along the
// axis: 0.1 % short of the angle at 10 deg).
//
// Jacobians by Ceres automatic differentiation in the ambient block (PoseManifold gives the tangent).
#pragma once

#include <ceres/cost_function.h>

#include <memory>

#include "odometry/types/se3.h"

namespace uf::estimator {

// sigma_translation_m, sigma_rotation_rad finite and > 0 (asserted). One block: the pose (7).
std::unique_ptr<ceres::CostFunction> MakePosePriorFactor(const SE3& T0, double sigma_translation_m,
                                                         double sigma_rotation_rad);

}  // namespace uf::estimator
