// Raw sensor measurements as the readers deliver them: plain structs in SI units with nanosecond stamps.
// Frames: each measurement is expressed in its own sensor's frame (imu, lidar, camera_i, wheel/base); the
// extrinsics between them come from the configuration (T_imu_lidar, T_imu_cam_i, ...), never from here.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <string>
#include <vector>

#include "odometry/types/stamp.h"

namespace uf {

struct ImuSample {
  Stamp stamp = 0;
  Eigen::Vector3d acc = Eigen::Vector3d::Zero();   // specific force in the imu frame, m/s^2 (+g up at rest)
  Eigen::Vector3d gyro = Eigen::Vector3d::Zero();  // angular velocity of the imu frame, in it, rad/s
};

// One return, in the lidar frame. float keeps a 10^5-point scan small; single precision is ~1e-6 m here.
struct LidarPoint {
  float x = 0, y = 0, z = 0;   // m, lidar frame
  float intensity = 0;         // as the sensor reports it (unitless; scale differs between sensors)
  std::uint16_t ring = 0;      // laser (row) index as the sensor numbers it; valid if LidarScan::has_ring
  std::int32_t offset_ns = 0;  // time of this point minus LidarScan::stamp, ns; valid if has_point_times
};

struct LidarScan {
  Stamp stamp = 0;  // scan start: a point was measured at stamp + offset_ns
  Stamp end = 0;    // scan end (>= stamp); the last point time, or stamp + sweep period when unknown
  std::vector<LidarPoint> points;
  bool has_point_times = false;  // false: offset_ns is meaningless and the scan cannot be deskewed per point
  bool point_times_from_azimuth = false;  // offset_ns was derived from each point's azimuth, not measured
  bool has_ring = false;                  // false: ring is meaningless
};

// An 8-bit image, rows top to bottom, pixels left to right, channels interleaved (gray, or R G B).
struct Image {
  int width = 0;                     // pixels
  int height = 0;                    // pixels
  int channels = 0;                  // 1 (gray) or 3 (RGB)
  std::vector<std::uint8_t> pixels;  // width * height * channels bytes, row-major, no padding

  bool empty() const { return pixels.empty(); }
};

// An image still in its file encoding (PNG, JPEG, ...) or a raw ROS encoding; decoded only when needed.
struct EncodedImage {
  std::string format;         // "png", "jpeg", or a raw sensor_msgs/Image encoding ("mono8", "bgr8", ...)
  int width = 0, height = 0;  // raw encodings only (compressed formats carry their own size)
  int row_step = 0;           // raw encodings only: bytes per row
  std::vector<std::uint8_t> bytes;  // the encoded data

  bool empty() const { return bytes.empty(); }
};

struct CameraFrame {
  Stamp stamp = 0;       // mid-exposure time
  int camera = 0;        // index of the camera in the rig (the configuration's camera list)
  Image image;           // decoded pixels; empty until decoded (see uf::DecodeCameraFrame in odometry/io)
  EncodedImage encoded;  // the bytes as read; readers fill this and leave `image` empty (lazy decoding)
};

// Wheel (or vehicle) odometry, expressed in the wheel odometry frame (the vehicle base frame; its pose
// relative to the imu is the configured T_imu_wheel).
struct WheelSample {
  Stamp stamp = 0;
  Eigen::Vector3d linear_velocity = Eigen::Vector3d::Zero();   // m/s, wheel/base frame
  Eigen::Vector3d angular_velocity = Eigen::Vector3d::Zero();  // rad/s, wheel/base frame
};

enum class GnssFixStatus { kNoFix, kFix, kSbas, kRtkFloat, kRtkFixed };

// A GNSS position fix of the antenna on the WGS84 ellipsoid.
struct GnssFix {
  Stamp stamp = 0;
  double latitude_deg = 0;   // degrees, north positive
  double longitude_deg = 0;  // degrees, east positive
  double altitude_m = 0;     // m above the WGS84 ellipsoid (not above mean sea level)
  Eigen::Matrix3d covariance_enu = Eigen::Matrix3d::Identity();  // m^2, local east-north-up at the fix
  GnssFixStatus status = GnssFixStatus::kNoFix;
};

}  // namespace uf
