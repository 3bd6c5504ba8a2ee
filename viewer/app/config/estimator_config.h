// The `lo:` and `lio:` sections of a configuration file (LiDAR odometry, and what LiDAR-inertial odometry
// adds), mapped onto estimator::LidarOdometryConfig. Their keys, defaults and units are in docs/CONFIG.md;
// the file is read by LoadConfigFile (config_file.h).
//
// T_body_lidar is not read: the body is the LiDAR in LO and the IMU in LIO, with T_imu_lidar from the
// dataset. use_imu comes from --mode.
#pragma once

#include <string>

#include "odometry/estimator/config/lidar_odometry_config.h"

namespace uf::app {

// "lo:\n  input_voxel_m: 1\n..." with every key, and the lio: section when use_imu or use_wheel (its
// wheel: keys).
std::string EmitLidarOdometryConfig(const estimator::LidarOdometryConfig& config);

}  // namespace uf::app
