// Mode M of the LIO initialization (docs/METHOD.md "Observability-aware initialization"; paper Sec. III-C):
// the LiDAR-odometry-aided short-window MAP estimate of gravity, velocities and accelerometer bias, with the
// LO poses as geometric priors.
//
// Input: the LO poses (R_k, p_k) = T_lo_imu of nodes k = 0..n in an arbitrary world "lo", and the IMU
// preintegration (dR_k, dv_k, dp_k over T_k) between nodes k and k + 1.
// 1. Gyro bias from the LO rotations (GyroBiasFromRotations, inertial_alignment.h); the preintegrations are
//    re-integrated at (0, b_g).
// 2. A linear-Gaussian MAP over x = [p_0 .. p_n, v_0 .. v_n, g, b_a] (world "lo"):
//      LO position      p_k = p_k^LO                                         sigma: lidar_position_sigma_m
//      IMU, per k       v_k+1 - v_k - g T_k               = R_k (dv_k + dv/dba b_a)
//                       p_k+1 - p_k - v_k T_k - g T_k^2/2 = R_k (dp_k + dp/dba b_a)
//                       with the preintegration's 6x6 covariance of (dv, dp), rotated by R_k
//      bias prior       b_a = 0                                               sigma: accel_bias_sigma
//    solved by least squares on the whitened rows. |g| of this free solution is the gravity estimate that the
//    admission check compares with the configured gravity.
// 3. The same MAP with |g| fixed: g = gravity (u + B d), u = g / |g|, B an orthonormal basis of the plane
//    normal to u, d in R^2 (the tilt, rad); three Gauss-Newton steps on d, u <- normalize(u + B d).
// 4. The posterior covariance (inverse normal matrix) of that last solve gives the predicted standard
//    deviation of the gravity direction (the largest of d's two) and of the last node's velocity. The
//    direction comes from the second difference of the LO positions against the IMU, so it tightens with the
//    window's span T roughly as lidar_position_sigma_m / T^2; the accelerometer bias is told apart from a
//    tilt only by rotation, so without it the bias prior bounds the tilt at about accel_bias_sigma / gravity.
// The gravity-aligned world is "lo" rotated by the smallest rotation taking g to (0, 0, -|g|).
#pragma once

#include <span>
#include <vector>

#include "odometry/estimator/config/inertial_init_config.h"
#include "odometry/estimator/init/inertial_alignment.h"
#include "odometry/estimator/preintegration/imu_preintegration.h"
#include "odometry/types/se3.h"
#include "odometry/types/status.h"

namespace uf::estimator {

// poses[k] = T_lo_imu of node k (n + 1 >= 3 nodes), preintegrations[k] between nodes k and k + 1 (any
// linearization bias; they are re-integrated). Fails only when the system is singular; the admission
// (gravity norm, tilt sigma, consistency) is init_admission.h's. mode = "lidar-aided".
Expected<InertialAlignment> ShortWindowMapAlignment(std::span<const SE3> poses,
                                                    std::vector<ImuPreintegration> preintegrations,
                                                    const InertialInitConfig& config);

}  // namespace uf::estimator
