// The configuration file: one YAML file with top-level sections (dataset:, sim:, calibration:, lo:, lio:,
// wio:, splat:), read once and handed section by section to their schemas. Every key is optional; the keys,
// their defaults and units are in docs/CONFIG.md. Errors name the file, the key path, its line and the value
// ("FILE: lo.map.voxel_m (line 3): expected a number, got 'fast'").
#pragma once

#include <filesystem>

#include "odometry/estimator/config/lidar_odometry_config.h"
#include "odometry/sim/sequence/simulation_config.h"
#include "viewer/app/config/dataset_config.h"
#include "viewer/app/config/estimator_config.h"
#include "viewer/app/config/sim_config.h"
#include "viewer/app/config/splat_config.h"
#include "viewer/app/config/wio_config.h"

namespace uf::app {

// Every section's settings: the base given to LoadConfigFile with what the file sets.
struct ConfigFile {
  DatasetConfig dataset;                    // dataset:
  estimator::LidarOdometryConfig odometry;  // lo: and lio: (use_imu and T_body_lidar are not read)
  estimator::InertialOdometryConfig wio;    // wio: (use_gnss and the extrinsics are not read)
  SplatConfig splat;                        // splat:
  sim::SimulationConfig sim;                // sim:
};

// Reads FILE over `base`: a file without a section, or an empty file, keeps the base's settings for it. The
// calibration: section is left to ReadCalibrationFile (odometry/io/calibration_file.h); any other
// top-level key is an error. The odometries (LO with use_imu false, WIO with its GNSS keys) and the splat
// settings are validated
// (their Validate()); the simulation's are checked by the sim command once its options are applied.
Expected<ConfigFile> LoadConfigFile(const std::filesystem::path& file, ConfigFile base = {});

}  // namespace uf::app
