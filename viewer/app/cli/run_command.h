// `ultrafusion run DATASET [--out DIR] [--config FILE] [--mode auto|lo|lio] [--output-frame lidar|imu]
// [--from map|splat] [--no-map] [--no-mesh] [--no-splat] [--map-voxel M]`: the options and the `dataset:`,
// `lo:`, `lio:` and `splat:` sections of --config become a pipeline::RunRequest, which the pipeline
// (viewer/pipeline/run/run_pipeline.h) plans and runs stage by stage into DIR or a new runs/<UTC time>/;
// report.md and report.html are written from its summary (report/run_report.h), a table printed.
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
