// Which streams of a dataset a pipeline uses, and how they sit relative to each other, from the calibration
// that came with the data (StreamInfo::T_body_sensor; the body of a dataset is its IMU unless the IMU stream
// says otherwise).
#pragma once

#include <optional>

#include "odometry/io/dataset_reader.h"
#include "odometry/types/se3.h"

namespace uf {

// The first LiDAR, IMU, wheel and GNSS streams and the first camera with intrinsics (-1: none), and their
// extrinsics to the IMU (ImuFromSensor). camera_right: the first later camera with intrinsics that forms a
// stereo rig with `camera` (both with extrinsics, optical axes within kMaxStereoAxisAngleDeg, a baseline
// in (1 mm, kMaxStereoBaselineM]); -1: none.
struct DatasetSensors {
  int lidar = -1, imu = -1, wheel = -1, gnss = -1, camera = -1, camera_right = -1;
  std::optional<SE3> T_imu_lidar, T_imu_wheel, T_imu_gnss, T_imu_camera, T_imu_camera_right;
};

inline constexpr double kMaxStereoAxisAngleDeg = 30;
inline constexpr double kMaxStereoBaselineM = 2;

DatasetSensors FindSensors(const DatasetDescription& description);

// T_imu_sensor (p_imu = T_imu_sensor * p_sensor): the stream's T_body_sensor composed with the inverse of
// the first IMU stream's (identity when the IMU has none, the body then being the IMU). Empty when the
// stream carries no T_body_sensor.
std::optional<SE3> ImuFromSensor(const DatasetDescription& description, int stream);

}  // namespace uf
