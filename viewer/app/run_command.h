// `ultrafusion run DATASET --out DIR [--config FILE] [--mode auto|lo|lio] [--output-frame lidar|imu]`:
// runs the odometry over a dataset and writes trajectory.tum, trajectory_kitti.txt, timing.json,
// config.yaml and report.md (with ATE/RPE and plots/ when the dataset has ground truth) into DIR.
// Settings come from the defaults, then the `dataset:` and `lo:` sections of --config.
// Modes: lo = LiDAR-only odometry. LIO is not built yet: `--mode lio` is a usage error (exit 2), and
// `--mode auto` (LIO when there is an IMU, else LO) falls back to LO with a warning.
#pragma once

#include "viewer/app/subcommand.h"

namespace uf::app {

Subcommand AddRunCommand(CLI::App& app);

}  // namespace uf::app
