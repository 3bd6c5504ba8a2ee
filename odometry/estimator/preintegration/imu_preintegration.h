// IMU preintegration between two keyframes i and j (Forster, Carlone, Dellaert, Scaramuzza, "On-Manifold
// Preintegration for Real-Time Visual-Inertial Odometry", T-RO 2017), discretised with the midpoint rule on
// the bias-corrected measurements.
//
// With measurements (acc, gyro) at both ends of each step [t_k, t_k+1], dt = t_k+1 - t_k, biases b_a, b_g:
//   w      = (gyro_k + gyro_k+1) / 2 - b_g
//   dR_k+1 = dR_k Exp(w dt)
//   a      = (dR_k (acc_k - b_a) + dR_k+1 (acc_k+1 - b_a)) / 2
//   dv_k+1 = dv_k + a dt,   dp_k+1 = dp_k + dv_k dt + a dt^2 / 2
// starting from dR = I, dv = dp = 0. The deltas relate the keyframe states (world z up, g = (0, 0,
// -gravity)):
//   R_j = R_i dR,   v_j = v_i + g T + R_i dv,   p_j = p_i + v_i T + g T^2 / 2 + R_i dp   (T = sum of dt).
//
// Error state e = [dtheta, dv, dp, dba, dbg] (15), with the rotation error on the right: dR_true = dR
// Exp(dtheta). Each step propagates e_k+1 = F e_k + G n, where n = [n_g, n_a, n_ba, n_bg] holds the gyro and
// accelerometer white noise (variance density^2 / dt) and the bias random-walk increments (variance rw^2 dt);
// F is the exact derivative of the step above, so
//   covariance  P_k+1 = F P_k F^T + G Q G^T   (P_0 = 0; includes the bias random walk over the interval)
//   bias Jacobian  J_k+1 = top 9 rows of F [J_k; I]   (J_0 = 0; J = d[dtheta, dv, dp]/d[b_a, b_g], 9x6).
// Sign convention of the covariance: it is the covariance of the IMU factor's residual at the true states,
// [Log(dR^T dR_true), dv_true - dv, dp_true - dp, b_j - b_i] (the bias drifting up makes the measured deltas
// too large, so the delta and bias-change blocks correlate negatively in this convention).
// Clipped readings (params.gyro_range, accel_range): an axis reading at the sensor's full scale says only
// that the true value lies beyond it, by an unknown amount. The step takes that amount as zero-mean noise of
// standard deviation kClippedExcess * range on the axis, for each end sample clipped there (the midpoint
// halves it, as it does the reading): q_axis += (kClippedExcess range (c_k + c_k+1) / 2)^2, c = 1 when
// clipped. F carries it into dv and dp, so the factor loosens where the IMU saw less than happened
// (docs/METHOD.md "Factor-wise reliability scheduling", IMU score).
// Forster's first-order update for biases b = b_lin + db (db = [db_a; db_g]):
//   dR(b) = dR Exp(dR/dbg db_g),   dv(b) = dv + dv/dba db_a + dv/dbg db_g,   dp(b) likewise.
#pragma once

#include <Eigen/Core>
#include <vector>

#include "odometry/estimator/config/imu_noise_params.h"
#include "odometry/estimator/state/nav_state.h"
#include "odometry/types/measurements.h"
#include "odometry/types/so3.h"
#include "odometry/types/stamp.h"
#include "odometry/types/status.h"

namespace uf::estimator {

using Matrix15d = Eigen::Matrix<double, 15, 15>;

// A clipped reading's unknown excess beyond the full scale, as a share of the full scale (one standard
// deviation): a rate or force up to twice the range is within one sigma.
constexpr double kClippedExcess = 1.0;

// Block offsets of the error state, the covariance and the IMU factor's residual.
constexpr int kImuRotation = 0, kImuVelocity = 3, kImuPosition = 6, kImuAccelBias = 9, kImuGyroBias = 12;

class ImuPreintegration {
 public:
  // Empty (dR = I, T = 0) with the linearization biases (imu frame); asserts that params validate.
  ImuPreintegration(const Eigen::Vector3d& accel_bias, const Eigen::Vector3d& gyro_bias,
                    const ImuNoiseParams& params);

  // Adds the step [begin.stamp, end.stamp] (midpoint rule) and keeps both samples for Repropagate. Fails,
  // leaving this unchanged, when end.stamp <= begin.stamp or a sample is not finite.
  Status Integrate(const ImuSample& begin, const ImuSample& end);

  // Integrates the samples (sorted by stamp) over [t_i, t_j], with boundary samples interpolated linearly
  // between their neighbours. Fails when t_j <= t_i, the samples do not cover [t_i, t_j], or a step fails.
  static Expected<ImuPreintegration> Between(const std::vector<ImuSample>& samples, Stamp t_i, Stamp t_j,
                                             const Eigen::Vector3d& accel_bias,
                                             const Eigen::Vector3d& gyro_bias, const ImuNoiseParams& params);

  // Integrates every kept step again with new linearization biases (resets deltas, Jacobians, covariance).
  void Repropagate(const Eigen::Vector3d& accel_bias, const Eigen::Vector3d& gyro_bias);

  // The deltas at the linearization biases.
  const SO3& delta_R() const { return delta_R_; }
  const Eigen::Vector3d& delta_v() const { return delta_v_; }
  const Eigen::Vector3d& delta_p() const { return delta_p_; }
  Stamp sum_dt() const { return sum_dt_; }  // ns
  double sum_dt_seconds() const { return ToSeconds(sum_dt_); }
  const Eigen::Vector3d& accel_bias() const { return accel_bias_; }  // the linearization point
  const Eigen::Vector3d& gyro_bias() const { return gyro_bias_; }
  const ImuNoiseParams& params() const { return params_; }
  // g in the world: (0, 0, -gravity) unless set (a world tilted from gravity, window_extrinsic.cpp).
  const Eigen::Vector3d& gravity_world() const { return gravity_world_; }
  void SetGravityWorld(const Eigen::Vector3d& g) { gravity_world_ = g; }
  int num_steps() const { return static_cast<int>(steps_.size()); }
  // Steps with an end sample clipped on some axis (header; 0 when no range is set).
  int clipped_steps() const { return clipped_steps_; }

  // Bias Jacobians: d[dtheta, dv, dp]/d[b_a, b_g] (9x6, rows and columns in the error-state order) and
  // its 3x3 blocks (dR/dba is zero).
  const Eigen::Matrix<double, 9, 6>& bias_jacobian() const { return bias_jacobian_; }
  Eigen::Matrix3d dR_dbg() const { return bias_jacobian_.block<3, 3>(kImuRotation, 3); }
  Eigen::Matrix3d dv_dba() const { return bias_jacobian_.block<3, 3>(kImuVelocity, 0); }
  Eigen::Matrix3d dv_dbg() const { return bias_jacobian_.block<3, 3>(kImuVelocity, 3); }
  Eigen::Matrix3d dp_dba() const { return bias_jacobian_.block<3, 3>(kImuPosition, 0); }
  Eigen::Matrix3d dp_dbg() const { return bias_jacobian_.block<3, 3>(kImuPosition, 3); }
  // Covariance (15x15, order [dtheta, dv, dp, dba, dbg], sign convention above).
  const Matrix15d& covariance() const { return covariance_; }

  // First-order corrected deltas for biases (accel_bias, gyro_bias) (Forster eq. 44).
  SO3 CorrectedDeltaR(const Eigen::Vector3d& gyro_bias) const;
  Eigen::Vector3d CorrectedDeltaV(const Eigen::Vector3d& accel_bias, const Eigen::Vector3d& gyro_bias) const;
  Eigen::Vector3d CorrectedDeltaP(const Eigen::Vector3d& accel_bias, const Eigen::Vector3d& gyro_bias) const;

  // The state at t_i + T from the state at t_i and the corrected deltas for its biases (biases carried over).
  NavState Predict(const NavState& state_i) const;

 private:
  struct Step {
    ImuSample begin, end;
  };
  void Propagate(const Step& step);

  ImuNoiseParams params_;
  Eigen::Vector3d gravity_world_;
  Eigen::Vector3d accel_bias_, gyro_bias_;
  std::vector<Step> steps_;
  Stamp sum_dt_ = 0;
  int clipped_steps_ = 0;
  SO3 delta_R_;
  Eigen::Vector3d delta_v_ = Eigen::Vector3d::Zero();
  Eigen::Vector3d delta_p_ = Eigen::Vector3d::Zero();
  Eigen::Matrix<double, 9, 6> bias_jacobian_ = Eigen::Matrix<double, 9, 6>::Zero();
  Matrix15d covariance_ = Matrix15d::Zero();
};

}  // namespace uf::estimator
