#include "viewer/app/config/estimator_config.h"

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <functional>
#include <map>
#include <optional>

#include "viewer/app/config/yaml_fields.h"

namespace uf::app {
namespace {

using estimator::LidarOdometryConfig;
using estimator::VoxelMapConfig;

using yaml::Boolean;
using yaml::FormatNumber;
using yaml::Nested;
using yaml::Number;
using yaml::ParseMap;
using yaml::Setter;
using yaml::Whole;

Status ParseLoSection(const std::string& file, const YAML::Node& node, LidarOdometryConfig& c) {
  VoxelMapConfig& m = c.map;
  const std::map<std::string, Setter> map_setters = {{"voxel_m", Number(m.voxel_m)},
                                                     {"max_points_per_voxel", Whole(m.max_points_per_voxel)},
                                                     {"max_range_m", Number(m.max_range_m)},
                                                     {"plane_eigen_ratio", Number(m.plane_eigen_ratio)},
                                                     {"min_plane_points", Whole(m.min_plane_points)},
                                                     {"min_plane_sigma_m", Number(m.min_plane_sigma_m)}};
  const std::map<std::string, Setter> setters = {{"input_voxel_m", Number(c.input_voxel_m)},
                                                 {"window_size", Whole(c.window_size)},
                                                 {"max_iterations", Whole(c.max_iterations)},
                                                 {"max_solver_time_s", Number(c.max_solver_time_s)},
                                                 {"max_residuals_per_scan", Whole(c.max_residuals_per_scan)},
                                                 {"huber_m", Number(c.huber_m)},
                                                 {"min_range_m", Number(c.min_range_m)},
                                                 {"max_range_m", Number(c.max_range_m)},
                                                 {"map_insert_voxel_m", Number(c.map_insert_voxel_m)},
                                                 {"association_rounds", Whole(c.association_rounds)},
                                                 {"max_correction_m", Number(c.max_correction_m)},
                                                 {"max_correction_rad", Number(c.max_correction_rad)},
                                                 {"min_points", Whole(c.min_points)},
                                                 {"max_plane_distance_m", Number(c.max_plane_distance_m)},
                                                 {"marginalize", Boolean(c.marginalize)}};
  const std::map<std::string, Setter> motion_setters = {
      {"acc_density", Number(c.motion.acc_density)},
      {"angular_acc_density", Number(c.motion.angular_acc_density)}};
  const Nested nested = {
      {"map", [&](const std::string& path,
                  const YAML::Node& map) { return ParseMap(file, path, map, map_setters); }},
      {"motion", [&](const std::string& path, const YAML::Node& motion) {
         return ParseMap(file, path, motion, motion_setters);
       }}};
  return ParseMap(file, "lo", node, setters, nested);
}

Status ParseLioSection(const std::string& file, const YAML::Node& node, LidarOdometryConfig& c) {
  estimator::ImuNoiseParams& imu = c.imu;
  estimator::InertialInitConfig& init = c.init;
  const std::map<std::string, Setter> imu_setters = {
      {"accel_noise_density", Number(imu.accel_noise_density)},
      {"gyro_noise_density", Number(imu.gyro_noise_density)},
      {"accel_bias_random_walk", Number(imu.accel_bias_random_walk)},
      {"gyro_bias_random_walk", Number(imu.gyro_bias_random_walk)},
      {"gravity", Number(imu.gravity)},
      {"max_accel_bias_change", Number(imu.max_accel_bias_change)},
      {"max_gyro_bias_change", Number(imu.max_gyro_bias_change)}};
  const std::map<std::string, Setter> init_setters = {
      {"window_scans", Whole(init.window_scans)},
      {"static_max_gyro_std", Number(init.static_max_gyro_std)},
      {"static_max_acc_std", Number(init.static_max_acc_std)},
      {"static_max_motion_m", Number(init.static_max_motion_m)},
      {"max_gravity_error", Number(init.max_gravity_error)}};
  const std::map<std::string, Setter> setters = {{"imu_max_gap_s", Number(c.imu_max_gap_s)},
                                                 {"imu_max_wait_s", Number(c.imu_max_wait_s)},
                                                 {"max_speed_mps", Number(c.max_speed_mps)}};
  const Nested nested = {
      {"imu", [&](const std::string& path,
                  const YAML::Node& map) { return ParseMap(file, path, map, imu_setters); }},
      {"init", [&](const std::string& path, const YAML::Node& map) {
         return ParseMap(file, path, map, init_setters);
       }}};
  return ParseMap(file, "lio", node, setters, nested);
}

}  // namespace

Expected<LidarOdometryConfig> LoadLidarOdometryConfig(const std::filesystem::path& file) {
  const std::string name = file.string();
  LidarOdometryConfig config;
  try {
    const YAML::Node root = YAML::LoadFile(name);
    if (root.IsMap()) {
      if (const YAML::Node lo = root["lo"]; lo && !lo.IsNull())
        if (Status s = ParseLoSection(name, lo, config); !s.ok()) return s;
      if (const YAML::Node lio = root["lio"]; lio && !lio.IsNull())
        if (Status s = ParseLioSection(name, lio, config); !s.ok()) return s;
    }
  } catch (const YAML::BadFile&) {
    return Status::Error(name + ": cannot open the configuration file");
  } catch (const YAML::Exception& e) {
    return Status::Error(name + ": " + e.what());
  }
  if (Status s = config.Validate(); !s.ok()) return Status::Error(name + ": " + s.message());
  return config;
}

std::string EmitLidarOdometryConfig(const LidarOdometryConfig& c) {
  const VoxelMapConfig& m = c.map;
  std::string text = "lo:\n";
  text += "  input_voxel_m: " + FormatNumber(c.input_voxel_m) + "\n";
  text += "  window_size: " + std::to_string(c.window_size) + "\n";
  text += "  max_iterations: " + std::to_string(c.max_iterations) + "\n";
  text += "  max_solver_time_s: " + FormatNumber(c.max_solver_time_s) + "\n";
  text += "  max_residuals_per_scan: " + std::to_string(c.max_residuals_per_scan) + "\n";
  text += "  huber_m: " + FormatNumber(c.huber_m) + "\n";
  text += "  min_range_m: " + FormatNumber(c.min_range_m) + "\n";
  text += "  max_range_m: " + FormatNumber(c.max_range_m) + "\n";
  text += "  map_insert_voxel_m: " + FormatNumber(c.map_insert_voxel_m) + "\n";
  text += "  association_rounds: " + std::to_string(c.association_rounds) + "\n";
  text += "  max_correction_m: " + FormatNumber(c.max_correction_m) + "\n";
  text += "  max_correction_rad: " + FormatNumber(c.max_correction_rad) + "\n";
  text += "  min_points: " + std::to_string(c.min_points) + "\n";
  text += "  max_plane_distance_m: " + FormatNumber(c.max_plane_distance_m) + "\n";
  text += std::string("  marginalize: ") + (c.marginalize ? "true" : "false") + "\n";
  text += "  motion:\n";
  text += "    acc_density: " + FormatNumber(c.motion.acc_density) + "\n";
  text += "    angular_acc_density: " + FormatNumber(c.motion.angular_acc_density) + "\n";
  text += "  map:\n";
  text += "    voxel_m: " + FormatNumber(m.voxel_m) + "\n";
  text += "    max_points_per_voxel: " + std::to_string(m.max_points_per_voxel) + "\n";
  text += "    max_range_m: " + FormatNumber(m.max_range_m) + "\n";
  text += "    plane_eigen_ratio: " + FormatNumber(m.plane_eigen_ratio) + "\n";
  text += "    min_plane_points: " + std::to_string(m.min_plane_points) + "\n";
  text += "    min_plane_sigma_m: " + FormatNumber(m.min_plane_sigma_m) + "\n";
  if (!c.use_imu) return text;
  const estimator::ImuNoiseParams& imu = c.imu;
  const estimator::InertialInitConfig& init = c.init;
  text += "lio:\n";
  text += "  imu_max_gap_s: " + FormatNumber(c.imu_max_gap_s) + "\n";
  text += "  imu_max_wait_s: " + FormatNumber(c.imu_max_wait_s) + "\n";
  text += "  max_speed_mps: " + FormatNumber(c.max_speed_mps) + "\n";
  text += "  imu:\n";
  text += "    accel_noise_density: " + FormatNumber(imu.accel_noise_density) + "\n";
  text += "    gyro_noise_density: " + FormatNumber(imu.gyro_noise_density) + "\n";
  text += "    accel_bias_random_walk: " + FormatNumber(imu.accel_bias_random_walk) + "\n";
  text += "    gyro_bias_random_walk: " + FormatNumber(imu.gyro_bias_random_walk) + "\n";
  text += "    gravity: " + FormatNumber(imu.gravity) + "\n";
  text += "    max_accel_bias_change: " + FormatNumber(imu.max_accel_bias_change) + "\n";
  text += "    max_gyro_bias_change: " + FormatNumber(imu.max_gyro_bias_change) + "\n";
  text += "  init:\n";
  text += "    window_scans: " + std::to_string(init.window_scans) + "\n";
  text += "    static_max_gyro_std: " + FormatNumber(init.static_max_gyro_std) + "\n";
  text += "    static_max_acc_std: " + FormatNumber(init.static_max_acc_std) + "\n";
  text += "    static_max_motion_m: " + FormatNumber(init.static_max_motion_m) + "\n";
  text += "    max_gravity_error: " + FormatNumber(init.max_gravity_error) + "\n";
  return text;
}

std::string EmitDatasetConfig(const DatasetConfig& config) {
  const DatasetOptions& r = config.reader;
  std::string text = "dataset:\n";
  text += "  format: " + std::string(DatasetFormatName(r.format)) + "\n";
  if (!r.topics.empty()) {
    text += "  topics:\n";
    for (const TopicSelection& t : r.topics)
      text += "    - {topic: \"" + t.topic + "\", kind: " + std::string(SensorKindName(t.kind)) + "}\n";
  }
  const char* unit = r.imu_accel_unit == ImuAccelUnit::kAuto               ? "auto"
                     : r.imu_accel_unit == ImuAccelUnit::kMetersPerSecond2 ? "m/s^2"
                                                                           : "g";
  text += "  imu_accel_unit: " + std::string(unit) + "\n";
  text += std::string("  derive_point_times_from_azimuth: ") +
          (r.derive_point_times_from_azimuth ? "true" : "false") + "\n";
  text += "  lidar_sweep_period_s: " + FormatNumber(r.lidar_sweep_period_s) + "\n";
  text += std::string("  folder_scan_stamp: ") +
          (r.folder_scan_stamp == ScanStampPosition::kSweepMiddle ? "sweep_middle" : "sweep_start") + "\n";
  if (!config.stream.time_offsets.empty()) {
    text += "  time_offsets_s:\n";
    for (const auto& [name, offset] : config.stream.time_offsets)
      text += "    \"" + name + "\": " + FormatSeconds(offset) + "\n";
  }
  text += "  reorder_window_s: " + FormatSeconds(config.stream.reorder_window) + "\n";
  return text;
}

}  // namespace uf::app
