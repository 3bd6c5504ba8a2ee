// calibration_estimated.yaml of a run whose window estimated calibration: the camera's time offset or
// extrinsic (visual.estimate_time_offset, visual.estimate_extrinsic; wio. or lio.) and the LiDAR
// extrinsic's translation (lio.estimate_lidar_translation).
#pragma once

#include <filesystem>

#include "viewer/pipeline/run/run_pipeline.h"
#include "viewer/pipeline/stage_runner.h"
#include "viewer/pipeline/stages/odometry_stage.h"

namespace uf::pipeline {

// The calibration file format (which dataset.calibration_file reads) with the IMU and each sensor whose
// calibration the window estimated: the tracked camera with its time offset the one the run read with plus
// the t_d the window ended with and its extrinsic the estimated one (else the given one); the LiDAR with
// T_body_lidar as the window ended (its translation estimated) and the time offset the run read with.
// Nothing when nothing was estimated. Errors: a file that cannot be written.
Status WriteWindowCalibrationEstimate(const RunPlan& plan, const OdometryStageOutput& odometry,
                                      const std::filesystem::path& out, StageContext& context);

}  // namespace uf::pipeline
