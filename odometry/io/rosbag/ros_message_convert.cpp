#include "odometry/io/rosbag/ros_message_convert.h"

#include <algorithm>
#include <cctype>
#include <climits>

namespace uf::bag {
namespace {

Eigen::Vector3d ReadVector3(RosCursor& cursor) {
  const double x = cursor.ReadFloat64();
  const double y = cursor.ReadFloat64();
  const double z = cursor.ReadFloat64();
  return {x, y, z};
}

Status TooShort(std::string_view type, std::size_t size) {
  return Status::Error("message is too short for a " + std::string(type) + " (" + std::to_string(size) +
                       " bytes)");
}

// A uint32 image dimension as int; 0 when it does not fit (the decoder then refuses the frame).
int ToInt(std::uint32_t value) { return value <= INT_MAX ? static_cast<int>(value) : 0; }

}  // namespace

Expected<ImuSample> ConvertImu(std::span<const std::uint8_t> message, RosHeader* header) {
  RosCursor cursor(message);
  *header = ReadRosHeader(cursor);
  cursor.SkipFloat64s(4 + 9);  // orientation (x y z w), orientation_covariance
  ImuSample sample;
  sample.stamp = header->stamp;
  sample.gyro = ReadVector3(cursor);
  cursor.SkipFloat64s(9);  // angular_velocity_covariance
  sample.acc = ReadVector3(cursor);
  cursor.SkipFloat64s(9);  // linear_acceleration_covariance
  if (!cursor.ok()) return TooShort("sensor_msgs/Imu", message.size());
  return sample;
}

Expected<CameraFrame> ConvertImage(std::span<const std::uint8_t> message, RosHeader* header) {
  RosCursor cursor(message);
  *header = ReadRosHeader(cursor);
  CameraFrame frame;
  frame.stamp = header->stamp;
  frame.encoded.height = ToInt(cursor.Read<std::uint32_t>());
  frame.encoded.width = ToInt(cursor.Read<std::uint32_t>());
  frame.encoded.format = std::string(cursor.ReadString());
  cursor.Read<std::uint8_t>();  // is_bigendian: matters for 16-bit encodings only
  frame.encoded.row_step = ToInt(cursor.Read<std::uint32_t>());
  const std::span<const std::uint8_t> pixels = cursor.TakeArray(1);
  if (!cursor.ok()) return TooShort("sensor_msgs/Image", message.size());
  frame.encoded.bytes.assign(pixels.begin(), pixels.end());
  return frame;
}

std::string NormaliseImageFormat(std::string_view format) {
  std::string lower(format);
  std::transform(lower.begin(), lower.end(), lower.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  if (lower.find("compresseddepth") != std::string::npos) return lower;
  if (lower.find("png") != std::string::npos) return "png";
  if (lower.find("jpeg") != std::string::npos || lower.find("jpg") != std::string::npos) return "jpeg";
  return lower;
}

Expected<CameraFrame> ConvertCompressedImage(std::span<const std::uint8_t> message, RosHeader* header) {
  RosCursor cursor(message);
  *header = ReadRosHeader(cursor);
  CameraFrame frame;
  frame.stamp = header->stamp;
  frame.encoded.format = NormaliseImageFormat(cursor.ReadString());
  const std::span<const std::uint8_t> bytes = cursor.TakeArray(1);
  if (!cursor.ok()) return TooShort("sensor_msgs/CompressedImage", message.size());
  frame.encoded.bytes.assign(bytes.begin(), bytes.end());
  return frame;
}

Expected<GnssFix> ConvertNavSatFix(std::span<const std::uint8_t> message, RosHeader* header) {
  RosCursor cursor(message);
  *header = ReadRosHeader(cursor);
  GnssFix fix;
  fix.stamp = header->stamp;
  const std::int8_t status = cursor.Read<std::int8_t>();
  cursor.Read<std::uint16_t>();  // service: GPS, GLONASS, COMPASS, GALILEO bits
  // NavSatStatus: NO_FIX = -1, FIX = 0, SBAS_FIX = 1, GBAS_FIX = 2. GBAS (ground-based augmentation) is how
  // drivers report RTK, but the message cannot say float or fixed, so it maps to the weaker kRtkFloat.
  switch (status) {
    case 0:
      fix.status = GnssFixStatus::kFix;
      break;
    case 1:
      fix.status = GnssFixStatus::kSbas;
      break;
    case 2:
      fix.status = GnssFixStatus::kRtkFloat;
      break;
    default:
      fix.status = GnssFixStatus::kNoFix;
      break;
  }
  fix.latitude_deg = cursor.ReadFloat64();
  fix.longitude_deg = cursor.ReadFloat64();
  fix.altitude_m = cursor.ReadFloat64();
  Eigen::Matrix3d covariance;
  for (int row = 0; row < 3; ++row) {
    for (int col = 0; col < 3; ++col) covariance(row, col) = cursor.ReadFloat64();
  }
  const std::uint8_t covariance_type = cursor.Read<std::uint8_t>();
  if (!cursor.ok()) return TooShort("sensor_msgs/NavSatFix", message.size());
  // position_covariance is row-major, m^2, in the local east-north-up frame at the fix (REP-145). With
  // COVARIANCE_TYPE_UNKNOWN (0) the values mean nothing and GnssFix keeps its default, the identity (1 m^2
  // per axis); a consumer that needs an honest uncertainty for such a receiver sets it in its configuration.
  if (covariance_type != 0 && covariance.allFinite()) fix.covariance_enu = covariance;
  return fix;
}

Expected<WheelSample> ConvertOdometry(std::span<const std::uint8_t> message, RosHeader* header,
                                      std::string_view* child_frame) {
  RosCursor cursor(message);
  *header = ReadRosHeader(cursor);
  *child_frame = cursor.ReadString();
  cursor.SkipFloat64s(3 + 4 + 36);  // pose.pose (position, orientation), pose.covariance
  WheelSample sample;
  sample.stamp = header->stamp;
  sample.linear_velocity = ReadVector3(cursor);
  sample.angular_velocity = ReadVector3(cursor);
  cursor.SkipFloat64s(36);  // twist.covariance
  if (!cursor.ok()) return TooShort("nav_msgs/Odometry", message.size());
  return sample;
}

Expected<WheelSample> ConvertTwistStamped(std::span<const std::uint8_t> message, RosHeader* header) {
  RosCursor cursor(message);
  *header = ReadRosHeader(cursor);
  WheelSample sample;
  sample.stamp = header->stamp;
  sample.linear_velocity = ReadVector3(cursor);
  sample.angular_velocity = ReadVector3(cursor);
  if (!cursor.ok()) return TooShort("geometry_msgs/TwistStamped", message.size());
  return sample;
}

Expected<PointCloud2Message> ParsePointCloud2(std::span<const std::uint8_t> message) {
  RosCursor cursor(message);
  PointCloud2Message cloud;
  cloud.header = ReadRosHeader(cursor);
  cloud.layout.height = cursor.Read<std::uint32_t>();
  cloud.layout.width = cursor.Read<std::uint32_t>();
  // PointField[]: string name, uint32 offset, uint8 datatype, uint32 count (at least 4 + 9 bytes each).
  const std::uint32_t field_count = cursor.Read<std::uint32_t>();
  if (field_count > cursor.remaining() / 13) return TooShort("sensor_msgs/PointCloud2", message.size());
  cloud.layout.fields.resize(field_count);
  for (PointFieldLayout& field : cloud.layout.fields) {
    field.name = std::string(cursor.ReadString());
    field.offset = cursor.Read<std::uint32_t>();
    field.datatype = cursor.Read<std::uint8_t>();
    field.count = cursor.Read<std::uint32_t>();
  }
  cloud.layout.is_bigendian = cursor.Read<std::uint8_t>() != 0;
  cloud.layout.point_step = cursor.Read<std::uint32_t>();
  cloud.layout.row_step = cursor.Read<std::uint32_t>();
  cloud.data = cursor.TakeArray(1);
  cursor.Read<std::uint8_t>();  // is_dense: NaN points are dropped whatever it says
  if (!cursor.ok()) return TooShort("sensor_msgs/PointCloud2", message.size());
  return cloud;
}

}  // namespace uf::bag
