// LiDAR point-to-plane factors of the sliding window (paper Section III; docs/METHOD.md "LiDAR point-to-plane
// factor"), with per-point deskew inside the factor. Style after Ceres' examples/slam/pose_graph_3d error
// term.
//
// PointToPlaneFactor, blocks: pose_b, pose_e = T_world_body at scan begin and scan end (nav_state.h layout).
// A point p_L measured at fraction a in [0, 1] of the scan (a = (t_i - t_begin) / (t_end - t_begin)):
//   d    = Log(R_b^T R_e)
//   R(a) = R_b Exp(a d),   t(a) = (1 - a) t_b + a t_e                    (slerp / lerp)
//   p_B  = R_BL p_L + t_BL                                             (T_body_lidar, constant)
//   p_w  = R(a) p_B + t(a)
//   r    = n^T (p_w - q) / sigma                                       (plane {n, q, sigma} from the map)
// Jacobians in the tangent [dt; dtheta] of each pose (t <- t + dt, R <- R Exp(dtheta)), lifted to the 7-wide
// ambient blocks with TangentToAmbientJacobian: dr/dp_w = n^T / sigma through the interpolation
// (interpolated_point.h, which has the derivation):
//   dr/dt_b = (1 - a) n^T / sigma,   dr/dt_e = a n^T / sigma
//   dr/dtheta_{b,e} = -n^T R(a) [p_B]x Phi_{b,e} / sigma,   u = a d
//     Phi_b = Exp(u)^T - a Jr(u) Jl(d)^-1,   Phi_e = a Jr(u) Jr(d)^-1
// a = 0 gives Phi_b = I, Phi_e = 0; a = 1 gives Phi_b = 0, Phi_e = I; R_b = R_e gives (1 - a) I and a I.
//
// PointToPlaneFactorSinglePose, block: pose = T_world_body, for a point already deskewed into the body frame
// at that pose (or a scan without point times): r = n^T (R p_B + t - q) / sigma,
//   dr/dt = n^T / sigma,   dr/dtheta = -n^T R [p_B]x / sigma.
//
// The lever-arm variants (LIO with lio.estimate_lidar_translation) take the translation t_BL of T_body_lidar
// from a third (Euclidean, 3) block instead of holding it: p_B = R_BL p_L + t_BL, and
//   dr/dt_BL = n^T R(a) / sigma        (single pose: n^T R / sigma)
// the other Jacobians as above at that p_B.
//
// No robust loss inside: the window wraps these in its Huber loss.
#pragma once

#include <ceres/sized_cost_function.h>

#include <Eigen/Core>

#include "odometry/estimator/factors/tangent_jacobian.h"
#include "odometry/estimator/lidar/plane_fit.h"
#include "odometry/types/se3.h"

namespace uf::estimator {

class PointToPlaneFactor : public ceres::SizedCostFunction<1, 7, 7>, public TangentJacobianCost {
 public:
  // alpha in [0, 1] (asserted), plane.sigma > 0 (asserted), plane.normal of unit length.
  PointToPlaneFactor(const Eigen::Vector3d& point_lidar, double alpha, const Plane& plane,
                     const SE3& T_body_lidar);
  bool Evaluate(double const* const* parameters, double* residuals, double** jacobians) const override;
  // Jacobians 1 x 6 in the tangents [dt; dtheta] (the formulas above).
  bool EvaluateTangent(double const* const* parameters, double* residuals,
                       double** tangent_jacobians) const override;

 private:
  const Eigen::Vector3d point_body_;  // p_B = T_body_lidar p_L
  const double alpha_;
  const Eigen::Vector3d normal_;       // n
  const Eigen::Vector3d plane_point_;  // q
  const double sqrt_information_;      // 1 / sigma
};

class PointToPlaneFactorSinglePose : public ceres::SizedCostFunction<1, 7>, public TangentJacobianCost {
 public:
  // point_body: the point in the body frame at the pose's time.
  PointToPlaneFactorSinglePose(const Eigen::Vector3d& point_body, const Plane& plane);
  bool Evaluate(double const* const* parameters, double* residuals, double** jacobians) const override;
  bool EvaluateTangent(double const* const* parameters, double* residuals,
                       double** tangent_jacobians) const override;

 private:
  const Eigen::Vector3d point_body_;
  const Eigen::Vector3d normal_;
  const Eigen::Vector3d plane_point_;
  const double sqrt_information_;
};

// Blocks: pose_b, pose_e, t_BL (3).
class PointToPlaneLeverFactor : public ceres::SizedCostFunction<1, 7, 7, 3>, public TangentJacobianCost {
 public:
  // As PointToPlaneFactor, with the extrinsic's rotation R_body_lidar held.
  PointToPlaneLeverFactor(const Eigen::Vector3d& point_lidar, double alpha, const Plane& plane,
                          const Eigen::Matrix3d& R_body_lidar);
  bool Evaluate(double const* const* parameters, double* residuals, double** jacobians) const override;
  bool EvaluateTangent(double const* const* parameters, double* residuals,
                       double** tangent_jacobians) const override;

 private:
  const Eigen::Vector3d point_rotated_;  // R_BL p_L
  const double alpha_;
  const Eigen::Vector3d normal_;
  const Eigen::Vector3d plane_point_;
  const double sqrt_information_;
};

// Blocks: pose, t_BL (3); the point at the pose's time, in the LiDAR frame.
class PointToPlaneLeverFactorSinglePose : public ceres::SizedCostFunction<1, 7, 3>,
                                          public TangentJacobianCost {
 public:
  PointToPlaneLeverFactorSinglePose(const Eigen::Vector3d& point_lidar, const Plane& plane,
                                    const Eigen::Matrix3d& R_body_lidar);
  bool Evaluate(double const* const* parameters, double* residuals, double** jacobians) const override;
  bool EvaluateTangent(double const* const* parameters, double* residuals,
                       double** tangent_jacobians) const override;

 private:
  const Eigen::Vector3d point_rotated_;  // R_BL p_L
  const Eigen::Vector3d normal_;
  const Eigen::Vector3d plane_point_;
  const double sqrt_information_;
};

}  // namespace uf::estimator
