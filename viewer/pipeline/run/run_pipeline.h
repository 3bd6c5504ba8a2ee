// `ultrafusion run` as a library: a request (what the command line asked for) is planned into a RunPlan
// (every check that can fail before a file is written: configuration, dataset, mode, frames, estimator and
// mapper), then the stages run in order on it:
//
//   dataset   one pass over the dataset as `ultrafusion info` makes it        stages/dataset_stage.h
//   odometry  LO, LIO or WIO; keyframes go straight to the map's mapper      stages/odometry_stage.h
//   map       the last keyframes, the georeference, map.vdb                   stages/map_stage.h
//             (--from map: the earlier trajectory and the scans read again)
//             stages/map_from_trajectory_stage.h
//   exports   map.ply, map.las, map.glb, georef.json                          stages/exports_stage.h
//   splat     splats trained on the camera images; views: rendered views      stages/splat_stage.h
//   accuracy  against the ground truth beside the dataset                     stages/accuracy_stage.h
//
// Each stage takes an input struct made from the plan and the earlier stages' outputs, and returns its own
// output; nothing else is shared between them. Adding a stage is a file in stages/ and an entry in
// RunStageList (run_stage_list.cpp).
#pragma once

#include <filesystem>
#include <memory>
#include <optional>
#include <string>

#include "mapping/keyframe_mapper.h"
#include "odometry/io/dataset_sensors.h"
#include "odometry/io/measurement_stream.h"
#include "viewer/app/config/dataset_config.h"
#include "viewer/app/config/splat_config.h"
#include "viewer/pipeline/calibrate/calibration_branch.h"
#include "viewer/pipeline/progress_line.h"
#include "viewer/pipeline/run/run_estimator.h"
#include "viewer/pipeline/run/run_frames.h"
#include "viewer/pipeline/run/run_mode.h"
#include "viewer/pipeline/run/run_summary.h"

namespace uf::pipeline {

enum class RunFrom { kStart, kMap, kSplat };  // --from: re-run from that stage on an earlier run's outputs

struct RunRequest {
  std::filesystem::path dataset, out;           // out: "" = a new runs/<UTC time>/ with runs/latest
  std::optional<EstimatorMode> mode;            // --mode: none = auto (ChooseMode)
  std::optional<TrajectoryFrame> output_frame;  // none: the estimator's body
  RunFrom from = RunFrom::kStart;
  bool no_map = false, no_splat = false, no_mesh = false;
  double map_voxel_m = 0.05;
  std::string splat_device;  // --device: the splat and views stages' Vulkan device ("": the default)
  bool calibrate_online = false;  // --calibrate-online (LIO): the calibration branch (calibration_branch.h)
  double calibration_hold_s = 15.0;  // --calibration-hold: the window waits this long for the locks
  int overlay_every = 50;            // --overlay-every: V modes, an overlay of the tracks every N-th frame
  // The sections of --config (the defaults without one).
  app::DatasetConfig dataset_config;
  estimator::LidarOdometryConfig lo_config;
  estimator::InertialOdometryConfig wio_config;
  app::SplatConfig splat_config;
};

// Everything the stages need, resolved and opened.
struct RunPlan {
  RunRequest request;
  std::unique_ptr<DatasetReader> reader;
  std::unique_ptr<MeasurementStream> stream;
  std::unique_ptr<RunEstimator> odometry;
  std::unique_ptr<CalibrationBranch> calibration;   // --calibrate-online
  // The point-time convention that the check chose, checked again when the registration degrades
  std::unique_ptr<estimator::PointTimeRecheck> point_time_recheck;
  std::unique_ptr<mapping::KeyframeMapper> mapper;  // none with --no-map, --from splat or in WIO
  DatasetSensors sensors;
  EstimatorMode mode;
  RunFrames frames;
  estimator::LidarOdometryConfig lo_config;      // as the estimator runs it (LO, LIO)
  estimator::InertialOdometryConfig wio_config;  // as the estimator runs it (WIO)
  RunSummary summary;                            // what is known before the stages run

  // The camera factors' options and T_imu_camera, of the window that runs (V modes).
  const estimator::VisualFactorConfig& visual_config() const {
    return frames.mode == OdometryMode::kWio ? wio_config.visual : lo_config.visual;
  }
  const SE3& T_imu_camera() const {
    return frames.mode == OdometryMode::kWio ? wio_config.T_body_camera : lo_config.T_body_camera;
  }
  // The stereo rig's right camera stream whose frames go to the estimator (V modes with visual.stereo and
  // a second camera in the data); -1: none.
  int stereo_stream() const {
    const bool right = frames.mode == OdometryMode::kWio ? wio_config.right_camera != nullptr
                                                         : lo_config.right_camera != nullptr;
    return right ? sensors.camera_right : -1;
  }
};

// Whether a planning error is the user's options or configuration (exit code 2) or the data (1).
enum class PlanErrorKind { kUsage, kData };

// Checks the request and opens what the stages use; writes nothing. `kind` receives the error's kind. A
// --device that names no Vulkan device is a usage error here, before any data is read.
Expected<RunPlan> PlanRun(RunRequest request, PlanErrorKind& kind);

// Creates the output folder (request.out, new or empty, else a new versioned one), writes config.yaml,
// run.json and cameras.yaml (run_cameras.h), runs the stages and returns what happened (a failed stage is
// in summary.stages, not an error). Errors: the output folder or its first files cannot be written.
Expected<RunSummary> RunPipeline(RunPlan& plan, std::filesystem::path& out);

}  // namespace uf::pipeline
