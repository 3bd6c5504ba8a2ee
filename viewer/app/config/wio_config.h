// The `wio:` section of a configuration file (the wheel-inertial window of the wio and wgio modes), mapped
// onto estimator::InertialOdometryConfig. Its keys, defaults and units are in docs/CONFIG.md; the file is
// read by LoadConfigFile (config_file.h).
//
// T_body_wheel and T_body_gnss are not read: they come from the dataset's calibration (the body is the
// IMU). use_gnss comes from --mode.
#pragma once

#include <string>

#include "odometry/estimator/config/inertial_odometry_config.h"

namespace uf::app {

// "wio:\n  node_interval_s: 0.1\n..." with every key.
std::string EmitInertialOdometryConfig(const estimator::InertialOdometryConfig& config);

}  // namespace uf::app
