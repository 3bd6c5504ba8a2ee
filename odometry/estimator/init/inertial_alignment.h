// Inertial alignments (docs/METHOD.md "Observability-aware initialization"): the static mode S, which LIO and
// WIO share, and the linear moving alignment that WIO uses with the wheel's poses. LIO chooses between S and
// its LiDAR-aided short-window MAP (short_window_map.h) with init_mode_selection.h.
//
// Both take the first window of the estimator, whose poses come from another sensor (LiDAR odometry, wheel
// dead reckoning) in an arbitrary world frame "lo" (the first IMU pose), and return what the inertial window
// needs to start: the rotation into a gravity-aligned world (z up), the velocity of every node in it, and the
// IMU biases.
//
// S, static: the IMU rests (NotStaticReason of init_mode_selection.h: the spread of gyro and accelerometer
//   over the interval, the mean specific force is gravity, the poses do not move). Gravity direction from
//   the mean specific force, b_g = mean angular rate, b_a = 0 (not separable from a tilt while static), v =
//   0.
// Moving, linear (WIO's wheel-aided mode; VINS-Mono's visual-inertial alignment with metric poses): with the
//   preintegration between nodes k and k+1 (interval T_k) and the poses (R_k, p_k) of the IMU:
//   1. gyro bias: R_k^T R_k+1 = dR_k Exp(dR/dbg b_g) to first order, so stacking
//        dR/dbg_k b_g = Log(dR_k^T R_k^T R_k+1)
//      over k gives b_g by least squares; the preintegrations are re-integrated at b_g.
//   2. velocities and gravity (b_a = 0), linear in x = [v_0 .. v_n, g] (world "lo"):
//        p_k+1 - p_k - v_k T_k - g T_k^2 / 2 = R_k dp_k,    v_k+1 - v_k - g T_k = R_k dv_k
//   3. consistency: |g| must be within max_gravity_error of the configured gravity, else the window is not
//      admitted (not enough excitation or a bad pose solution; the caller retries with a later window);
//   4. g is rescaled to the configured norm and the velocities solved again with g fixed.
// The gravity-aligned world is the "lo" world rotated by the smallest rotation taking g to (0, 0, -|g|).
#pragma once

#include <span>
#include <string>
#include <vector>

#include "odometry/estimator/config/inertial_init_config.h"
#include "odometry/estimator/init/init_mode_selection.h"
#include "odometry/estimator/preintegration/imu_buffer.h"
#include "odometry/estimator/preintegration/imu_preintegration.h"
#include "odometry/types/measurements.h"
#include "odometry/types/se3.h"
#include "odometry/types/status.h"

namespace uf::estimator {

struct InertialAlignment {
  // "static", "lidar-aided" (LiDAR or wheel poses) or "visual-inertial" (mode D; "visual-inertial (the
  // stereo rig's scale)" with a rig)
  std::string mode;
  SO3 R_gravity_lo;                         // world "lo" -> gravity-aligned world
  std::vector<Eigen::Vector3d> velocities;  // per node, gravity-aligned world, m/s
  Eigen::Vector3d accel_bias = Eigen::Vector3d::Zero();
  Eigen::Vector3d gyro_bias = Eigen::Vector3d::Zero();
  double gravity_estimate = 0;  // |g| before rescaling (M), or the mean specific force (S), m/s^2
  // The short-window MAP only: predicted standard deviations of the gravity direction (rad) and of the last
  // node's velocity (m/s, the largest axis), and the LO position noise it used (m); 0 where not computed.
  double tilt_sigma_rad = 0, velocity_sigma_mps = 0, position_sigma_m = 0;
};

// The smallest rotation taking the direction of g_lo to -z: the gravity-aligned world from world "lo".
SO3 AlignGravity(const Eigen::Vector3d& g_lo);

// Step 1 of the moving alignments: b_g by least squares from the LO rotations, for preintegrations
// (between consecutive poses) linearized at b_g = 0.
Eigen::Vector3d GyroBiasFromRotations(std::span<const SE3> poses,
                                      const std::vector<ImuPreintegration>& preintegrations);

// S, from the window's indicators (ComputeInitIndicators over its IMU samples and poses); `poses` are the LO
// (WIO: wheel) poses of the IMU (T_lo_imu) of its nodes. Fails (with the reason) when the indicators are not
// at rest by S's limits (NotStaticReason).
Expected<InertialAlignment> StaticAlignment(const InitIndicators& indicators, std::span<const SE3> poses,
                                            const InertialInitConfig& config, double gravity);

// The linear moving alignment. poses[k] = T_lo_imu of node k (n + 1 >= 3 nodes), preintegrations[k] between
// nodes k and k + 1 (any linearization bias; they are re-integrated). Fails when the system is singular or
// |g| is inconsistent.
Expected<InertialAlignment> LidarAidedAlignment(std::span<const SE3> poses,
                                                std::vector<ImuPreintegration> preintegrations,
                                                const InertialInitConfig& config);

// WIO: S, else (allow_moving) the linear moving alignment, over the nodes at `stamps` with the poses T_lo_imu
// from another sensor (LiDAR odometry, wheel dead reckoning) and the IMU samples of `imu` (preintegrated
// between the nodes for M). Fails with the reasons of both (the caller retries with a later window).
Expected<InertialAlignment> AlignStaticOrMoving(const ImuBuffer& imu, std::span<const Stamp> stamps,
                                                std::span<const SE3> poses, const InertialInitConfig& config,
                                                double gravity, bool allow_moving = true);

}  // namespace uf::estimator
