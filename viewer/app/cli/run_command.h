// `ultrafusion run DATASET [--out DIR] [--config FILE] [--mode auto|lo|lio] [--output-frame lidar|imu]
// [--no-map] [--no-mesh] [--map-voxel M]`: runs the pipeline's stages (run_stages.h: dataset, odometry,
// map, exports, accuracy) over a dataset, with progress per stage and a summary table at the end, into DIR
// or a new runs/<UTC time>/ (run_folder.h). Writes config.yaml (the resolved config and the command line
// that repeats the run), the stages' files, report.md and report.html.
// Settings come from the defaults, then the `dataset:`, `lo:` and `lio:` sections of --config.
// Modes: lo = LiDAR-only odometry, lio = LiDAR-inertial; auto = LIO when there is an IMU and the LiDAR's
// extrinsic, else LO (with a warning).
// Errors: bad options or config exit 2 and bad data found before anything is written exit 1, both leaving
// no folder behind; a stage that fails stops the run, keeps what the earlier stages wrote, and report.md
// says which stage failed and why (exit 1).
#pragma once

#include "viewer/app/cli/subcommand.h"

namespace uf::app {

Subcommand AddRunCommand(CLI::App& app);

}  // namespace uf::app
