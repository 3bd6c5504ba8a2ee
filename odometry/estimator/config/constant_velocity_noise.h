// Noise densities of the constant-velocity motion prior of LiDAR-only odometry (constant_velocity_factor.h).
#pragma once

namespace uf::estimator {

struct ConstantVelocityNoise {
  // Loose defaults. When they were chosen the KITTI scans were taken as motion-compensated (no point times),
  // and a tight prior (2 m/s^2/sqrt(Hz)) gave metres of ATE on the KITTI 00 keyframes, 20 gave 0.17 m. With
  // point times from azimuth (today) 2 and 5 give 0.141 and 0.140 m there against 0.146 m; they stay loose
  // because tighter priors let hand-held keyframes slide (simulated wild at 2 Hz, LO, 10 seeds: worst
  // 4.7 m at 2 and 1.1 m at 5 against 0.34 m; docs/METHOD.md "Registration, acceptance and recovery").
  double acc_density = 20.0;         // m/s^2/sqrt(Hz): white-noise linear acceleration
  double angular_acc_density = 5.0;  // rad/s^2/sqrt(Hz): white-noise angular acceleration
  // m/s^2/sqrt(Hz): the sweep-velocity prior on scans kept apart (factors/sweep_velocity_factor.h); 0: off.
  // A walker's: simulated hand-held motion changes its world-frame velocity by 0.2 m/s per axis (median)
  // between a 2 Hz scan interval and the next sweep, 0.7 s apart (0.2 / sqrt(0.7)); a car turning at 2-3
  // m/s^2 calls for about 1 (docs/METHOD.md "Sweep-velocity prior").
  double sweep_acc_density = 0.25;
};

}  // namespace uf::estimator
