// The `lo:` and `lio:` sections of a configuration file (LiDAR odometry, and what LiDAR-inertial odometry
// adds), mapped onto estimator::LidarOdometryConfig, and the text of the resolved `dataset:`, `lo:` and
// `lio:` sections that `ultrafusion run` saves as config.yaml.
// Every key is optional; unknown keys are an error naming the file, the key and its line.
//
//   lo:
//     input_voxel_m: 1.0            # scan downsampling for registration, m
//     window_size: 10               # states in the sliding window
//     max_iterations: 8             # solver iterations per scan
//     max_solver_time_s: 0.04       # solver time per scan, s
//     max_residuals_per_scan: 1500  # point-to-plane residuals per scan
//     huber_m: 0.5                  # robust loss scale, m
//     min_range_m: 1.0              # points nearer than this are dropped, m
//     max_range_m: 100.0            # points farther than this are dropped, m
//     map_insert_voxel_m: 0.5       # downsampling of the deskewed scan inserted into the map, m
//     association_rounds: 10        # at most this many solve + re-query rounds per scan
//     max_correction_m: 5.0         # a solve moving a scan farther than this from its guess diverged, m
//     max_correction_rad: 0.5       #   or rotating it more, rad
//     min_points: 50                # scans with fewer prepared points are skipped
//     max_plane_distance_m: 1.0     # correspondences farther from their plane are dropped, m
//     marginalize: true             # oldest states into a prior (false: oldest pose held fixed)
//     motion:                       # constant-velocity prior between consecutive poses
//       acc_density: 20.0           # m/s^2/sqrt(Hz)
//       angular_acc_density: 5.0    # rad/s^2/sqrt(Hz)
//     map:                          # the voxel-hash local map
//       voxel_m: 0.5
//       max_points_per_voxel: 20
//       max_range_m: 100.0
//       plane_eigen_ratio: 0.12
//       min_plane_points: 5
//       min_plane_sigma_m: 0.05
//   lio:                            # only with --mode lio (or auto with an IMU)
//     imu_max_gap_s: 0.05           # longer IMU gaps are bridged by the constant-velocity prior, s
//     imu_max_wait_s: 0.5           # a scan waits this long for the IMU to cover it, s
//     max_speed_mps: 80             # faster states are divergence (re-initialization), m/s
//     imu: {accel_noise_density, gyro_noise_density, accel_bias_random_walk, gyro_bias_random_walk,
//           gravity, max_accel_bias_change, max_gyro_bias_change}   (see imu_noise_params.h)
//     init: {window_scans: 5, static_max_gyro_std: 0.02, static_max_acc_std: 0.3,
//            static_max_motion_m: 0.05, max_gravity_error: 0.1}   (see inertial_alignment.h)
//
// T_body_lidar is not read: the body is the LiDAR in LO and the IMU in LIO, with T_imu_lidar from the
// dataset. use_imu comes from --mode.
#pragma once

#include <filesystem>
#include <string>

#include "odometry/estimator/config/lidar_odometry_config.h"
#include "viewer/app/config/dataset_config.h"

namespace uf::app {

// Reads the file's `lo:` and `lio:` sections onto the defaults and validates the result (use_imu is false
// here: the caller sets it and validates again); other sections are skipped
// (the dataset reader rejects unknown top-level keys).
Expected<estimator::LidarOdometryConfig> LoadLidarOdometryConfig(const std::filesystem::path& file);

// "lo:\n  input_voxel_m: 1\n..." with every field (and the lio: section when use_imu), readable by
// LoadLidarOdometryConfig.
std::string EmitLidarOdometryConfig(const estimator::LidarOdometryConfig& config);

// "dataset:\n  format: kitti\n..." with every field, readable by LoadDatasetConfig.
std::string EmitDatasetConfig(const DatasetConfig& config);

}  // namespace uf::app
