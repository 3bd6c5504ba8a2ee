// What one `ultrafusion run` did, gathered from the stages' outputs once they have run: the report
// (viewer/app/report/run_report.h) and the console summary are made from it.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "viewer/pipeline/run/run_frames.h"
#include "viewer/pipeline/splat/splat_job.h"
#include "viewer/pipeline/stage_runner.h"
#include "viewer/pipeline/stages/accuracy_stage.h"
#include "viewer/pipeline/stages/dataset_stage.h"
#include "viewer/pipeline/stages/map_stage.h"
#include "viewer/pipeline/stages/odometry_stage.h"

namespace uf::pipeline {

struct RunSummary {
  std::string dataset, format;
  std::string mode;  // described: "lio (LiDAR-inertial odometry on velodyne and imu)"
  TrajectoryFrame output_frame = TrajectoryFrame::kLidar;
  std::vector<std::string> notes;  // mode fallbacks, no-op options, georeference, splat warnings
  std::string config_yaml;         // the resolved config, as saved in config.yaml
  std::string repeat_command;      // the command line that repeats the run with config.yaml
  // Scans without point times: the azimuth convention their times are derived with, and why.
  std::optional<PointTimeSelection> point_times;
  std::vector<StageRecord> stages;
  double wall_seconds = 0;
  std::optional<DatasetSummary> dataset_summary;  // the dataset stage's
  OdometrySummary odometry;                       // zero counts when neither the odometry nor --from map ran
  std::optional<MapSummary> map;                  // none with --no-map
  std::optional<SplatJobResult> splat;            // once the splat stage ran
  std::string splat_views;                        // the views stage's line, once it ran
  GroundTruthCheck accuracy;
};

}  // namespace uf::pipeline
