#include "viewer/pipeline/run/run_calibration_estimate.h"

#include "odometry/io/calibration_file.h"
#include "odometry/types/printf_text.h"

namespace uf::pipeline {

Status WriteWindowCalibrationEstimate(const RunPlan& plan, const OdometryStageOutput& odometry,
                                      const std::filesystem::path& out, StageContext& context) {
  const estimator::VisualFactorConfig& visual = plan.visual_config();
  const estimator::SensorFactorStats& factors = odometry.summary.sensor_factors;
  const bool camera_estimated =
      plan.mode.camera && (visual.estimate_time_offset || visual.estimate_extrinsic);
  if (!camera_estimated && !factors.lidar_extrinsic) return {};
  const DatasetDescription& description = plan.stream->description();
  auto stream_name = [&](int index) { return description.streams[static_cast<std::size_t>(index)].name; };
  Calibration calibration;
  calibration.sensors.push_back({.name = stream_name(plan.sensors.imu),
                                 .kind = SensorKind::kImu,
                                 .T_body_sensor = SE3(),
                                 .time_offset = 0,
                                 .camera_model = nullptr});
  std::string header = "Estimated by ultrafusion run (" + ModeName(plan.mode) + "), as the window ended:";
  if (factors.lidar_extrinsic) {
    calibration.sensors.push_back({.name = stream_name(plan.sensors.lidar),
                                   .kind = SensorKind::kLidar,
                                   .T_body_sensor = *factors.lidar_extrinsic,
                                   .time_offset = plan.stream->time_offset(plan.sensors.lidar),
                                   .camera_model = nullptr});
    header +=
        " the LiDAR's T_body_sensor with its translation estimated (lio.estimate_lidar_translation), "
        "its time offset the one the run read with";
    header += camera_estimated ? ";" : ".";
  }
  if (camera_estimated) {
    const StreamInfo& camera = description.streams[static_cast<std::size_t>(plan.sensors.camera)];
    const double t_d = factors.camera_time_offset_s;
    calibration.sensors.push_back(
        {.name = camera.name,
         .kind = SensorKind::kCamera,
         .T_body_sensor = factors.camera_extrinsic.value_or(plan.T_imu_camera()),
         .time_offset = plan.stream->time_offset(plan.sensors.camera) + FromSeconds(t_d),
         .camera_model = camera.camera_model});
    header += PrintfText(
                  " the camera time offset t_d = %.4f s (camera stamp + t_d = IMU time), added to the offset "
                  "the run read with",
                  t_d) +
              (visual.estimate_time_offset ? "" : " (held, not estimated)") +
              (factors.camera_time_offset_estimates > 0
                   ? PrintfText(" (the median of the window's %.0f estimates over the run, weighted by their "
                                "features' image motion)",
                                factors.camera_time_offset_estimates)
                   : "") +
              "; its T_body_sensor " +
              (factors.camera_extrinsic ? "estimated" : "the given one (not estimated)") + ".";
  }
  if (Status s = WriteCalibrationFile(out / "calibration_estimated.yaml", calibration, header); !s.ok())
    return s;
  context.AddOutput("calibration_estimated.yaml");
  return {};
}

}  // namespace uf::pipeline
