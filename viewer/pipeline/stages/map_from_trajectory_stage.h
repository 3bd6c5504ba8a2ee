// The map stage of `ultrafusion run --from map`, first half: instead of keyframes from the odometry, the
// trajectory of an earlier run (its trajectory.tum) and the dataset's scans read again. Each scan is deskewed
// with the trajectory at every point's time (mapping/deskew_with_trajectory.h) and handed to the mapper as a
// keyframe, so that the map, its colour and its exports are then made exactly as after the odometry
// (RunMapStage).
//
// Frames (run_frames.h): trajectory.tum holds T_W_F(t); the mapper wants the estimator's body E:
//   T_W_E(t) = T_W_F(t) * T_F_E,
// and a point p measured at time t_p in the LiDAR frame lands at
//   p_W = T_W_E(t_p) * T_E_lidar * p,
// with T_W_E(t) from Trajectory::PoseAt (slerp and lerp between the bracketing poses). Points outside the
// trajectory's time span are dropped (the scans there are counted and noted).
#pragma once

#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "mapping/keyframe_mapper.h"
#include "odometry/io/dataset_sensors.h"
#include "odometry/io/measurement_stream.h"
#include "odometry/types/keyframe.h"
#include "viewer/pipeline/run/run_frames.h"
#include "viewer/pipeline/stage_runner.h"

namespace uf::pipeline {

struct MapFromTrajectoryInput {
  MeasurementStream* stream = nullptr;
  mapping::KeyframeMapper* mapper = nullptr;
  DatasetSensors sensors;
  RunFrames frames;
  double min_range_m = 1.0, max_range_m = 100.0;  // LiDAR points mapped (the odometry's range limits), m
  std::filesystem::path out;                      // holds trajectory.tum
};

struct MapFromTrajectoryOutput {
  Trajectory estimated;  // T_W_E
  std::vector<GnssFix> fixes;
  std::int64_t scans = 0, keyframes_mapped = 0;
  std::vector<std::string> notes;  // scans outside the trajectory
};

Expected<MapFromTrajectoryOutput> RunMapFromTrajectory(const MapFromTrajectoryInput& input,
                                                       StageContext& context);

}  // namespace uf::pipeline
