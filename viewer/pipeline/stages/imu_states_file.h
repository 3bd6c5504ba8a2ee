// The inertial states of a run that estimated them (LIO, WIO and the modes built on them): imu_states.csv,
// one row per keyframe with the body's velocity and speed and the IMU's accelerometer and gyroscope biases,
// and plots/imu_accel_bias.png and plots/imu_gyro_bias.png (each bias's x, y, z over time). The biases are
// in the IMU frame; the velocity is in the estimator's world frame (gravity-aligned, the first pose's
// position and yaw; not ENU even when the trajectory is written in ENU). With the LiDAR extrinsic's
// translation estimated (lio.estimate_lidar_translation) the rows also carry it, and
// plots/lidar_translation.png shows it.
#pragma once

#include <Eigen/Core>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "odometry/types/stamp.h"
#include "odometry/types/status.h"

namespace uf::pipeline {

struct ImuStateRow {
  Stamp stamp = 0;
  Eigen::Vector3d velocity = Eigen::Vector3d::Zero();    // body, world frame, m/s
  Eigen::Vector3d accel_bias = Eigen::Vector3d::Zero();  // imu frame, m/s^2
  Eigen::Vector3d gyro_bias = Eigen::Vector3d::Zero();   // imu frame, rad/s
  std::optional<Eigen::Vector3d> lidar_translation;      // T_body_lidar's, m, where estimated
};

// What WriteImuStateFiles wrote, relative to its folder: every file, and the two plots (all empty for no
// rows).
struct ImuStateFiles {
  std::vector<std::string> files;
  std::string accel_bias_plot, gyro_bias_plot;
  std::string lidar_translation_plot;  // empty where no row has the translation
};

// Writes folder/imu_states.csv and the two plots (folder/plots must exist). Nothing is written for no rows.
// Errors: a file that cannot be written or a non-finite state (nothing half written is left behind).
Expected<ImuStateFiles> WriteImuStateFiles(const std::filesystem::path& folder,
                                           const std::vector<ImuStateRow>& rows);

}  // namespace uf::pipeline
