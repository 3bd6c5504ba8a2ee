// Visual reprojection factor with inverse depth (paper Sec. III-B; docs/METHOD.md "Visual reprojection
// factor"; the formulation of VINS-Mono's ProjectionTdFactor). A feature first observed in keyframe i (its
// anchor) at undistorted normalized coordinates u_i, seen again in keyframe j at u_j; its depth in the anchor
// camera is 1 / lambda.
//
// Blocks: pose_i, pose_j = T_world_imu of the two keyframes (nav_state.h layout), T_imu_cam (7, pose layout:
// the camera extrinsic, on PoseManifold), lambda (1, inverse depth, 1/m), t_d (1, camera time offset, s:
// camera stamp + t_d = IMU time).
//
// Time offset. A keyframe's node sits at its camera stamp plus the offset t_d0 the node was made with. With
// the feature's image velocity v (normalized units per second, from the front end), its position at the
// node's time for the offset t_d is, to first order,
//   u'(t_d) = u - (t_d - t_d0) v                                          (u_i', u_j' alike, v = (v_x, v_y,
//   0))
// Then
//   P_ci = u_i' / lambda                              (u_i' homogeneous: (x, y, 1))
//   P_bi = R_bc P_ci + t_bc,   P_w = R_i P_bi + t_i,   P_bj = R_j^T (P_w - t_j),   P_cj = R_bc^T (P_bj -
//   t_bc) r    = s (pi(P_cj) - u_j'(t_d)),   pi(P) = (P_x / P_z, P_y / P_z),   s = focal / sigma_px
// so that r is in units of sigma_px pixels.
// Jacobians in the tangents (poses and extrinsic: [dt; dtheta], t <- t + dt, R <- R Exp(dtheta)), with
// D = dpi/dP = [1/z, 0, -x/z^2; 0, 1/z, -y/z^2] at P_cj, R_cb = R_bc^T and A = R_cb R_j^T:
//   dr/dt_i     = s D A                            dr/dtheta_i = -s D A R_i [P_bi]x
//   dr/dt_j     = -s D A                           dr/dtheta_j = s D R_cb [P_bj]x
//   dr/dt_bc    = s D R_cb (R_j^T R_i - I)         dr/dtheta_bc = s D ([P_cj]x - A R_i R_bc [P_ci]x)
//   dr/dlambda  = -s D A R_i R_bc P_ci / lambda
//   dr/dt_d     = s (-D A R_i R_bc v_i / lambda + v_j)
// (the [P]x terms: R Exp(dtheta) P = R P - R [P]x dtheta, and (R Exp(dtheta))^T X = R^T X + [R^T X]x dtheta).
//
// Stereo: the target may be seen by the rig's second camera, at T_target_camera from the first (p_target =
// T p_camera; identity for the camera itself). Then P_t = R_tc P_cj + t_tc replaces P_cj in the residual,
// r = s (pi(P_t) - u_j'(t_d)), and every s D above becomes s D_t R_tc, with D_t = dpi/dP at P_t. The rig's
// own extrinsic is held: T_body_target = T_body_camera T_target_camera^-1 moves with the free extrinsic.
//
// No robust loss inside: the window wraps these in its loss.
#pragma once

#include <ceres/sized_cost_function.h>

#include <Eigen/Core>

#include "odometry/estimator/factors/tangent_jacobian.h"
#include "odometry/types/se3.h"

namespace uf::estimator {

// One observation of a feature: undistorted normalized coordinates and their image velocity (1/s).
struct FeatureObservation {
  Eigen::Vector2d normalized = Eigen::Vector2d::Zero();
  Eigen::Vector2d velocity = Eigen::Vector2d::Zero();
};

class ReprojectionFactor : public ceres::SizedCostFunction<2, 7, 7, 7, 1, 1>, public TangentJacobianCost {
 public:
  // sqrt_information: s = focal length / pixel sigma of the target's camera (> 0, asserted); td_i, td_j:
  // the offsets the two keyframes' nodes were made with (t_d0 above); T_target_camera: see Stereo above.
  ReprojectionFactor(const FeatureObservation& anchor, const FeatureObservation& target, double td_i,
                     double td_j, double sqrt_information, const SE3& T_target_camera = SE3());
  bool Evaluate(double const* const* parameters, double* residuals, double** jacobians) const override;
  // Jacobians 2 x 6 for poses and extrinsic, 2 x 1 for lambda and t_d, row-major.
  bool EvaluateTangent(double const* const* parameters, double* residuals,
                       double** tangent_jacobians) const override;

 private:
  const FeatureObservation anchor_, target_;
  const double td_i_, td_j_;
  const double sqrt_information_;
  const Eigen::Matrix3d R_tc_;
  const Eigen::Vector3d t_tc_;
};

}  // namespace uf::estimator
