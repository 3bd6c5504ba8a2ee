// The `lo:` section of a configuration file (LiDAR odometry), mapped onto estimator::LidarOdometryConfig,
// and the text of the resolved `dataset:` and `lo:` sections that `ultrafusion run` saves as config.yaml.
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
//     map_insert_voxel_m: 0.25      # downsampling of the deskewed scan inserted into the map, m
//     association_rounds: 2         # solve, re-query planes, solve again
//     max_correction_m: 5.0         # a solve moving a scan farther than this from its guess diverged, m
//     max_correction_rad: 0.5       #   or rotating it more, rad
//     min_points: 50                # scans with fewer prepared points are skipped
//     motion:                       # constant-velocity prior between consecutive poses
//       acc_density: 2.0            # m/s^2/sqrt(Hz)
//       angular_acc_density: 0.5    # rad/s^2/sqrt(Hz)
//     map:                          # the voxel-hash local map
//       voxel_m: 0.5
//       max_points_per_voxel: 20
//       max_range_m: 100.0
//       plane_eigen_ratio: 0.12
//       min_plane_points: 5
//       min_plane_sigma_m: 0.05
//
// T_body_lidar is not read: in LO mode the body is the LiDAR (identity).
#pragma once

#include <filesystem>
#include <string>

#include "odometry/estimator/lidar_odometry/lidar_odometry.h"
#include "viewer/app/dataset_config.h"

namespace uf::app {

// Reads the file's `lo:` section onto the defaults and validates the result; other sections are skipped
// (the dataset reader rejects unknown top-level keys).
Expected<estimator::LidarOdometryConfig> LoadLidarOdometryConfig(const std::filesystem::path& file);

// "lo:\n  input_voxel_m: 1\n..." with every field, readable by LoadLidarOdometryConfig.
std::string EmitLidarOdometryConfig(const estimator::LidarOdometryConfig& config);

// "dataset:\n  format: kitti\n..." with every field, readable by LoadDatasetConfig.
std::string EmitDatasetConfig(const DatasetConfig& config);

}  // namespace uf::app
