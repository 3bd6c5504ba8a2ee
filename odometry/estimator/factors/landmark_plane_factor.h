// A landmark held on the LiDAR map's surface (LVIO; docs/METHOD.md "LiDAR-visual-inertial odometry", "Depth
// from the LiDAR map"). A landmark whose anchor ray met a plane of the map took its depth there; this factor
// keeps it on that plane while the window solves its inverse depth, so the map's geometry fixes the
// landmark's distance and the camera's bearings to it measure the motion in metres (without it the depth is
// only the start, and a camera alone knows the motion up to scale).
//
// Blocks: pose_i = T_world_imu of the anchor's node, T_imu_cam (7, pose layout), lambda (1, inverse depth in
// the anchor camera, 1/m), t_d (1, camera time offset, s). With the anchor's normalized coordinates moved to
// the node's time as in reprojection_factor.h, u' = u - (t_d - t_d0) v, and the plane (n, q, sigma):
//   P_c = (u', 1) / lambda,   P_b = R_bc P_c + t_bc,   P_w = R_i P_b + t_i
//   r   = n^T (P_w - q) / sigma
// Jacobians in the tangents ([dt; dtheta], R <- R Exp(dtheta)), with m = n^T / sigma:
//   dr/dt_i  = m                      dr/dtheta_i  = -m R_i [P_b]x
//   dr/dt_bc = m R_i                  dr/dtheta_bc = -m R_i R_bc [P_c]x
//   dr/dlambda = -m R_i R_bc P_c / lambda,   dr/dt_d = -m R_i R_bc (v, 0) / lambda
// No robust loss inside: the window wraps it in its loss.
#pragma once

#include <ceres/sized_cost_function.h>

#include "odometry/estimator/factors/reprojection_factor.h"
#include "odometry/estimator/factors/tangent_jacobian.h"
#include "odometry/estimator/lidar/plane_fit.h"

namespace uf::estimator {

class LandmarkPlaneFactor : public ceres::SizedCostFunction<1, 7, 7, 1, 1>, public TangentJacobianCost {
 public:
  // anchor: the landmark's first observation; td0: the offset its node was made with; plane: in the world,
  // sigma > 0 (asserted).
  LandmarkPlaneFactor(const FeatureObservation& anchor, double td0, const Plane& plane);
  bool Evaluate(double const* const* parameters, double* residuals, double** jacobians) const override;
  // Jacobians 1 x 6 for the pose and the extrinsic, 1 x 1 for lambda and t_d.
  bool EvaluateTangent(double const* const* parameters, double* residuals,
                       double** tangent_jacobians) const override;

 private:
  const FeatureObservation anchor_;
  const double td0_;
  const Plane plane_;
};

}  // namespace uf::estimator
