// The wheel odometry factor between window nodes i and j (paper: "wheel preintegration: relative planar
// motion with T_IO, scale s and time offset; only the observable planar subspace is constrained";
// docs/METHOD.md "Wheel factor"): a preintegrated wheel motion (wheel_preintegration.h) against the blocks
// x = {pose_i[7], pose_j[7], scale[1]} (pose layout in state/nav_state.h: T_world_imu).
//
// With T_imu_wheel = (R_c, t_c) constant (from the calibration), the wheel frame's pose is
// T_world_wheel = T_world_imu T_imu_wheel: R_a = R_i R_c, p_a = p_i + R_i t_c at i, likewise R_b, p_b at j.
//   r_p = R_a^T (p_b - p_a) - s dp = R_c^T (R_i^T (p_j + R_j t_c - p_i) - t_c) - s dp   (wheel frame at i)
//   r_R = Log(dR^T R_a^T R_b) = Log(E),   E = dR^T R_c^T R_i^T R_j R_c
//   r   = U [r_p; r_R],   U upper triangular with U^T U = covariance^-1 (the preintegration's, at s = 1)
// The covariance carries the soft non-holonomic densities on the lateral and vertical velocity and the
// roll and pitch rates, so U constrains the forward distance and the yaw firmly and the other four
// directions loosely (rotated along the path as the vehicle turns).
//
// Jacobians of [r_p; r_R] in the pose tangents [dt; dtheta] (t <- t + dt, R <- R Exp(dtheta)), with
// Jr^-1 = RightJacobianInverseSO3(r_R) and u = R_i^T (p_j + R_j t_c - p_i):
//   dr_p/dt_i     = -R_c^T R_i^T              dr_p/dt_j     = R_c^T R_i^T
//   dr_p/dtheta_i = R_c^T [u]x                dr_p/dtheta_j = -R_c^T R_i^T R_j [t_c]x
//   dr_R/dtheta_i = -Jr^-1 R_c^T R_j^T R_i    dr_R/dtheta_j = Jr^-1 R_c^T
//   dr_R/dt_{i,j} = 0,   dr_p/ds = -dp,   dr_R/ds = 0
// (from R_i^T -> Exp(-d) R_i^T: d(R_i^T w) = [R_i^T w]x d; R_j t_c -> R_j t_c - R_j [t_c]x d; and
// E -> E Exp(R_c^T d) for R_j, E -> E Exp(-R_c^T R_j^T R_i d) for R_i). EvaluateTangent gives them times U;
// Evaluate lifts the pose columns to the 7-wide blocks with TangentToAmbientJacobian. The scale block is
// Euclidean (one column). With estimate_scale false the caller holds the scale block constant at 1.
//
// WheelScalePriorFactor: r = (s - prior) / sigma on the scale block, dr/ds = 1 / sigma.
//
// No robust loss inside.
#pragma once

#include <ceres/sized_cost_function.h>

#include <Eigen/Core>

#include "odometry/estimator/factors/tangent_jacobian.h"
#include "odometry/estimator/preintegration/wheel_preintegration.h"
#include "odometry/types/se3.h"

namespace uf::estimator {

class WheelFactor : public ceres::SizedCostFunction<6, 7, 7, 1>, public TangentJacobianCost {
 public:
  // Jacobians of the unweighted residual [r_p; r_R] in the tangents (pose: [dt; dtheta], scale: itself).
  struct TangentJacobians {
    Eigen::Matrix<double, 6, 6> pose_i, pose_j;
    Eigen::Matrix<double, 6, 1> scale;
  };

  // Asserts that the preintegration covers a positive interval and T_imu_wheel is finite.
  WheelFactor(WheelPreintegration preintegration, const SE3& T_imu_wheel);

  bool Evaluate(double const* const* parameters, double* residuals, double** jacobians) const override;
  // Weighted residual and its Jacobians 6 x 6 (poses) and 6 x 1 (scale) in the tangents, row-major.
  bool EvaluateTangent(double const* const* parameters, double* residuals,
                       double** tangent_jacobians) const override;

  // The unweighted residual [r_p; r_R] at the blocks, and its tangent Jacobians when jacobians is not null.
  Vector6d Residual(const double* pose_i, const double* pose_j, double scale,
                    TangentJacobians* jacobians = nullptr) const;

  const WheelPreintegration& preintegration() const { return preintegration_; }
  const SE3& T_imu_wheel() const { return T_imu_wheel_; }
  // Upper triangular U with U^T U = covariance^-1.
  const Matrix6d& sqrt_information() const { return sqrt_information_; }

 private:
  WheelPreintegration preintegration_;
  SE3 T_imu_wheel_;
  Matrix6d sqrt_information_;
};

// The scale block's prior (WheelFactorConfig::scale_prior_sigma): keeps s near prior where the motion
// leaves it unobserved.
class WheelScalePriorFactor : public ceres::SizedCostFunction<1, 1> {
 public:
  // sigma finite and > 0 (asserted).
  explicit WheelScalePriorFactor(double sigma, double prior = 1.0);
  bool Evaluate(double const* const* parameters, double* residuals, double** jacobians) const override;

 private:
  double prior_, inverse_sigma_;
};

}  // namespace uf::estimator
