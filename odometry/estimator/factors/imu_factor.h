// The IMU factor between keyframes i and j of the sliding window (Forster et al., T-RO 2017, Section VI):
// a preintegrated IMU measurement (see imu_preintegration.h) against the states
// x = {pose_i[7], speed_bias_i[9], pose_j[7], speed_bias_j[9]} (layout in state/nav_state.h).
//
// With R, p the rotation and translation of T_world_imu, T the interval, g = (0, 0, -gravity) and the
// preintegration's deltas corrected to first order for the biases of state i (db = b_i - b_lin):
//   r_R  = Log(dR(bg_i)^T R_i^T R_j)
//   r_v  = R_i^T (v_j - v_i - g T) - dv(ba_i, bg_i)
//   r_p  = R_i^T (p_j - p_i - v_i T - g T^2 / 2) - dp(ba_i, bg_i)
//   r_ba = ba_j - ba_i,   r_bg = bg_j - bg_i
// The residual r = [r_R, r_v, r_p, r_ba, r_bg] (15, the preintegration's covariance order) is whitened by
// the upper Cholesky factor U of the information matrix, U^T U = covariance^-1, so |U r|^2 is the
// Mahalanobis distance.
//
// Jacobians are derived in the tangent of the pose ([dt; dtheta], R <- R Exp(dtheta)) and lifted to the
// ambient blocks with TangentToAmbientJacobian; with Jr^-1 = RightJacobianInverseSO3(r_R),
// E = dR(bg_i)^T R_i^T R_j and phi_b = dR/dbg db_g:
//   dr_R/dtheta_i = -Jr^-1 R_j^T R_i          dr_R/dtheta_j = Jr^-1
//   dr_R/dbg_i    = -Jr^-1 E^T Jr(phi_b) dR/dbg
//   dr_v/dtheta_i = [R_i^T (v_j - v_i - g T)]x,   dr_v/dv_i = -R_i^T,  dr_v/dv_j = R_i^T
//   dr_p/dtheta_i = [R_i^T (p_j - p_i - v_i T - g T^2 / 2)]x,  dr_p/dp_i = -R_i^T,  dr_p/dp_j = R_i^T,
//   dr_p/dv_i     = -R_i^T T
//   dr_v/db_i = -dv/db,   dr_p/db_i = -dp/db,   dr_b/db_i = -I,   dr_b/db_j = I.
//
// Bias far from the linearization point: when |ba_i - ba_lin| > params.max_accel_bias_change or
// |bg_i - bg_lin| > params.max_gyro_bias_change, Evaluate integrates the raw samples again at b_i (a local
// copy: Evaluate stays const and thread-safe, but costs one re-integration per call) instead of the
// first-order update. The window should call Relinearize between solves so that this stays rare. The
// weight (sqrt information) is fixed at construction or Relinearize.
#pragma once

#include <ceres/sized_cost_function.h>

#include <Eigen/Core>

#include "odometry/estimator/preintegration/imu_preintegration.h"

namespace uf::estimator {

using Vector15d = Eigen::Matrix<double, 15, 1>;

class ImuFactor : public ceres::SizedCostFunction<15, 7, 9, 7, 9> {
 public:
  // Jacobians of the unweighted residual in the tangent spaces (pose: [dt; dtheta], speed_bias: itself).
  struct TangentJacobians {
    Eigen::Matrix<double, 15, 6> pose_i, pose_j;
    Eigen::Matrix<double, 15, 9> speed_bias_i, speed_bias_j;
  };

  // Asserts that the preintegration covers a positive interval.
  explicit ImuFactor(ImuPreintegration preintegration);

  bool Evaluate(double const* const* parameters, double* residuals, double** jacobians) const override;

  // The unweighted residual r at the blocks, and its tangent Jacobians when jacobians is not null.
  Vector15d Residual(const double* pose_i, const double* speed_bias_i, const double* pose_j,
                     const double* speed_bias_j, TangentJacobians* jacobians = nullptr) const;

  // Re-integrates the stored preintegration at these biases (and recomputes the weight) when they are
  // beyond the thresholds; returns whether it did. Not to be called while a solve is running.
  bool Relinearize(const Eigen::Vector3d& accel_bias, const Eigen::Vector3d& gyro_bias);

  const ImuPreintegration& preintegration() const { return preintegration_; }
  // Upper triangular U with U^T U = covariance^-1.
  const Matrix15d& sqrt_information() const { return sqrt_information_; }

 private:
  bool NeedsRepropagation(const Eigen::Vector3d& accel_bias, const Eigen::Vector3d& gyro_bias) const;

  ImuPreintegration preintegration_;
  Matrix15d sqrt_information_;
};

}  // namespace uf::estimator
