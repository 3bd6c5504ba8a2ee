// The schema of each section of the configuration file (schema.h), declared in the section's file: the one
// place where a key, its field, unit and meaning are written. Internal to uf_app_config.
#pragma once

#include "odometry/estimator/config/inertial_odometry_config.h"
#include "odometry/estimator/config/lidar_odometry_config.h"
#include "odometry/sim/sequence/simulation_config.h"
#include "viewer/app/config/dataset_config.h"
#include "viewer/app/config/schema.h"
#include "viewer/app/config/splat_config.h"

namespace uf::app::config {

const Schema<DatasetConfig>& DatasetSchema();                  // dataset_config.cpp
const Schema<estimator::LidarOdometryConfig>& LoSchema();      // estimator_config.cpp
const Schema<estimator::LidarOdometryConfig>& LioSchema();     // estimator_config.cpp
const Schema<estimator::InertialOdometryConfig>& WioSchema();  // wio_config.cpp
const Schema<SplatConfig>& SplatSchema();                      // splat_config.cpp
const Schema<sim::SimulationConfig>& SimSchema();              // sim_config.cpp

// The parts that the lio: and wio: sections share (estimator_parts.cpp). `scale`: what the IMU's default
// noise densities are, for the key's meaning; `lidar`: the LIO initialization (LO poses; with its window and
// its mode M's keys) or the WIO one (wheel poses; the static and gravity-norm keys only).
Schema<estimator::ImuNoiseParams> ImuNoiseSchema(const std::string& scale);
Schema<estimator::InertialInitConfig> InitSchema(bool lidar);
Schema<estimator::WheelFactorConfig> WheelSchema();
Schema<estimator::GnssFactorConfig> GnssSchema();
Schema<estimator::VisualFactorConfig> VisualSchema();  // the camera factors of either window

}  // namespace uf::app::config
