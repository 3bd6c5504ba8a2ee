#include "odometry/io/rosbag/livox_custom_decode.h"

#include <cmath>
#include <cstdlib>
#include <cstring>
#include <vector>

#include "odometry/io/rosbag/lidar_point_times.h"
#include "odometry/io/rosbag/ros_cursor.h"

namespace uf {

Expected<DecodedLidarScan> DecodeLivoxCustomMsg(std::span<const std::uint8_t> message, Stamp fallback_stamp,
                                                double sweep_period_s, std::string* frame_id,
                                                bool* header_stamp_zero) {
  constexpr std::size_t kPointBytes = 19;
  bag::RosCursor cursor(message);
  const bag::RosHeader header = bag::ReadRosHeader(cursor);
  const std::uint64_t timebase = cursor.Read<std::uint64_t>();
  cursor.Read<std::uint32_t>();  // point_num: the array's own count is what bounds the data
  cursor.Skip(4);                // lidar_id, rsvd[3]
  std::uint32_t count = 0;
  const std::span<const std::uint8_t> points = cursor.TakeArray(kPointBytes, &count);
  if (!cursor.ok()) {
    return Status::Error("message is too short for a livox CustomMsg (" + std::to_string(message.size()) +
                         " bytes, " + std::to_string(count) + " points announced)");
  }
  if (frame_id != nullptr) *frame_id = std::string(header.frame_id);
  if (header_stamp_zero != nullptr) *header_stamp_zero = header.stamp == 0;
  const Stamp base = header.stamp != 0 ? header.stamp : fallback_stamp;
  // Point times relative to base; a timebase beyond +-4e18 ns of it is damage (see AssignPointTimes).
  const bool timebase_usable = timebase < (std::uint64_t{1} << 62) &&
                               std::abs(static_cast<std::int64_t>(timebase) - base) < (std::int64_t{1} << 61);

  DecodedLidarScan decoded;
  LidarScan& scan = decoded.scan;
  scan.has_ring = true;
  scan.points.reserve(count);
  std::vector<std::int64_t> times;
  times.reserve(count);
  for (std::size_t i = 0; i < count; ++i) {
    const std::uint8_t* bytes = points.data() + i * kPointBytes;
    LidarPoint point;
    const std::uint32_t offset_time = bag::LoadLittleEndian<std::uint32_t>(bytes);
    std::memcpy(&point.x, bytes + 4, 4);
    std::memcpy(&point.y, bytes + 8, 4);
    std::memcpy(&point.z, bytes + 12, 4);
    if (!std::isfinite(point.x) || !std::isfinite(point.y) || !std::isfinite(point.z)) {
      ++decoded.non_finite_points;
      continue;
    }
    point.intensity = bytes[16];
    point.ring = bytes[18];  // line: the laser that measured the point
    scan.points.push_back(point);
    if (timebase_usable) times.push_back(static_cast<std::int64_t>(timebase) - base + offset_time);
  }
  if (!timebase_usable) {
    decoded.point_times_dropped = "livox timebase far from the header stamp (times dropped)";
    AssignNoPointTimes(base, sweep_period_s, scan);
    return decoded;
  }
  decoded.point_time = PointTimeConvention::kLivoxOffsetNanoseconds;
  decoded.point_time_field = "offset_time";
  decoded.point_times_dropped = AssignPointTimes(base, times, sweep_period_s, scan);
  return decoded;
}

}  // namespace uf
