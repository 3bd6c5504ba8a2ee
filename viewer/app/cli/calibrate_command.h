// `ultrafusion calibrate DATASET [--out DIR]`: the LiDAR-IMU time offset and rotation of a rig, estimated
// online on a LiDAR-only odometry pass (viewer/pipeline/calibrate/calibrate_job.h), to check a rig before a
// mapping drive. Prints the estimates against the dataset's calibration; writes calibration_estimated.yaml,
// the solves and their plots with --out.
#pragma once

#include "viewer/app/cli/subcommand.h"

namespace uf::app {

Subcommand AddCalibrateCommand(CLI::App& app);

}  // namespace uf::app
