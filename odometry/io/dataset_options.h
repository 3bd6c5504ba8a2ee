// How to open a dataset: the format (normally detected from the path) and per-sensor overrides. Filled
// from the `dataset:` section of the configuration by viewer/app; the defaults suit every documented layout.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "odometry/io/measurement.h"
#include "odometry/types/azimuth_convention.h"
#include "odometry/types/se3.h"

namespace uf {

enum class DatasetFormat { kAuto, kRosBag, kKittiFolder, kKittiRaw, kEuroc, kUltrafusion };

std::string_view DatasetFormatName(
    DatasetFormat format);  // "auto", "rosbag", "kitti", "kitti_raw", "euroc", "ultrafusion"

// Unit of sensor_msgs/Imu linear_acceleration. kAuto: the reader looks at the first second of samples and
// takes g when the median norm is near 1 (0.5..1.5), m/s^2 when it is near 9.81 (5..15), else reports an
// error.
enum class ImuAccelUnit { kAuto, kMetersPerSecond2, kStandardGravity };

enum class ScanStampPosition { kSweepMiddle, kSweepStart };

// A ROS topic to read as a given kind of sensor, whatever its message type allows, and where the sensor sits
// on the body (bags carry no calibration the reader understands; /tf is not read).
struct TopicSelection {
  std::string topic;
  SensorKind kind = SensorKind::kImu;
  std::optional<SE3> T_body_sensor;  // becomes the stream's StreamInfo::T_body_sensor
};

struct DatasetOptions {
  DatasetFormat format = DatasetFormat::kAuto;
  // ROS bags: when non-empty, read exactly these topics (and no others); otherwise every topic whose
  // message type the reader understands is read, its kind found from the type.
  std::vector<TopicSelection> topics;
  ImuAccelUnit imu_accel_unit = ImuAccelUnit::kAuto;
  // Spinning LiDARs without per-point time: derive offsets from azimuth (flagged in the scan) when true,
  // else deliver the scan without point times.
  bool derive_point_times_from_azimuth = true;
  // How those times are derived (odometry/types/azimuth_convention.h). nullopt ("auto"): each reader's
  // default (KITTI-style folders: clockwise from behind; ROS bags: clockwise from the first point; the
  // project's folders: the times as stored), which `run` and `info` check against the data
  // (odometry/estimator/point_times/point_time_check.h) and replace by the convention that fits.
  std::optional<AzimuthConvention> point_time_convention;
  // Sweep period for spinning LiDARs whose scans do not say when they end (KITTI .bin/.pcd folders): used
  // for LidarScan::end and for azimuth-derived point times. Seconds.
  double lidar_sweep_period_s = 0.1;
  // KITTI-style folders: where in the sweep the times.txt stamp of a scan lies. KITTI stamps the instant
  // the head faced forward (the camera trigger), half-way through the sweep, so the scan starts half a
  // sweep earlier; folders converted from other sources may stamp the sweep start.
  ScanStampPosition folder_scan_stamp = ScanStampPosition::kSweepMiddle;
  // A calibration file (calibration_file.h) whose sensors replace the extrinsics and time offsets of the
  // streams of the same name (recalibrated_reader.h); empty: the data's own calibration.
  std::string calibration_file;
};

}  // namespace uf
