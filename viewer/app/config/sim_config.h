// The `sim:` section of a configuration file, mapped onto uf::sim::SimulationConfig (read by LoadConfigFile,
// config_file.h, and written). Its keys, defaults and units are in docs/CONFIG.md; configs/sim.yaml states
// them with their ranges, configs/sim-degraded.yaml injects errors. Every key is optional: a key that is not
// given keeps the value of the base config. A list that is given (darkness, slips, outages, ...) replaces
// the base's list.
//
// Conventions of the file (the struct's are in odometry/sim/sequence/simulation_config.h):
//   - start_time_s is the sequence start in seconds since the epoch, parsed exactly to the nanosecond.
//   - Event windows [begin_s, end_s] are seconds RELATIVE TO THE SEQUENCE START; they are stored as
//     absolute stamps begin = start_stamp + begin_s, end = start_stamp + end_s (ns, begin inclusive, end
//     exclusive). They are resolved after the whole section's start_time_s is known, wherever that key
//     stands; windows inherited from `base` are absolute already and are not moved.
//   - extrinsic: T_body_sensor (maps sensor-frame points to the body = IMU frame), either
//       {translation_m: [x, y, z], rotation_rpy_deg: [roll, pitch, yaw]}, R = Rz(yaw) Ry(pitch) Rx(roll)
//     (each part optional, the other keeps the base's value), or {matrix: [16 numbers, row-major 4x4]}.
//
// Only the structure is checked here (unknown keys, types, list shapes, windows with end <= begin, names
// of GNSS qualities, a matrix that is no rigid transform); value ranges are checked by
// uf::sim::ValidateSimulationConfig and the models' Validate functions. Errors read
// "FILE: sim.lidar.rate_hz (line 12): expected a number, got 'fast'".
#pragma once

#include <string>
#include <string_view>

#include "odometry/sim/sequence/simulation_config.h"
#include "odometry/types/status.h"

namespace uf::app {

// The whole config as a YAML document with a `sim:` section that LoadConfigFile reads back to exactly the
// same struct: numbers in shortest round-trip form, stamps and windows as exact decimal seconds, extrinsics
// as 4x4 matrices (with their translation and roll-pitch-yaw in a comment). Sensor `threads` of the
// lidar and camera models are not part of the file (the top-level `threads` is).
std::string EmitSimConfig(const sim::SimulationConfig& config);

// "single", "rtk_float", "rtk_fixed".
std::string_view GnssQualityName(sim::GnssQuality quality);
Expected<sim::GnssQuality> ParseGnssQuality(std::string_view name);

}  // namespace uf::app
