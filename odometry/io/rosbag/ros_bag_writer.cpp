#include "odometry/io/rosbag/ros_bag_writer.h"

#include <nav_msgs/Odometry.h>
#include <rosbag/bag.h>
#include <sensor_msgs/CompressedImage.h>
#include <sensor_msgs/Imu.h>
#include <sensor_msgs/NavSatFix.h>
#include <sensor_msgs/PointCloud2.h>

#include <cstring>
#include <exception>

#include "odometry/io/image_decode.h"

namespace uf {
namespace fs = std::filesystem;

struct RosBagWriter::State {
  fs::path path, temporary;
  std::vector<BagTopic> topics;
  rosbag::Bag bag;
  bool finished = false;
};

namespace {

ros::Time ToRosTime(Stamp t) {
  return ros::Time(static_cast<uint32_t>(t / kNanosecondsPerSecond),
                   static_cast<uint32_t>(t % kNanosecondsPerSecond));
}

std_msgs::Header Header(Stamp t, const std::string& frame_id) {
  std_msgs::Header header;
  header.stamp = ToRosTime(t);
  header.frame_id = frame_id;
  return header;
}

geometry_msgs::Vector3 ToVector3(const Eigen::Vector3d& v) {
  geometry_msgs::Vector3 out;
  out.x = v.x();
  out.y = v.y();
  out.z = v.z();
  return out;
}

sensor_msgs::Imu ToMessage(const ImuSample& sample, const std::string& frame_id) {
  sensor_msgs::Imu imu;
  imu.header = Header(sample.stamp, frame_id);
  imu.orientation.w = 1.0;
  imu.orientation_covariance[0] = -1.0;  // REP 145: no orientation estimate
  imu.angular_velocity = ToVector3(sample.gyro);
  imu.linear_acceleration = ToVector3(sample.acc);
  return imu;
}

sensor_msgs::PointField Field(const char* name, uint32_t offset, uint8_t datatype) {
  sensor_msgs::PointField field;
  field.name = name;
  field.offset = offset;
  field.datatype = datatype;
  field.count = 1;
  return field;
}

// Packed layout, 22 bytes per point: x y z intensity (float32) at 0..15, t (uint32 ns) at 16, ring (uint16)
// at 20. Little-endian, as the host.
sensor_msgs::PointCloud2 ToMessage(const LidarScan& scan, const std::string& frame_id) {
  using sensor_msgs::PointField;
  sensor_msgs::PointCloud2 cloud;
  cloud.header = Header(scan.stamp, frame_id);
  cloud.height = 1;
  cloud.width = static_cast<uint32_t>(scan.points.size());
  cloud.fields = {Field("x", 0, PointField::FLOAT32), Field("y", 4, PointField::FLOAT32),
                  Field("z", 8, PointField::FLOAT32), Field("intensity", 12, PointField::FLOAT32)};
  if (scan.has_point_times) cloud.fields.push_back(Field("t", 16, PointField::UINT32));
  if (scan.has_ring) cloud.fields.push_back(Field("ring", 20, PointField::UINT16));
  cloud.is_bigendian = false;
  cloud.point_step = 22;
  cloud.row_step = cloud.point_step * cloud.width;
  cloud.is_dense = true;
  cloud.data.resize(static_cast<std::size_t>(cloud.row_step));
  std::uint8_t* out = cloud.data.data();
  for (const LidarPoint& p : scan.points) {
    const float xyzi[4] = {p.x, p.y, p.z, p.intensity};
    const auto t = static_cast<uint32_t>(std::max(p.offset_ns, 0));
    std::memcpy(out, xyzi, sizeof(xyzi));
    std::memcpy(out + 16, &t, sizeof(t));
    std::memcpy(out + 20, &p.ring, sizeof(p.ring));
    out += cloud.point_step;
  }
  return cloud;
}

nav_msgs::Odometry ToMessage(const WheelSample& sample, const std::string& frame_id) {
  nav_msgs::Odometry odometry;
  odometry.header = Header(sample.stamp, "odom");
  odometry.child_frame_id = frame_id;
  odometry.pose.pose.orientation.w = 1.0;
  odometry.twist.twist.linear = ToVector3(sample.linear_velocity);
  odometry.twist.twist.angular = ToVector3(sample.angular_velocity);
  return odometry;
}

sensor_msgs::NavSatFix ToMessage(const GnssFix& fix, const std::string& frame_id) {
  sensor_msgs::NavSatFix message;
  message.header = Header(fix.stamp, frame_id);
  using sensor_msgs::NavSatStatus;
  switch (fix.status) {
    case GnssFixStatus::kNoFix:
      message.status.status = NavSatStatus::STATUS_NO_FIX;
      break;
    case GnssFixStatus::kFix:
      message.status.status = NavSatStatus::STATUS_FIX;
      break;
    case GnssFixStatus::kSbas:
      message.status.status = NavSatStatus::STATUS_SBAS_FIX;
      break;
    case GnssFixStatus::kRtkFloat:
    case GnssFixStatus::kRtkFixed:
      message.status.status = NavSatStatus::STATUS_GBAS_FIX;
      break;
  }
  message.status.service = NavSatStatus::SERVICE_GPS;
  message.latitude = fix.latitude_deg;
  message.longitude = fix.longitude_deg;
  message.altitude = fix.altitude_m;
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) message.position_covariance[3 * r + c] = fix.covariance_enu(r, c);
  message.position_covariance_type = sensor_msgs::NavSatFix::COVARIANCE_TYPE_KNOWN;
  return message;
}

Expected<sensor_msgs::CompressedImage> ToMessage(const CameraFrame& frame, const std::string& frame_id) {
  sensor_msgs::CompressedImage image;
  image.header = Header(frame.stamp, frame_id);
  if (frame.encoded.format == "png" || frame.encoded.format == "jpeg") {
    image.format = frame.encoded.format;
    image.data = frame.encoded.bytes;
    return image;
  }
  auto png = EncodePng(frame.image, "camera frame at " + FormatSeconds(frame.stamp));
  if (!png) return png.status();
  image.format = "png";
  image.data = std::move(*png);
  return image;
}

}  // namespace

RosBagWriter::RosBagWriter(std::unique_ptr<State> state) : state_(std::move(state)) {}
RosBagWriter::RosBagWriter(RosBagWriter&&) noexcept = default;
RosBagWriter& RosBagWriter::operator=(RosBagWriter&&) noexcept = default;

RosBagWriter::~RosBagWriter() {
  if (!state_ || state_->finished) return;
  try {
    state_->bag.close();
  } catch (const std::exception&) {
  }
  std::error_code ignored;
  fs::remove(state_->temporary, ignored);
}

Expected<RosBagWriter> RosBagWriter::Create(const fs::path& path, std::vector<BagTopic> topics) {
  auto state = std::make_unique<State>();
  state->path = path;
  state->temporary = fs::path(path.string() + ".part");
  state->topics = std::move(topics);
  try {
    state->bag.open(state->temporary.string(), rosbag::bagmode::Write);
    state->bag.setCompression(rosbag::compression::LZ4);
  } catch (const std::exception& e) {
    return Status::Error(path.string() + ": cannot create the bag: " + e.what());
  }
  return RosBagWriter(std::move(state));
}

Status RosBagWriter::Write(int topic, const MeasurementData& data) {
  State& s = *state_;
  if (s.finished) return Status::Error(s.path.string() + ": write after Finish()");
  if (topic < 0 || topic >= static_cast<int>(s.topics.size()) || s.topics[topic].kind != KindOf(data))
    return Status::Error(s.path.string() + ": measurement does not match topic " + std::to_string(topic));
  const BagTopic& t = s.topics[topic];
  const Stamp stamp = StampOf(data);
  if (stamp < 0)
    return Status::Error(s.path.string() + ": " + t.topic + ": stamp " + FormatSeconds(stamp) +
                         " is before 1970 (ROS time is unsigned)");
  try {
    const ros::Time time = ToRosTime(stamp);
    if (const auto* imu = std::get_if<ImuSample>(&data))
      s.bag.write(t.topic, time, ToMessage(*imu, t.frame_id));
    if (const auto* scan = std::get_if<LidarScan>(&data))
      s.bag.write(t.topic, time, ToMessage(*scan, t.frame_id));
    if (const auto* wheel = std::get_if<WheelSample>(&data))
      s.bag.write(t.topic, time, ToMessage(*wheel, t.frame_id));
    if (const auto* fix = std::get_if<GnssFix>(&data))
      s.bag.write(t.topic, time, ToMessage(*fix, t.frame_id));
    if (const auto* frame = std::get_if<CameraFrame>(&data)) {
      auto image = ToMessage(*frame, t.frame_id);
      if (!image) return image.status();
      s.bag.write(t.topic, time, *image);
    }
  } catch (const std::exception& e) {
    return Status::Error(s.path.string() + ": " + t.topic + ": " + e.what());
  }
  return {};
}

Status RosBagWriter::Finish() {
  State& s = *state_;
  try {
    s.bag.close();
  } catch (const std::exception& e) {
    return Status::Error(s.path.string() + ": closing the bag failed: " + e.what());
  }
  std::error_code error;
  fs::rename(s.temporary, s.path, error);
  if (error) return Status::Error(s.path.string() + ": " + error.message());
  s.finished = true;
  return {};
}

}  // namespace uf
