// The odometry stage's files (odometry_stage.h): what the stage collects over the run, and the files written
// from it at the end: trajectory.tum and trajectory_kitti.txt (in ENU with trajectory_wgs84.csv and
// trajectory.geojson when the estimator georeferenced the run), timing.json, the reliability files, the IMU
// states and the plots.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "odometry/types/segmented_vector.h"
#include "viewer/pipeline/stages/imu_states_file.h"
#include "viewer/pipeline/stages/odometry_stage.h"

namespace uf::pipeline {

// What the stage collects: the trajectory (moved to OdometryStageOutput::estimated at the end), the
// processing time of each of the odometry's steps, in order, and (WIO) the world -> ENU alignment as it was
// when each pose left the window (none before the alignment started; InEnuPerPose). The per-step records
// grow in segments, never moved, so that an hour-long run's memory grows by what they hold (SegmentedVector).
struct OdometryCollected {
  SegmentedVector<Stamp> pose_stamps;  // strictly increasing
  SegmentedVector<SE3> poses;
  SegmentedVector<Stamp> stamps;
  SegmentedVector<double> ms;
  std::optional<StageTimes> stage_sums;  // the LiDAR window's stages summed over its steps (each has them)
  SegmentedVector<std::optional<SE3>> T_enu_world_at_pose;
  // The keyframes with a LiDAR degeneracy (registered scans), a wheel score (wheel scheduling) or GNSS
  // fixes checked.
  SegmentedVector<ScoredKeyframe> scored;
  std::vector<std::string> camera_warnings;  // the first frames that failed to decode
  SegmentedVector<StepTime> visual;          // the steps with the camera's figures (V modes)
  SegmentedVector<ImuStateRow> imu_states;   // the keyframes with inertial estimates (Keyframe::inertial)
};

// Writes the files from what was collected (the per-step records are moved out) and fills the summary's
// plots, scores and spans.
Status WriteOdometryFiles(const OdometryStageInput& in, const OdometryStageOutput& out,
                          OdometryCollected& collected, OdometrySummary& summary, StageContext& context);

}  // namespace uf::pipeline
