#include "odometry/io/rosbag/bag_streams.h"

#include <algorithm>

#include "odometry/io/rosbag/imu_unit.h"

namespace uf::bag {

std::optional<MessageType> MessageTypeOf(std::string_view ros_type) {
  if (ros_type == "sensor_msgs/PointCloud2") return MessageType::kPointCloud2;
  if (ros_type == "livox_ros_driver/CustomMsg" || ros_type == "livox_ros_driver2/CustomMsg") {
    return MessageType::kLivoxCustom;
  }
  if (ros_type == "sensor_msgs/Imu") return MessageType::kImu;
  if (ros_type == "sensor_msgs/Image") return MessageType::kImage;
  if (ros_type == "sensor_msgs/CompressedImage") return MessageType::kCompressedImage;
  if (ros_type == "sensor_msgs/NavSatFix") return MessageType::kNavSatFix;
  if (ros_type == "nav_msgs/Odometry") return MessageType::kOdometry;
  if (ros_type == "geometry_msgs/TwistStamped") return MessageType::kTwistStamped;
  return std::nullopt;
}

SensorKind SensorKindOf(MessageType type) {
  switch (type) {
    case MessageType::kPointCloud2:
    case MessageType::kLivoxCustom:
      return SensorKind::kLidar;
    case MessageType::kImu:
      return SensorKind::kImu;
    case MessageType::kImage:
    case MessageType::kCompressedImage:
      return SensorKind::kCamera;
    case MessageType::kNavSatFix:
      return SensorKind::kGnss;
    case MessageType::kOdometry:
    case MessageType::kTwistStamped:
      return SensorKind::kWheel;
  }
  return SensorKind::kImu;
}

namespace {

BagStream MakeStream(const Connection& connection, MessageType type, const DatasetOptions& options) {
  BagStream stream;
  stream.type = type;
  stream.info.name = connection.topic;
  stream.info.kind = SensorKindOf(type);
  stream.info.message_type = connection.type;
  if (stream.info.kind == SensorKind::kImu && options.imu_accel_unit != ImuAccelUnit::kAuto) {
    stream.info.imu_accel_unit = std::string(ImuAccelUnitName(options.imu_accel_unit));
  }
  return stream;
}

void NumberCameras(BagStreamPlan& plan) {
  int camera = 0;
  for (BagStream& stream : plan.streams) {
    if (stream.info.kind == SensorKind::kCamera) stream.info.camera = camera++;
  }
}

}  // namespace

Expected<BagStreamPlan> PlanBagStreams(const std::vector<Connection>& connections,
                                       const DatasetOptions& options, const std::string& bag_path) {
  BagStreamPlan plan;
  std::unordered_map<std::string, int> stream_of_topic;
  if (options.topics.empty()) {
    for (const Connection& connection : connections) {
      const std::optional<MessageType> type = MessageTypeOf(connection.type);
      if (!type) continue;  // a type we do not read: ignored
      auto [it, added] = stream_of_topic.emplace(connection.topic, static_cast<int>(plan.streams.size()));
      if (added) {
        plan.streams.push_back(MakeStream(connection, *type, options));
      } else if (plan.streams[it->second].info.message_type != connection.type) {
        continue;  // a second type on one topic: only the first is read
      }
      plan.stream_of_connection[connection.id] = it->second;
    }
    NumberCameras(plan);
    return plan;
  }

  for (const TopicSelection& selection : options.topics) {
    auto on_topic = [&](const Connection& connection) { return connection.topic == selection.topic; };
    const auto first = std::find_if(connections.begin(), connections.end(), on_topic);
    if (first == connections.end()) {
      return Status::Error(bag_path + ": topic " + selection.topic + " (requested as " +
                           std::string(SensorKindName(selection.kind)) + ") is not in the bag");
    }
    const std::optional<MessageType> type = MessageTypeOf(first->type);
    if (!type || SensorKindOf(*type) != selection.kind) {
      return Status::Error(bag_path + ": topic " + selection.topic + " has type " + first->type +
                           ", which cannot be read as " + std::string(SensorKindName(selection.kind)));
    }
    if (stream_of_topic.contains(selection.topic)) {
      return Status::Error("dataset options: topic " + selection.topic + " is selected twice");
    }
    const int index = static_cast<int>(plan.streams.size());
    stream_of_topic[selection.topic] = index;
    plan.streams.push_back(MakeStream(*first, *type, options));
    plan.streams.back().info.T_body_sensor = selection.T_body_sensor;
    for (const Connection& connection : connections) {
      if (!on_topic(connection)) continue;
      if (connection.type != first->type) {
        return Status::Error(bag_path + ": topic " + selection.topic + " carries two message types, " +
                             first->type + " and " + connection.type);
      }
      plan.stream_of_connection[connection.id] = index;
    }
  }
  NumberCameras(plan);
  return plan;
}

}  // namespace uf::bag
