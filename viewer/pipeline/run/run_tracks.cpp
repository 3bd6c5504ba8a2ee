#include "viewer/pipeline/run/run_tracks.h"

#include "odometry/estimator/schedule/camera_degeneracy.h"
#include "odometry/io/calibration_file.h"
#include "odometry/types/printf_text.h"
#include "viewer/pipeline/track/track_job.h"

namespace uf::pipeline {

Status WriteRunTracks(const RunPlan& plan, const OdometryStageOutput& odometry,
                      const std::filesystem::path& out, StageContext& context) {
  if (odometry.tracked_frames.empty()) return {};
  const StreamInfo& camera =
      plan.stream->description().streams[static_cast<std::size_t>(plan.sensors.camera)];
  TrackResult tracks;
  tracks.camera_stream = camera.name;
  tracks.width = camera.camera_model->width();
  tracks.height = camera.camera_model->height();
  tracks.max_features = plan.visual_config().tracker.max_features;
  tracks.frames = odometry.tracked_frames;
  for (const estimator::FrameTrackStats& stats : tracks.frames)
    tracks.degeneracy.push_back(
        estimator::ScoreCameraFrame(stats.tracked, stats.grid_occupancy, stats.epipolar_error_px));
  tracks.stereo.resize(tracks.frames.size());
  tracks.overlays = odometry.overlays;
  Expected<std::vector<std::string>> written = WriteTrackOutputs(out, tracks);
  if (!written) return written.status();
  for (const std::string& file : *written) context.AddOutput(file);
  return {};
}

Status WriteCameraCalibrationEstimate(const RunPlan& plan, const OdometryStageOutput& odometry,
                                      const std::filesystem::path& out, StageContext& context) {
  const estimator::VisualFactorConfig& visual = plan.visual_config();
  if (!plan.mode.camera || !(visual.estimate_time_offset || visual.estimate_extrinsic)) return {};
  const DatasetDescription& description = plan.stream->description();
  const StreamInfo& camera = description.streams[static_cast<std::size_t>(plan.sensors.camera)];
  const estimator::SensorFactorStats& factors = odometry.summary.sensor_factors;
  const double t_d = factors.camera_time_offset_s;
  const SE3 T_imu_camera = factors.camera_extrinsic.value_or(plan.T_imu_camera());
  Calibration calibration;
  calibration.sensors.push_back({.name = description.streams[static_cast<std::size_t>(plan.sensors.imu)].name,
                                 .kind = SensorKind::kImu,
                                 .T_body_sensor = SE3(),
                                 .time_offset = 0,
                                 .camera_model = nullptr});
  calibration.sensors.push_back(
      {.name = camera.name,
       .kind = SensorKind::kCamera,
       .T_body_sensor = T_imu_camera,
       .time_offset = plan.stream->time_offset(plan.sensors.camera) + FromSeconds(t_d),
       .camera_model = camera.camera_model});
  const std::string header =
      "Estimated by ultrafusion run (" + ModeName(plan.mode) + "), as the window ended: " +
      PrintfText(
          "the camera time offset t_d = %.4f s (camera stamp + t_d = IMU time), added to the offset "
          "the run read with",
          t_d) +
      (visual.estimate_time_offset ? "" : " (held, not estimated)") + "; T_body_sensor " +
      (factors.camera_extrinsic ? "estimated" : "the given one (not estimated)") + ".";
  if (Status s = WriteCalibrationFile(out / "calibration_estimated.yaml", calibration, header); !s.ok())
    return s;
  context.AddOutput("calibration_estimated.yaml");
  return {};
}

}  // namespace uf::pipeline
