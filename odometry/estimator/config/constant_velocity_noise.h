// Noise densities of the constant-velocity motion prior of LiDAR-only odometry (constant_velocity_factor.h).
#pragma once

namespace uf::estimator {

struct ConstantVelocityNoise {
  // Loose defaults: KITTI scans come already motion-compensated, so their data want (almost) no motion
  // within a sweep while the vehicle moves ~10 m/s between sweeps; a tight prior (2 m/s^2/sqrt(Hz))
  // fights that and gave metres of ATE on the KITTI 00 keyframes, 20 gives 0.17 m.
  double acc_density = 20.0;         // m/s^2/sqrt(Hz): white-noise linear acceleration
  double angular_acc_density = 5.0;  // rad/s^2/sqrt(Hz): white-noise angular acceleration
};

}  // namespace uf::estimator
