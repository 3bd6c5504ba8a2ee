// Which topics of a bag become which streams: by message type, or exactly the topics the options name.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <unordered_map>
#include <vector>

#include "odometry/io/dataset_reader.h"
#include "odometry/io/rosbag/bag_file.h"

namespace uf::bag {

// The message types the reader decodes.
enum class MessageType {
  kPointCloud2,      // sensor_msgs/PointCloud2             -> lidar
  kLivoxCustom,      // livox_ros_driver(2)/CustomMsg        -> lidar
  kImu,              // sensor_msgs/Imu                      -> imu
  kImage,            // sensor_msgs/Image                    -> camera
  kCompressedImage,  // sensor_msgs/CompressedImage          -> camera
  kNavSatFix,        // sensor_msgs/NavSatFix                -> gnss
  kOdometry,         // nav_msgs/Odometry                    -> wheel
  kTwistStamped,     // geometry_msgs/TwistStamped           -> wheel
};

std::optional<MessageType> MessageTypeOf(std::string_view ros_type);
SensorKind SensorKindOf(MessageType type);

struct BagStream {
  StreamInfo info;
  MessageType type = MessageType::kImu;
};

struct BagStreamPlan {
  std::vector<BagStream> streams;
  std::unordered_map<std::uint32_t, int> stream_of_connection;  // connections not listed are not read
};

// Without options.topics: every topic of a known type, in the order of the bag's connections (cameras
// numbered in that order). With it: exactly those topics, in that order; an error names a topic that is
// absent, has two message types, or has a type that cannot be read as the requested kind.
Expected<BagStreamPlan> PlanBagStreams(const std::vector<Connection>& connections,
                                       const DatasetOptions& options, const std::string& bag_path);

}  // namespace uf::bag
