#include "odometry/sim/sequence/sequence_streams.h"

#include <memory>

namespace uf::sim {

std::vector<SequenceStream> SequenceStreams(const SimulationConfig& config) {
  std::vector<SequenceStream> streams;
  auto add = [&](bool enabled, SensorKind kind, const char* name, BagTopic topic, double rate_hz,
                 const SensorPlacement* placement) {
    if (!enabled) return;
    topic.kind = kind;
    const Stamp delay = placement ? FromSeconds(placement->stamp_delay_s) : 0;
    streams.push_back({kind, name, std::move(topic), rate_hz, 0.0,
                       placement ? std::optional(*placement) : std::nullopt, delay});
  };
  add(config.imu.enabled, SensorKind::kImu, "imu", {"/imu/data", "imu_link"}, config.imu.rate_hz, nullptr);
  const double keyframe_rate_hz = config.lidar.keyframe_rate_hz;
  add(config.lidar.enabled, SensorKind::kLidar, "lidar", {"/lidar/points", "lidar"},
      keyframe_rate_hz > 0.0 ? keyframe_rate_hz : config.lidar.model.rate_hz, &config.lidar.placement);
  if (config.lidar.enabled) streams.back().keyframe_rate_hz = keyframe_rate_hz;
  add(config.camera.enabled, SensorKind::kCamera, "cam0", {"/cam0/image_raw/compressed", "cam0"},
      config.camera.model.rate_hz, &config.camera.placement);
  if (config.camera.enabled) streams.back().camera = 0;
  if (config.camera.enabled && config.camera.stereo_baseline_m > 0.0) {
    const SensorPlacement right = RightCameraPlacement(config.camera);
    add(true, SensorKind::kCamera, "cam1", {"/cam1/image_raw/compressed", "cam1"},
        config.camera.model.rate_hz, &right);
    streams.back().camera = 1;
  }
  add(config.wheel.enabled, SensorKind::kWheel, "wheel", {"/wheel/odom", "base_link"},
      config.wheel.model.rate_hz, &config.wheel.placement);
  add(config.gnss.enabled, SensorKind::kGnss, "gnss", {"/gnss/fix", "gnss"}, config.gnss.model.rate_hz,
      &config.gnss.placement);
  return streams;
}

Calibration SequenceCalibration(const SimulationConfig& config, const std::vector<SequenceStream>& streams,
                                bool truth) {
  Calibration calibration;
  calibration.body_frame = "imu";
  for (const SequenceStream& stream : streams) {
    SensorCalibration sensor;
    sensor.name = stream.name;
    sensor.kind = stream.kind;
    if (stream.placement) {
      sensor.T_body_sensor = truth ? stream.placement->T_body_sensor : stream.placement->GivenExtrinsic();
      sensor.time_offset = truth ? -stream.stamp_delay : 0;
    }
    if (stream.kind == SensorKind::kCamera)
      sensor.camera_model = std::make_shared<PinholeRadtan>(CameraModelOf(config.camera.model));
    calibration.sensors.push_back(std::move(sensor));
  }
  return calibration;
}

std::vector<StreamInfo> DatasetStreams(const SimulationConfig& config,
                                       const std::vector<SequenceStream>& streams) {
  const Calibration given = SequenceCalibration(config, streams, false);
  std::vector<StreamInfo> infos;
  for (std::size_t i = 0; i < streams.size(); ++i) {
    StreamInfo info;
    info.name = streams[i].name;
    info.kind = streams[i].kind;
    info.nominal_rate_hz = streams[i].rate_hz;
    info.T_body_sensor = given.sensors[i].T_body_sensor;
    info.camera_model = given.sensors[i].camera_model;
    info.camera = streams[i].camera;
    infos.push_back(std::move(info));
  }
  return infos;
}

}  // namespace uf::sim
