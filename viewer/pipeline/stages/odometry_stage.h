// The odometry stage of `ultrafusion run`: the estimator in its mode over the dataset's measurement stream.
// The LiDAR scans, IMU and wheel samples (and the GNSS fixes in a G mode) go to the estimator
// (run_estimator.h: the LiDAR window or the wheel-inertial one), the camera frames and the keyframes leaving
// its window go straight to the map's KeyframeMapper (a scan is never held twice), the GNSS fixes are kept
// for the georeference after the run. Writes trajectory.tum and trajectory_kitti.txt (in the run's trajectory
// frame, RunFrames::OutputTrajectory; in ENU when the estimator georeferenced the run, with
// trajectory_wgs84.csv and trajectory.geojson), timing.json and plots/timing_per_scan.png
// (timing_per_node.png in WIO): odometry_files.h.
#pragma once

#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "mapping/keyframe_mapper.h"
#include "odometry/estimator/point_times/point_time_recheck.h"
#include "odometry/io/dataset_sensors.h"
#include "odometry/io/measurement_stream.h"
#include "viewer/pipeline/calibrate/calibration_branch.h"
#include "viewer/pipeline/run/run_estimator.h"
#include "viewer/pipeline/run/run_frames.h"
#include "viewer/pipeline/run_files.h"
#include "viewer/pipeline/stage_runner.h"
#include "viewer/pipeline/stages/reliability_files.h"

namespace uf::pipeline {

struct OdometryStageInput {
  MeasurementStream* stream = nullptr;
  RunEstimator* odometry = nullptr;
  mapping::KeyframeMapper* mapper = nullptr;  // none with --no-map (and in WIO)
  DatasetSensors sensors;
  RunFrames frames;
  bool gnss_factors = false;    // the fixes go to the estimator (a G mode)
  bool camera_factors = false;  // the frames of sensors.camera go to the estimator, decoded (a V mode)
  int stereo_stream = -1;       // a stereo rig's right camera: its frames go to the estimator too (-1: none)
  int overlay_every = 0;        // V modes: an overlay of the tracks on every N-th frame (0: none)
  int min_track_length = 4;     // of the overlay's colours: the length the estimator needs
  // run --calibrate-online: the calibration branch (holds the run for the locks, re-stamps the scans, hands
  // over the locked rotation)
  CalibrationBranch* calibration = nullptr;
  // Point times that the check at the start chose: checked again when the registration degrades
  // (point_time_recheck.h); none otherwise.
  estimator::PointTimeRecheck* point_time_recheck = nullptr;
  // The total of the stream that paces the odometry (PacedStream) for the progress line; 0: unknown.
  std::int64_t paced_messages = 0;
  std::filesystem::path out;
};

// What the report says of the odometry.
struct OdometrySummary {
  std::string step = "scan";  // what the estimator steps by: "scan" (LiDAR window) or "node" (WIO)
  // LiDAR scans fed (0 in WIO), trajectory poses, scans the odometry skipped.
  std::int64_t scans = 0, keyframes = 0, skipped = 0;
  TimingSummary timing;  // per step
  std::optional<StageTimes> stage_means;  // the LiDAR window's stages, mean ms per scan (none in WIO)
  std::vector<ReadWarning> reader_warnings;
  std::vector<std::string> odometry_warnings;
  std::string initialization;                       // LIO and WIO: how it initialized ("" never); LO: ""
  std::vector<estimator::TrackEvent> track_events;  // rejections, fallback guesses, restarts
  // The point-time convention checked again after the first rejection or restart (none: it was not)
  std::optional<estimator::PointTimeRecheckResult> point_time_recheck;
  estimator::SensorFactorStats sensor_factors;      // wheel (and GNSS) factors added and skipped
  std::string timing_plot;                          // "plots/timing_per_scan.png" once written
  // V modes: the camera's landmarks per step (node or scan) after its solve (the fewest over the steps that
  // had any: -1 none), their mean reprojection error there, and the plot of the landmarks over time.
  struct Visual {
    double mean_landmarks = 0;
    int fewest_landmarks = -1;
    int steps_with_landmarks = 0;
    double mean_reprojection_px = 0;
    std::string plot;  // "plots/visual_landmarks.png" once written
  } visual;
  // run --calibrate-online: what the calibration workers found and what the run applied of it
  std::optional<OnlineCalibrationSummary> online_calibration;
  std::optional<CalibrateResult> calibration_estimates;
  // The LiDAR window's degeneracy scores (reliability_files.h): keyframes scored, the spans at or above
  // kDegenerateReported, the plot once written.
  std::int64_t lidar_scored = 0;
  std::vector<DegenerateSpan> lidar_degenerate;
  std::string reliability_plot;
  // With wheel scheduling: intervals scored, the spans where the wheel's factors were left out, the plot.
  std::int64_t wheel_scored = 0;
  std::vector<DegenerateSpan> wheel_suppressed;
  std::string wheel_reliability_plot;
  // The GNSS fixes the innovation test saw (scored in reliability.csv), those it rejected, the plot.
  std::int64_t gnss_scored = 0, gnss_rejected = 0;
  double gnss_mean_score = 0;
  std::string gnss_reliability_plot;
  // The IMU's intervals scored, their mean score, the spans with clipped readings, the plot.
  std::int64_t imu_scored = 0;
  double imu_mean_score = 0;
  std::vector<DegenerateSpan> imu_clipped;
  std::string imu_reliability_plot;
  // With the camera: frames checked, the spans where their observations were left out, the plot.
  std::int64_t camera_scored = 0;
  std::vector<DegenerateSpan> camera_suppressed;
  std::string camera_reliability_plot;
  // The keyframes with inertial estimates (imu_states.csv) and their bias plots (none without).
  std::int64_t imu_states = 0;
  std::string imu_accel_bias_plot, imu_gyro_bias_plot;
  std::string lidar_translation_plot;  // with lio.estimate_lidar_translation
};

// The stream whose messages pace the odometry, for the progress line: the LiDAR's, or the IMU's in WIO.
int PacedStream(const DatasetSensors& sensors, OdometryMode mode);

struct OdometryStageOutput {
  Trajectory estimated;  // T_world_E, the estimator's body
  std::vector<GnssFix> fixes;
  // The estimator's own georeference (G modes, once its alignment started); trajectory.tum is then in ENU
  // and frames.T_map_world maps it back into the map's (the estimator's) world.
  std::optional<Georeference> georef;
  RunFrames frames;
  std::int64_t keyframes_mapped = 0;
  OdometrySummary summary;
  // V modes: the visual front end's statistics per frame tracked, the overlays (PNG bytes by stamp) and how
  // many frames failed to decode.
  std::vector<estimator::FrameTrackStats> tracked_frames;
  std::vector<std::pair<Stamp, std::vector<std::uint8_t>>> overlays;
  std::int64_t camera_undecodable = 0;
};

// Errors: the stream's or the estimator's, a run without a single pose, a file that cannot be written.
Expected<OdometryStageOutput> RunOdometryStage(const OdometryStageInput& input, StageContext& context);

}  // namespace uf::pipeline
