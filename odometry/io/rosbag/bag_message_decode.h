// One bag message of a known type -> its measurement, with what the reader reports beside it.
#pragma once

#include <cstdint>
#include <span>
#include <string>

#include "odometry/io/measurement.h"
#include "odometry/io/rosbag/bag_streams.h"
#include "odometry/io/rosbag/pointcloud2_decode.h"
#include "odometry/types/status.h"

namespace uf::bag {

struct DecodedMessage {
  MeasurementData data;
  std::string frame_id;            // the frame the measurement is expressed in (Odometry: child_frame_id)
  bool header_stamp_zero = false;  // the stamp is the record time, the header had none
  // LiDAR only:
  PointTimeConvention point_time = PointTimeConvention::kNone;
  std::string point_time_field;
  std::int64_t non_finite_points = 0;
  std::string point_times_dropped;
};

// An error means this message cannot be read (too short, inconsistent PointCloud2); the text is a fixed
// description, then this message's values in parentheses.
Expected<DecodedMessage> DecodeBagMessage(MessageType type, std::span<const std::uint8_t> message,
                                          Stamp record_time, const LidarDecodeOptions& lidar_options);

}  // namespace uf::bag
