// The stages of `ultrafusion run` and what they hand on to each other:
//   dataset   one pass as `ultrafusion info` makes it: the report's dataset summary, the scan count
//   odometry  LO or LIO over the dataset: trajectory.tum, trajectory_kitti.txt, timing.json, the timing
//             plot; keyframes go straight into the map stage's mapper (a scan is never held twice)
//   map       the remaining keyframes, the georeference from GNSS, map.vdb
//   exports   map.ply, map.las, map.glb, georef.json
//   splat     splats trained on the keyframe images; views: the splats rendered at the held-out poses
//             (run_splat_stage.h)
//   accuracy  against the ground truth found beside the dataset: the eval table and plots (an evaluation
//             that is not possible, e.g. a straight trajectory, is noted in the report, not a failure)
// With --from map the dataset and odometry stages are skipped and the map stage is
// RunMapFromTrajectoryStage (stage_map_from_trajectory.h): the earlier run's trajectory.tum and the scans.
// Each stage is a function of the shared RunState; run_command.cpp lists them (adding a stage is an entry
// there and a function here or in a file of its own).
#pragma once

#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "mapping/keyframe_mapper.h"
#include "mapping/map_file.h"
#include "odometry/estimator/lidar_odometry/lidar_odometry.h"
#include "odometry/io/dataset_sensors.h"
#include "odometry/io/measurement_stream.h"
#include "viewer/app/dataset_config.h"
#include "viewer/app/pipeline_stages.h"
#include "viewer/app/run_report.h"
#include "viewer/app/splat_job.h"

namespace uf::app {

struct RunState {
  // Resolved by the command before the stages run.
  std::filesystem::path dataset, out;
  DatasetConfig dataset_config;
  DatasetSensors sensors;  // the first LiDAR, IMU and GNSS streams, T_imu_lidar
  bool lio = false;
  bool mesh = true;
  double min_range_m = 1.0, max_range_m = 100.0;  // LiDAR points mapped (the odometry's range limits), m
  std::string output_frame;                       // of the written trajectory: "lidar" or "imu"
  SE3 T_estimator_body;                           // the dataset's body frame in the estimator's body frame
  std::unique_ptr<DatasetReader> reader;
  std::optional<MeasurementStream> stream;
  std::optional<estimator::LidarOdometry> odometry;
  std::optional<mapping::KeyframeMapper> mapper;  // none with --no-map
  SplatConfig splat_config;                       // the splat: section of --config

  // Filled by the stages.
  std::int64_t lidar_scans = 0;  // in the dataset (dataset stage); 0: unknown
  Trajectory estimated;          // T_world_body in the estimator's body frame (odometry stage)
  std::vector<GnssFix> fixes;    // for the georeference
  std::int64_t keyframes_mapped = 0;
  std::optional<mapping::MapGeoreference> georef;
  std::optional<SplatJobResult> splat;  // the splat stage's result, rendered by the views stage
  RunReport report;
};

Status RunDatasetStage(RunState& state, StageContext& context);
Status RunOdometryStage(RunState& state, StageContext& context);
Status RunAccuracyStage(RunState& state, StageContext& context);
Status RunMapStage(RunState& state, StageContext& context);
Status RunExportsStage(RunState& state, StageContext& context);

}  // namespace uf::app
