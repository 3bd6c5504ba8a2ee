// livox_ros_driver/CustomMsg (and livox_ros_driver2/CustomMsg, the same layout) from its serialized bytes:
//   std_msgs/Header header
//   uint64 timebase        ns, time of the first point
//   uint32 point_num
//   uint8  lidar_id
//   uint8[3] rsvd
//   CustomPoint[] points   uint32 count, then 19 bytes each:
//     uint32 offset_time   ns after timebase
//     float32 x, y, z      m
//     uint8 reflectivity, tag, line
// Point times are timebase + offset_time (kLivoxOffsetNanoseconds); reflectivity -> intensity, line -> ring.
// Every point is kept, tag included (Livox flags noise in `tag`; filtering is the front end's choice).
#pragma once

#include <cstdint>
#include <span>

#include "odometry/io/rosbag/pointcloud2_decode.h"
#include "odometry/types/status.h"

namespace uf {

// `fallback_stamp` replaces a zero header stamp. An error means the bytes do not hold a CustomMsg.
Expected<DecodedLidarScan> DecodeLivoxCustomMsg(std::span<const std::uint8_t> message, Stamp fallback_stamp,
                                                double sweep_period_s, std::string* frame_id = nullptr,
                                                bool* header_stamp_zero = nullptr);

}  // namespace uf
