// The map stage of `ultrafusion run --from map`: instead of keyframes from the odometry, the trajectory of
// an earlier run (its trajectory.tum) and the dataset's scans read again. Each scan is deskewed with the
// trajectory interpolated at every point's time (mapping/deskew_with_trajectory.h) and handed to the mapper
// as a keyframe, so the map, colour and exports are made exactly as after the odometry.
//
// Frames: trajectory.tum holds T_world_out(t) for the run's output frame (`out`: lidar or imu). The mapper
// wants the estimator's body (`est`: the LiDAR in LO, the IMU in LIO):
//   T_world_est(t) = T_world_out(t) * T_out_est,  T_out_est = I, T_imu_lidar or T_imu_lidar^-1,
// and T_est_lidar = I (LO) or T_imu_lidar (LIO). Scans whose middle lies outside the trajectory's time span
// are counted as skipped.
#pragma once

#include <optional>

#include "odometry/types/trajectory.h"
#include "viewer/app/run_stages.h"

namespace uf::app {

// Reads state.out/trajectory.tum, feeds the dataset's scans (and camera frames, GNSS fixes) to the
// mapper, then finishes and saves the map as RunMapStage does.
Status RunMapFromTrajectoryStage(RunState& state, StageContext& context);

}  // namespace uf::app
