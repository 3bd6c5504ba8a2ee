#include "odometry/io/rosbag/bag_message_decode.h"

#include <utility>

#include "odometry/io/rosbag/livox_custom_decode.h"
#include "odometry/io/rosbag/ros_message_convert.h"

namespace uf::bag {
namespace {

// Header stamp, or the record time when the header has none (stamp 0).
Stamp StampOrRecordTime(const RosHeader& header, Stamp record_time, DecodedMessage& decoded) {
  decoded.header_stamp_zero = header.stamp == 0;
  return decoded.header_stamp_zero ? record_time : header.stamp;
}

template <typename T>
Expected<DecodedMessage> Finish(Expected<T> converted, const RosHeader& header, Stamp record_time,
                                std::string_view frame_id) {
  if (!converted.ok()) return converted.status();
  DecodedMessage decoded;
  T measurement = std::move(converted).value();
  measurement.stamp = StampOrRecordTime(header, record_time, decoded);
  decoded.frame_id = std::string(frame_id);
  decoded.data = std::move(measurement);
  return decoded;
}

Expected<DecodedMessage> FinishLidar(Expected<DecodedLidarScan> scan, std::string frame_id, bool stamp_zero) {
  if (!scan.ok()) return scan.status();
  DecodedMessage decoded;
  decoded.header_stamp_zero = stamp_zero;
  decoded.frame_id = std::move(frame_id);
  decoded.point_time = scan->point_time;
  decoded.point_time_field = std::move(scan->point_time_field);
  decoded.non_finite_points = scan->non_finite_points;
  decoded.point_times_dropped = std::move(scan->point_times_dropped);
  decoded.data = std::move(scan->scan);
  return decoded;
}

}  // namespace

Expected<DecodedMessage> DecodeBagMessage(MessageType type, std::span<const std::uint8_t> message,
                                          Stamp record_time, const LidarDecodeOptions& lidar_options) {
  RosHeader header;
  switch (type) {
    case MessageType::kImu: {
      Expected<ImuSample> sample = ConvertImu(message, &header);
      return Finish(std::move(sample), header, record_time, header.frame_id);
    }
    case MessageType::kImage: {
      Expected<CameraFrame> frame = ConvertImage(message, &header);
      return Finish(std::move(frame), header, record_time, header.frame_id);
    }
    case MessageType::kCompressedImage: {
      Expected<CameraFrame> frame = ConvertCompressedImage(message, &header);
      return Finish(std::move(frame), header, record_time, header.frame_id);
    }
    case MessageType::kNavSatFix: {
      Expected<GnssFix> fix = ConvertNavSatFix(message, &header);
      return Finish(std::move(fix), header, record_time, header.frame_id);
    }
    case MessageType::kOdometry: {
      std::string_view child_frame;
      Expected<WheelSample> sample = ConvertOdometry(message, &header, &child_frame);
      return Finish(std::move(sample), header, record_time,
                    child_frame.empty() ? header.frame_id : child_frame);
    }
    case MessageType::kTwistStamped: {
      Expected<WheelSample> sample = ConvertTwistStamped(message, &header);
      return Finish(std::move(sample), header, record_time, header.frame_id);
    }
    case MessageType::kPointCloud2: {
      const Expected<PointCloud2Message> cloud = ParsePointCloud2(message);
      if (!cloud.ok()) return cloud.status();
      const bool stamp_zero = cloud->header.stamp == 0;
      const Stamp base = stamp_zero ? record_time : cloud->header.stamp;
      return FinishLidar(DecodePointCloud2(base, cloud->layout, cloud->data, lidar_options),
                         std::string(cloud->header.frame_id), stamp_zero);
    }
    case MessageType::kLivoxCustom: {
      std::string frame_id;
      bool stamp_zero = false;
      Expected<DecodedLidarScan> scan =
          DecodeLivoxCustomMsg(message, record_time, lidar_options.sweep_period_s, &frame_id, &stamp_zero);
      return FinishLidar(std::move(scan), std::move(frame_id), stamp_zero);
    }
  }
  return Status::Error("unhandled message type");
}

}  // namespace uf::bag
