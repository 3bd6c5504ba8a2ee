// Generates a whole simulated sequence into a folder: the dataset in the project's own format (and a ROS1
// bag on request), the ground truth, and the two calibration files. Measurements are generated in time
// order and written as they come (one LiDAR sweep or camera frame in memory at a time).
//
// DIR after success:
//   dataset.yaml + imu.csv, lidar.bin, cam0/, wheel.csv, gnss.csv   (ultrafusion_dataset_writer.h)
//   groundtruth.tum          T_world_body (body = IMU frame) at ground_truth_rate_hz
//   calibration_true.yaml    true extrinsics and time offsets (calibration_file.h)
//   calibration.yaml         what the user is given: extrinsics with the injected errors, offsets 0
//   truth_imu_bias.csv       the true IMU biases at each IMU sample
//   sim.bag                  with write_bag: the same measurements as a ROS1 bag (ros_bag_writer.h)
//   + the extra files the caller passes (the command saves the resolved config)
// Failure leaves none of these behind (temporary names until the end; dataset.yaml is written last).
#pragma once

#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#include "odometry/sim/sequence/simulation_config.h"
#include "odometry/types/status.h"

namespace uf::sim {

struct SimulationProgress {
  std::string stage;  // "scene", "imu", "sensors", ...
  std::int64_t done = 0, total = 0;
};
using ProgressCallback = std::function<void(const SimulationProgress&)>;

struct StreamSummary {
  std::string name;
  std::int64_t count = 0;
  double rate_hz = 0.0;
};

struct SimulationSummary {
  std::string scene;
  double duration_s = 0.0;
  double path_length_m = 0.0;
  std::size_t scene_triangles = 0;
  std::int64_t lidar_points = 0;
  std::vector<StreamSummary> streams;
  std::vector<std::string> files;                     // written into DIR, relative names
  double seconds_scene = 0.0, seconds_sensors = 0.0;  // wall time: scene + BVH, then measurements
  // The motion, from the spline all sensors derive from: the largest body rate |omega| (on a 5 ms grid),
  // and between consecutive written LiDAR scans the largest rotation and translation of the LiDAR (its
  // pose at mid-sweep); zero without a LiDAR or with fewer than two scans.
  double peak_body_rate_rad_s = 0.0;
  double max_scan_rotation_rad = 0.0, max_scan_translation_m = 0.0;
  // How closely that spline follows the poses it was fitted to (SimulationTrajectory).
  double fit_position_error_m = 0.0, fit_rotation_error_rad = 0.0;
};

struct ExtraFile {
  std::string name;  // relative to DIR
  std::string text;
};

// Validates the config, then generates. `out` must not exist or be empty.
Expected<SimulationSummary> GenerateSequence(const SimulationConfig& config, const std::filesystem::path& out,
                                             const std::vector<ExtraFile>& extra_files = {},
                                             const ProgressCallback& progress = {});

}  // namespace uf::sim
