// The `dataset:` section of a configuration file, mapped onto the plain option structs of odometry/io.
// Every key is optional; unknown keys are an error naming the key and the file.
//
//   dataset:
//     format: auto                # auto | rosbag | kitti | euroc | ultrafusion
//     topics:                     # ROS bags: read exactly these (default: every topic of a known type)
//       - {topic: /imu/data, kind: imu}      # kind: imu | lidar | camera | wheel | gnss
//     imu_accel_unit: auto        # auto | m/s^2 | g
//     derive_point_times_from_azimuth: true
//     lidar_sweep_period_s: 0.1
//     folder_scan_stamp: sweep_middle   # KITTI-style folders: times.txt stamps sweep_middle | sweep_start
//     time_offsets_s: {lidar: -0.012, /fix: 0.2}   # added to the stamps, by stream name or sensor kind
//     reorder_window_s: 1.0
#pragma once

#include <filesystem>

#include "odometry/io/dataset_options.h"
#include "odometry/io/measurement_stream.h"

namespace uf::app {

struct DatasetConfig {
  DatasetOptions reader;
  MeasurementStreamOptions stream;
};

// Reads the file's `dataset:` section. The other known sections (config_sections.h: sim, calibration) are
// left to their own readers; any other top-level key is reported as unknown.
Expected<DatasetConfig> LoadDatasetConfig(const std::filesystem::path& file);

// "rosbag", "kitti", ... as accepted by the config and the --format option.
Expected<DatasetFormat> ParseDatasetFormat(const std::string& name);

}  // namespace uf::app
