// The odometry stage of `ultrafusion run`: LO or LIO over the dataset's measurement stream. The LiDAR scans,
// IMU and wheel samples go to the estimator, the camera frames and the keyframes leaving its window go
// straight to the map's KeyframeMapper (a scan is never held twice), the GNSS fixes are kept for the
// georeference. Writes trajectory.tum and trajectory_kitti.txt (in the run's trajectory frame,
// RunFrames::OutputTrajectory), timing.json and plots/timing_per_scan.png.
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "mapping/keyframe_mapper.h"
#include "odometry/estimator/lidar_odometry/lidar_odometry.h"
#include "odometry/io/dataset_sensors.h"
#include "odometry/io/measurement_stream.h"
#include "viewer/pipeline/run/run_frames.h"
#include "viewer/pipeline/run_files.h"
#include "viewer/pipeline/stage_runner.h"

namespace uf::pipeline {

struct OdometryStageInput {
  MeasurementStream* stream = nullptr;
  estimator::LidarOdometry* odometry = nullptr;
  mapping::KeyframeMapper* mapper = nullptr;  // none with --no-map
  DatasetSensors sensors;
  RunFrames frames;
  std::int64_t lidar_scans = 0;  // the total for the progress line; 0: unknown
  std::filesystem::path out;
};

// What the report says of the odometry.
struct OdometrySummary {
  std::int64_t scans = 0, keyframes = 0, skipped = 0;
  TimingSummary timing;
  std::vector<ReadWarning> reader_warnings;
  std::vector<std::string> odometry_warnings;
  std::string initialization;                   // LIO: how it initialized ("" never); LO: ""
  estimator::SensorFactorStats sensor_factors;  // wheel (and GNSS) factors added and skipped
  std::string timing_plot;                      // "plots/timing_per_scan.png" once written
};

struct OdometryStageOutput {
  Trajectory estimated;  // T_world_E, the estimator's body
  std::vector<GnssFix> fixes;
  std::int64_t keyframes_mapped = 0;
  OdometrySummary summary;
};

// Errors: the stream's or the estimator's, a run without a single pose, a file that cannot be written.
Expected<OdometryStageOutput> RunOdometryStage(const OdometryStageInput& input, StageContext& context);

}  // namespace uf::pipeline
