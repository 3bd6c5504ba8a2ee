#include "odometry/io/dataset_sensors.h"

namespace uf {

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
