#include "odometry/io/dataset_sensors.h"

#include <cmath>
#include <numbers>

namespace uf {
namespace {

// Whether the camera at T_imu_right makes a stereo rig with the one at T_imu_left (see the header).
bool StereoPartner(const SE3& T_imu_left, const SE3& T_imu_right) {
  const SE3 T_left_right = T_imu_left.inverse() * T_imu_right;
  const double baseline = T_left_right.translation().norm();
  const double axis_cos = T_left_right.so3().matrix()(2, 2);  // z_left . z_right
  return baseline > 1e-3 && baseline <= kMaxStereoBaselineM &&
         axis_cos >= std::cos(kMaxStereoAxisAngleDeg * std::numbers::pi / 180);
}

}  // namespace

DatasetSensors FindSensors(const DatasetDescription& description) {
  DatasetSensors sensors;
  for (std::size_t s = 0; s < description.streams.size(); ++s) {
    const SensorKind kind = description.streams[s].kind;
    if (kind == SensorKind::kLidar && sensors.lidar < 0) sensors.lidar = static_cast<int>(s);
    if (kind == SensorKind::kImu && sensors.imu < 0) sensors.imu = static_cast<int>(s);
    if (kind == SensorKind::kWheel && sensors.wheel < 0) sensors.wheel = static_cast<int>(s);
    if (kind == SensorKind::kGnss && sensors.gnss < 0) sensors.gnss = static_cast<int>(s);
    if (kind == SensorKind::kCamera && sensors.camera < 0 && description.streams[s].camera_model)
      sensors.camera = static_cast<int>(s);
  }
  if (sensors.lidar >= 0) sensors.T_imu_lidar = ImuFromSensor(description, sensors.lidar);
  if (sensors.wheel >= 0) sensors.T_imu_wheel = ImuFromSensor(description, sensors.wheel);
  if (sensors.gnss >= 0) sensors.T_imu_gnss = ImuFromSensor(description, sensors.gnss);
  if (sensors.camera >= 0) sensors.T_imu_camera = ImuFromSensor(description, sensors.camera);
  for (std::size_t s = static_cast<std::size_t>(sensors.camera) + 1;
       sensors.T_imu_camera && s < description.streams.size(); ++s) {
    if (description.streams[s].kind != SensorKind::kCamera || !description.streams[s].camera_model) continue;
    const std::optional<SE3> T_imu_right = ImuFromSensor(description, static_cast<int>(s));
    if (!T_imu_right || !StereoPartner(*sensors.T_imu_camera, *T_imu_right)) continue;
    sensors.camera_right = static_cast<int>(s);
    sensors.T_imu_camera_right = T_imu_right;
    break;
  }
  return sensors;
}

std::optional<SE3> ImuFromSensor(const DatasetDescription& description, int stream) {
  const StreamInfo& sensor = description.streams.at(static_cast<std::size_t>(stream));
  if (!sensor.T_body_sensor) return std::nullopt;
  SE3 T_body_imu;  // identity: the body is the IMU unless the IMU stream says otherwise
  for (const StreamInfo& stream : description.streams) {
    if (stream.kind == SensorKind::kImu && stream.T_body_sensor) {
      T_body_imu = *stream.T_body_sensor;
      break;
    }
  }
  // p_imu = T_body_imu^-1 * p_body = T_body_imu^-1 * T_body_sensor * p_sensor
  return T_body_imu.inverse() * *sensor.T_body_sensor;
}

}  // namespace uf
