// Test fixtures that need ROS's own code: messages serialized by the ROS message classes, and bags written
// (and read back, for comparison) by librosbag. Compiled as C++17 in a library of its own because the ROS
// message headers use std::allocator<void>::rebind, which C++20 removed; this header has no ROS types.
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <vector>

namespace uf::testing {

struct RosMessage {
  std::string type;  // "sensor_msgs/Imu"
  std::string md5sum;
  std::string definition;
  std::vector<std::uint8_t> bytes;  // the serialized message
};

struct BagEntry {
  std::string topic;
  std::int64_t record_time_ns = 0;
  RosMessage message;
};

enum class BagCompression { kNone, kBz2, kLz4 };

// Writes the entries in order with librosbag (rosbag::Bag in write mode). Returns an error text, or "".
std::string WriteBag(const std::string& path, const std::vector<BagEntry>& entries,
                     BagCompression compression = BagCompression::kNone,
                     std::uint32_t chunk_threshold = 768 * 1024);

// What librosbag's rosbag::View reads from a bag (in its time order); empty with `error` set on failure.
struct LibrosbagMessage {
  std::string topic;
  std::string type;
  std::int64_t record_time_ns = 0;
  std::vector<std::uint8_t> bytes;
};
std::vector<LibrosbagMessage> ReadBagWithLibrosbag(const std::string& path, std::string* error);

struct Vec3 {
  double x = 0, y = 0, z = 0;
};

// Messages serialized by the ROS message classes (sensor_msgs, nav_msgs, geometry_msgs).
RosMessage MakeImu(std::int64_t stamp_ns, const std::string& frame_id, Vec3 acc, Vec3 gyro);
RosMessage MakeOdometry(std::int64_t stamp_ns, const std::string& frame_id, const std::string& child_frame_id,
                        Vec3 linear, Vec3 angular);
RosMessage MakeTwistStamped(std::int64_t stamp_ns, const std::string& frame_id, Vec3 linear, Vec3 angular);
RosMessage MakeNavSatFix(std::int64_t stamp_ns, const std::string& frame_id, std::int8_t status,
                         double latitude, double longitude, double altitude,
                         const std::array<double, 9>& covariance, std::uint8_t covariance_type);
RosMessage MakeImage(std::int64_t stamp_ns, const std::string& frame_id, std::uint32_t width,
                     std::uint32_t height, const std::string& encoding, std::uint32_t step,
                     std::vector<std::uint8_t> data);
RosMessage MakeCompressedImage(std::int64_t stamp_ns, const std::string& frame_id, const std::string& format,
                               std::vector<std::uint8_t> data);

struct CloudField {
  std::string name;
  std::uint32_t offset = 0;
  std::uint8_t datatype = 7;  // 1 int8 .. 8 float64 (sensor_msgs/PointField)
  std::uint32_t count = 1;
};
RosMessage MakePointCloud2(std::int64_t stamp_ns, const std::string& frame_id, std::uint32_t height,
                           std::uint32_t width, const std::vector<CloudField>& fields, bool is_bigendian,
                           std::uint32_t point_step, std::uint32_t row_step, std::vector<std::uint8_t> data);

// livox_ros_driver/CustomMsg has no ROS package here: serialized by hand from its .msg layout.
struct LivoxPoint {
  std::uint32_t offset_time = 0;
  float x = 0, y = 0, z = 0;
  std::uint8_t reflectivity = 0, tag = 0, line = 0;
};
RosMessage MakeLivoxCustomMsg(std::int64_t stamp_ns, const std::string& frame_id, std::uint64_t timebase,
                              const std::vector<LivoxPoint>& points,
                              const std::string& type = "livox_ros_driver/CustomMsg");

// Any bytes under any type name (damaged messages, types the reader does not know).
RosMessage MakeRaw(const std::string& type, std::vector<std::uint8_t> bytes);

}  // namespace uf::testing
