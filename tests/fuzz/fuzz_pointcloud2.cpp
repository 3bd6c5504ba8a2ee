// Fuzz target of the LiDAR message decoders alone: the first byte picks the decoder and its options, the
// rest is a serialized sensor_msgs/PointCloud2 (or livox CustomMsg). Any bytes give a scan or an error;
// never a crash or an out-of-bounds access, and a scan keeps its timing invariants.
#include <cstdint>
#include <span>

#include "odometry/io/rosbag/livox_custom_decode.h"
#include "odometry/io/rosbag/pointcloud2_decode.h"
#include "odometry/io/rosbag/ros_message_convert.h"

namespace {

void CheckScan(const uf::Expected<uf::DecodedLidarScan>& decoded) {
  if (!decoded.ok()) return;
  const uf::LidarScan& scan = decoded->scan;
  if (scan.end < scan.stamp) __builtin_trap();
  if (!scan.has_point_times) return;
  for (const uf::LidarPoint& point : scan.points) {
    if (point.offset_ns < 0 || scan.stamp + point.offset_ns > scan.end) __builtin_trap();
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size < 1) return 0;
  const std::uint8_t selector = data[0];
  const std::span<const std::uint8_t> message(data + 1, size - 1);
  uf::LidarDecodeOptions options;
  options.derive_point_times_from_azimuth = (selector & 1) != 0;
  options.sweep_period_s = (selector & 2) != 0 ? 0.1 : 0.05;
  const uf::Stamp fallback = 1'600'000'000'000'000'000;
  if ((selector & 4) != 0) {
    CheckScan(uf::DecodeLivoxCustomMsg(message, fallback, options.sweep_period_s));
    return 0;
  }
  const auto cloud = uf::bag::ParsePointCloud2(message);
  if (!cloud.ok()) return 0;
  const uf::Stamp base = cloud->header.stamp != 0 ? cloud->header.stamp : fallback;
  CheckScan(uf::DecodePointCloud2(base, cloud->layout, cloud->data, options));
  return 0;
}
