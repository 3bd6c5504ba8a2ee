// ROS1 messages, from their serialized bytes, into the measurement structs (layouts as in the .msg files of
// sensor_msgs, nav_msgs and geometry_msgs). Each returns an error when the bytes are too short for the
// message; extra bytes at the end are ignored. The measurement's stamp is the header stamp, reported in
// `header` too so the caller can replace a zero stamp.
#pragma once

#include <cstdint>
#include <span>
#include <string>
#include <string_view>

#include "odometry/io/rosbag/pointcloud2_decode.h"
#include "odometry/io/rosbag/ros_cursor.h"
#include "odometry/types/measurements.h"
#include "odometry/types/status.h"

namespace uf::bag {

// sensor_msgs/Imu: orientation and the covariances are skipped. Acceleration stays in the recorded unit.
Expected<ImuSample> ConvertImu(std::span<const std::uint8_t> message, RosHeader* header);

// sensor_msgs/Image: the raw pixels, undecoded (format = the ROS encoding, "mono8", "bgr8", ...).
Expected<CameraFrame> ConvertImage(std::span<const std::uint8_t> message, RosHeader* header);

// sensor_msgs/CompressedImage: the file bytes, undecoded (format normalised, see NormaliseImageFormat).
Expected<CameraFrame> ConvertCompressedImage(std::span<const std::uint8_t> message, RosHeader* header);

// CompressedImage::format names the codec in several ways ("jpeg", "jpg", "png", "rgb8; jpeg compressed
// bgr8"): -> "png" or "jpeg". Others (e.g. "16UC1; compressedDepth png", which has a 12-byte prefix before
// the PNG) are returned lower-cased for the decoder to refuse.
std::string NormaliseImageFormat(std::string_view format);

// sensor_msgs/NavSatFix.
Expected<GnssFix> ConvertNavSatFix(std::span<const std::uint8_t> message, RosHeader* header);

// nav_msgs/Odometry: twist.twist (linear and angular velocity, in child_frame_id). *child_frame gets
// child_frame_id.
Expected<WheelSample> ConvertOdometry(std::span<const std::uint8_t> message, RosHeader* header,
                                      std::string_view* child_frame);

// geometry_msgs/TwistStamped: twist, in header.frame_id.
Expected<WheelSample> ConvertTwistStamped(std::span<const std::uint8_t> message, RosHeader* header);

// sensor_msgs/PointCloud2 split into its layout and point bytes (a view into `message`).
struct PointCloud2Message {
  RosHeader header;
  PointCloud2Layout layout;
  std::span<const std::uint8_t> data;
};
Expected<PointCloud2Message> ParsePointCloud2(std::span<const std::uint8_t> message);

}  // namespace uf::bag
