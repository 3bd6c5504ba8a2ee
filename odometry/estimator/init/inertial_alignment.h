// Inertial initialization of LIO (docs/METHOD.md "Observability-aware initialization": bootstrap modes S and
// M; the paper's full mode selection is not implemented yet and would plug in here).
//
// Both modes take the first window of the estimator, solved as LiDAR-only odometry in an arbitrary world
// frame "lo" (the first IMU pose), and return what LIO needs to start: the rotation into a gravity-aligned
// world (z up), the velocity of every node in it, and the IMU biases.
//
// S, static: the IMU rests (checked: spread of gyro and accelerometer over the interval, and the LiDAR poses
//   do not move). Gravity direction from the mean specific force, b_g = mean angular rate, b_a = 0 (not
//   separable from a tilt while static), v = 0.
// M, LiDAR-aided (moving start; VINS-Mono's visual-inertial alignment with the metric LiDAR poses): with the
//   preintegration between nodes k and k+1 (interval T_k) and the LO poses (R_k, p_k) of the IMU:
//   1. gyro bias: R_k^T R_k+1 = dR_k Exp(dR/dbg b_g) to first order, so stacking
//        dR/dbg_k b_g = Log(dR_k^T R_k^T R_k+1)
//      over k gives b_g by least squares; the preintegrations are re-integrated at b_g.
//   2. velocities and gravity (b_a = 0), linear in x = [v_0 .. v_n, g] (world "lo"):
//        p_k+1 - p_k - v_k T_k - g T_k^2 / 2 = R_k dp_k,    v_k+1 - v_k - g T_k = R_k dv_k
//   3. consistency: |g| must be within max_gravity_error of the configured gravity, else the window is not
//      admitted (not enough excitation or a bad LO solution; the caller retries with a later window);
//   4. g is rescaled to the configured norm and the velocities solved again with g fixed.
// The gravity-aligned world is the "lo" world rotated by the smallest rotation taking g to (0, 0, -|g|).
#pragma once

#include <span>
#include <string>
#include <vector>

#include "odometry/estimator/config/inertial_init_config.h"
#include "odometry/estimator/preintegration/imu_buffer.h"
#include "odometry/estimator/preintegration/imu_preintegration.h"
#include "odometry/types/measurements.h"
#include "odometry/types/se3.h"
#include "odometry/types/status.h"

namespace uf::estimator {

struct InertialAlignment {
  std::string mode;                         // "static" or "lidar-aided"
  SO3 R_gravity_lo;                         // world "lo" -> gravity-aligned world
  std::vector<Eigen::Vector3d> velocities;  // per node, gravity-aligned world, m/s
  Eigen::Vector3d accel_bias = Eigen::Vector3d::Zero();
  Eigen::Vector3d gyro_bias = Eigen::Vector3d::Zero();
  double gravity_estimate = 0;  // |g| before rescaling (M), or the mean specific force (S), m/s^2
};

// S. `samples` cover the window; `poses` are the LO poses of the IMU (T_lo_imu) of its nodes. Fails (with the
// reason) when the IMU or the poses show motion, or there are fewer than 10 samples.
Expected<InertialAlignment> StaticAlignment(std::span<const ImuSample> samples, std::span<const SE3> poses,
                                            const InertialInitConfig& config, double gravity);

// M. poses[k] = T_lo_imu of node k (n + 1 >= 3 nodes), preintegrations[k] between nodes k and k + 1 (any
// linearization bias; they are re-integrated). Fails when the system is singular or |g| is inconsistent.
Expected<InertialAlignment> LidarAidedAlignment(std::span<const SE3> poses,
                                                std::vector<ImuPreintegration> preintegrations,
                                                const InertialInitConfig& config);

// S, else M, over the nodes at `stamps` with the poses T_lo_imu from another sensor (LiDAR odometry, wheel
// dead reckoning) and the IMU samples of `imu` (preintegrated between the nodes for M). Fails with the
// reasons of both (the caller retries with a later window).
Expected<InertialAlignment> AlignStaticOrMoving(const ImuBuffer& imu, std::span<const Stamp> stamps,
                                                std::span<const SE3> poses, const InertialInitConfig& config,
                                                double gravity);

}  // namespace uf::estimator
