// The IMU's score of the reliability scheduling over one node interval (docs/METHOD.md "Factor-wise
// reliability scheduling", IMU score; paper Sec. III-D, IMU excitation consistency), the paper's
//   D = w_e (1 - eta) + w_p min(1, chi2 / tau_imu) + w_s [clipped],
// eta = min(1, max(omega / tau_omega, a / tau_a)) the excitation (the interval's mean rotation rate and
// acceleration), chi2 the IMU factor's squared Mahalanobis residual at the window's estimate, and [clipped]
// 1 when a reading of the interval sat at the sensor's full scale (imu_preintegration.h). What acts on it is
// the preintegration's noise at the clipped steps and the wheel's scheduling, which does not score the wheel
// against a clipped interval; the score itself is written, not gated on.
#pragma once

#include "odometry/types/keyframe.h"

namespace uf::estimator {

struct ImuScoreInputs {
  double rate_rad_s = 0;         // |Log dR| / T
  double acceleration_mps2 = 0;  // |v_j - v_i| / T
  double chi2 = 0;               // |U r|^2 of the IMU factor (15 dof)
  int clipped_steps = 0;         // ImuPreintegration::clipped_steps
};

inline constexpr double kImuRateExcitation_rad_s = 0.1;  // tau_omega
inline constexpr double kImuAccelExcitation_mps2 = 0.5;  // tau_a
inline constexpr double kImuChi2Threshold = 30.58;       // tau_imu: chi2(15 dof) at 0.99
inline constexpr double kImuExcitationWeight = 0.2;      // w_e
inline constexpr double kImuResidualWeight = 0.4;        // w_p
inline constexpr double kImuClippedWeight = 0.4;         // w_s

// Non-finite inputs score their term 1.
ImuReliability ScoreImuInterval(const ImuScoreInputs& inputs);

}  // namespace uf::estimator
