#include "tests/unit/io/rosbag/ros_bag_fixtures.h"

#include <geometry_msgs/TwistStamped.h>
#include <nav_msgs/Odometry.h>
#include <rosbag/bag.h>
#include <rosbag/view.h>
#include <sensor_msgs/CompressedImage.h>
#include <sensor_msgs/Image.h>
#include <sensor_msgs/Imu.h>
#include <sensor_msgs/NavSatFix.h>
#include <sensor_msgs/PointCloud2.h>

#include <cstring>
#include <exception>

namespace uf::testing {

// A message that is already serialized, written by rosbag::Bag under the type it names.
struct SerializedMessage {
  const RosMessage* message;
};

}  // namespace uf::testing

namespace ros {
namespace message_traits {
template <>
struct MD5Sum<uf::testing::SerializedMessage> {
  static const char* value(const uf::testing::SerializedMessage& m) { return m.message->md5sum.c_str(); }
  static const char* value() { return "*"; }
};
template <>
struct DataType<uf::testing::SerializedMessage> {
  static const char* value(const uf::testing::SerializedMessage& m) { return m.message->type.c_str(); }
  static const char* value() { return "*"; }
};
template <>
struct Definition<uf::testing::SerializedMessage> {
  static const char* value(const uf::testing::SerializedMessage& m) { return m.message->definition.c_str(); }
  static const char* value() { return ""; }
};
}  // namespace message_traits
namespace serialization {
template <>
struct Serializer<uf::testing::SerializedMessage> {
  template <typename Stream>
  static void write(Stream& stream, const uf::testing::SerializedMessage& m) {
    const std::vector<std::uint8_t>& bytes = m.message->bytes;
    if (!bytes.empty()) std::memcpy(stream.advance(bytes.size()), bytes.data(), bytes.size());
  }
  static uint32_t serializedLength(const uf::testing::SerializedMessage& m) {
    return static_cast<uint32_t>(m.message->bytes.size());
  }
};
}  // namespace serialization
}  // namespace ros

namespace uf::testing {
namespace {

ros::Time ToRosTime(std::int64_t ns) {
  return ros::Time(static_cast<uint32_t>(ns / 1000000000), static_cast<uint32_t>(ns % 1000000000));
}

std_msgs::Header Header(std::int64_t stamp_ns, const std::string& frame_id) {
  std_msgs::Header header;
  header.stamp = ToRosTime(stamp_ns);
  header.frame_id = frame_id;
  return header;
}

geometry_msgs::Vector3 ToVector3(Vec3 v) {
  geometry_msgs::Vector3 out;
  out.x = v.x;
  out.y = v.y;
  out.z = v.z;
  return out;
}

template <typename M>
RosMessage Serialize(const M& message) {
  RosMessage out;
  out.type = ros::message_traits::DataType<M>::value();
  out.md5sum = ros::message_traits::MD5Sum<M>::value();
  out.definition = ros::message_traits::Definition<M>::value();
  out.bytes.resize(ros::serialization::serializationLength(message));
  ros::serialization::OStream stream(out.bytes.data(), static_cast<uint32_t>(out.bytes.size()));
  ros::serialization::serialize(stream, message);
  return out;
}

template <typename T>
void Append(std::vector<std::uint8_t>& bytes, T value) {
  const auto* raw = reinterpret_cast<const std::uint8_t*>(&value);
  bytes.insert(bytes.end(), raw, raw + sizeof(T));
}

}  // namespace

std::string WriteBag(const std::string& path, const std::vector<BagEntry>& entries,
                     BagCompression compression, std::uint32_t chunk_threshold) {
  try {
    rosbag::Bag bag(path, rosbag::bagmode::Write);
    bag.setChunkThreshold(chunk_threshold);
    bag.setCompression(compression == BagCompression::kBz2   ? rosbag::compression::BZ2
                       : compression == BagCompression::kLz4 ? rosbag::compression::LZ4
                                                             : rosbag::compression::Uncompressed);
    for (const BagEntry& entry : entries) {
      bag.write(entry.topic, ToRosTime(entry.record_time_ns), SerializedMessage{&entry.message});
    }
    bag.close();
  } catch (const std::exception& e) {
    return e.what();
  }
  return "";
}

std::vector<LibrosbagMessage> ReadBagWithLibrosbag(const std::string& path, std::string* error) {
  std::vector<LibrosbagMessage> messages;
  try {
    rosbag::Bag bag(path, rosbag::bagmode::Read);
    rosbag::View view(bag);
    for (const rosbag::MessageInstance& instance : view) {
      LibrosbagMessage message;
      message.topic = instance.getTopic();
      message.type = instance.getDataType();
      message.record_time_ns = static_cast<std::int64_t>(instance.getTime().toNSec());
      message.bytes.resize(instance.size());
      ros::serialization::OStream stream(message.bytes.data(), static_cast<uint32_t>(message.bytes.size()));
      instance.write(stream);
      messages.push_back(std::move(message));
    }
  } catch (const std::exception& e) {
    *error = e.what();
    return {};
  }
  return messages;
}

RosMessage MakeImu(std::int64_t stamp_ns, const std::string& frame_id, Vec3 acc, Vec3 gyro) {
  sensor_msgs::Imu imu;
  imu.header = Header(stamp_ns, frame_id);
  imu.orientation.w = 1;
  imu.angular_velocity = ToVector3(gyro);
  imu.linear_acceleration = ToVector3(acc);
  imu.linear_acceleration_covariance[0] = 0.5;  // non-zero neighbours of the fields read
  imu.angular_velocity_covariance[8] = 0.25;
  return Serialize(imu);
}

RosMessage MakeOdometry(std::int64_t stamp_ns, const std::string& frame_id, const std::string& child_frame_id,
                        Vec3 linear, Vec3 angular) {
  nav_msgs::Odometry odometry;
  odometry.header = Header(stamp_ns, frame_id);
  odometry.child_frame_id = child_frame_id;
  odometry.pose.pose.position.x = 123;
  odometry.pose.pose.orientation.w = 1;
  odometry.pose.covariance[35] = 7;
  odometry.twist.twist.linear = ToVector3(linear);
  odometry.twist.twist.angular = ToVector3(angular);
  odometry.twist.covariance[0] = 3;
  return Serialize(odometry);
}

RosMessage MakeTwistStamped(std::int64_t stamp_ns, const std::string& frame_id, Vec3 linear, Vec3 angular) {
  geometry_msgs::TwistStamped twist;
  twist.header = Header(stamp_ns, frame_id);
  twist.twist.linear = ToVector3(linear);
  twist.twist.angular = ToVector3(angular);
  return Serialize(twist);
}

RosMessage MakeNavSatFix(std::int64_t stamp_ns, const std::string& frame_id, std::int8_t status,
                         double latitude, double longitude, double altitude,
                         const std::array<double, 9>& covariance, std::uint8_t covariance_type) {
  sensor_msgs::NavSatFix fix;
  fix.header = Header(stamp_ns, frame_id);
  fix.status.status = status;
  fix.status.service = sensor_msgs::NavSatStatus::SERVICE_GPS;
  fix.latitude = latitude;
  fix.longitude = longitude;
  fix.altitude = altitude;
  for (int i = 0; i < 9; ++i) fix.position_covariance[i] = covariance[i];
  fix.position_covariance_type = covariance_type;
  return Serialize(fix);
}

RosMessage MakeImage(std::int64_t stamp_ns, const std::string& frame_id, std::uint32_t width,
                     std::uint32_t height, const std::string& encoding, std::uint32_t step,
                     std::vector<std::uint8_t> data) {
  sensor_msgs::Image image;
  image.header = Header(stamp_ns, frame_id);
  image.width = width;
  image.height = height;
  image.encoding = encoding;
  image.step = step;
  image.data = std::move(data);
  return Serialize(image);
}

RosMessage MakeCompressedImage(std::int64_t stamp_ns, const std::string& frame_id, const std::string& format,
                               std::vector<std::uint8_t> data) {
  sensor_msgs::CompressedImage image;
  image.header = Header(stamp_ns, frame_id);
  image.format = format;
  image.data = std::move(data);
  return Serialize(image);
}

RosMessage MakePointCloud2(std::int64_t stamp_ns, const std::string& frame_id, std::uint32_t height,
                           std::uint32_t width, const std::vector<CloudField>& fields, bool is_bigendian,
                           std::uint32_t point_step, std::uint32_t row_step, std::vector<std::uint8_t> data) {
  sensor_msgs::PointCloud2 cloud;
  cloud.header = Header(stamp_ns, frame_id);
  cloud.height = height;
  cloud.width = width;
  for (const CloudField& field : fields) {
    sensor_msgs::PointField point_field;
    point_field.name = field.name;
    point_field.offset = field.offset;
    point_field.datatype = field.datatype;
    point_field.count = field.count;
    cloud.fields.push_back(point_field);
  }
  cloud.is_bigendian = is_bigendian;
  cloud.point_step = point_step;
  cloud.row_step = row_step;
  cloud.data = std::move(data);
  cloud.is_dense = false;
  return Serialize(cloud);
}

RosMessage MakeLivoxCustomMsg(std::int64_t stamp_ns, const std::string& frame_id, std::uint64_t timebase,
                              const std::vector<LivoxPoint>& points, const std::string& type) {
  RosMessage message;
  message.type = type;
  message.md5sum = "e4d6829bdfe657cb6c21a746c86b21a6";  // livox_ros_driver/CustomMsg
  message.definition =
      "std_msgs/Header header\nuint64 timebase\nuint32 point_num\nuint8 lidar_id\n"
      "uint8[3] rsvd\nCustomPoint[] points\n";
  std::vector<std::uint8_t>& bytes = message.bytes;
  Append<std::uint32_t>(bytes, 0);  // seq
  Append<std::uint32_t>(bytes, static_cast<std::uint32_t>(stamp_ns / 1000000000));
  Append<std::uint32_t>(bytes, static_cast<std::uint32_t>(stamp_ns % 1000000000));
  Append<std::uint32_t>(bytes, static_cast<std::uint32_t>(frame_id.size()));
  bytes.insert(bytes.end(), frame_id.begin(), frame_id.end());
  Append<std::uint64_t>(bytes, timebase);
  Append<std::uint32_t>(bytes, static_cast<std::uint32_t>(points.size()));
  Append<std::uint8_t>(bytes, 1);   // lidar_id
  bytes.insert(bytes.end(), 3, 0);  // rsvd
  Append<std::uint32_t>(bytes, static_cast<std::uint32_t>(points.size()));
  for (const LivoxPoint& point : points) {
    Append(bytes, point.offset_time);
    Append(bytes, point.x);
    Append(bytes, point.y);
    Append(bytes, point.z);
    Append(bytes, point.reflectivity);
    Append(bytes, point.tag);
    Append(bytes, point.line);
  }
  return message;
}

RosMessage MakeRaw(const std::string& type, std::vector<std::uint8_t> bytes) {
  RosMessage message;
  message.type = type;
  message.md5sum = "*";
  message.bytes = std::move(bytes);
  return message;
}

}  // namespace uf::testing
