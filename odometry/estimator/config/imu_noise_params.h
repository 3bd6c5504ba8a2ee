// The IMU's noise model and gravity as the estimator uses them (preintegration covariance, IMU factor), and
// when the IMU factor re-integrates its measurements for a new bias.
//
// Densities are continuous-time, as a datasheet or Kalibr gives them. Over a step of dt seconds they become
// (Kalibr / EuRoC convention, the same as the simulator's ImuNoise):
//   white noise on one sample:    variance sigma^2 / dt        (sigma in unit/sqrt(Hz))
//   bias random walk over dt:     variance sigma_b^2 * dt      (sigma_b in unit/s/sqrt(Hz))
#pragma once

#include "odometry/types/status.h"

namespace uf::estimator {

struct ImuNoiseParams {
  double accel_noise_density = 2.0e-3;       // m/s^2/sqrt(Hz)
  double gyro_noise_density = 1.6968e-4;     // rad/s/sqrt(Hz)
  double accel_bias_random_walk = 3.0e-3;    // m/s^3/sqrt(Hz)
  double gyro_bias_random_walk = 1.9393e-5;  // rad/s^2/sqrt(Hz)
  double gravity = 9.80665;                  // m/s^2; world z up: g_world = (0, 0, -gravity)

  // The preintegrated deltas are linear in the bias change db = b - b_lin (Forster's first-order update)
  // while |db_a| <= max_accel_bias_change and |db_g| <= max_gyro_bias_change (Euclidean norms). Beyond,
  // the IMU factor integrates the raw samples again at the current bias (the second-order error of the
  // update grows as |db|^2 T^2; the defaults keep it below ~1e-4 rad and ~1e-3 m over 1 s, as VINS-Mono).
  double max_accel_bias_change = 0.1;  // m/s^2
  double max_gyro_bias_change = 0.01;  // rad/s

  // The sensor's full scale per axis (its datasheet's measurement range); 0: not known, not checked. An axis
  // reading at its full scale is clipped: the true value lies somewhere beyond. The preintegration counts
  // such samples and takes the unknown rest of the reading as noise (imu_preintegration.h; docs/METHOD.md
  // "Factor-wise reliability scheduling", IMU score).
  double gyro_range = 0.0;   // rad/s
  double accel_range = 0.0;  // m/s^2
};

// Ok, or an error naming the field and its value: densities and random walks must be finite and > 0
// (a zero density makes the information matrix singular), gravity finite and >= 0, the bias thresholds
// finite and > 0, the ranges finite and >= 0.
Status ValidateImuNoiseParams(const ImuNoiseParams& params);

}  // namespace uf::estimator
