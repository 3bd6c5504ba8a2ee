// sensor_msgs/PointCloud2 point data -> LidarScan, with no ROS types, so it can be tested and fuzzed alone.
//
// A cloud is height rows of width points; point (row, col) starts at byte row * row_step + col * point_step
// of `data`, and each field sits at its offset inside the point with its datatype (1 int8, 2 uint8, 3 int16,
// 4 uint16, 5 int32, 6 uint32, 7 float32, 8 float64) in the byte order is_bigendian says. Fields read:
//   x, y, z (required, any numeric type), intensity (or reflectivity), ring (or line), and the per-point
//   time,
// recognised by name and type:
//   `time`  float32/64 s after the header stamp (Velodyne)                 -> kRelativeSeconds
//   `t`     uint32 ns after the header stamp (Ouster)                      -> kRelativeNanoseconds
//   `timestamp` float64 absolute s (Hesai, Robosense)                      -> kAbsoluteSeconds
//   `timestamp` float64 absolute ns, values > 1e12 (Livox ROS driver 2)   -> kAbsoluteNanoseconds
// (a `time` or `timestamp` whose values are > 1e6 is taken as absolute: seconds, or ns above 1e12).
#pragma once

#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "odometry/io/dataset_reader.h"
#include "odometry/types/measurements.h"
#include "odometry/types/status.h"

namespace uf {

struct PointFieldLayout {
  std::string name;
  std::uint32_t offset = 0;   // bytes from the start of the point
  std::uint8_t datatype = 0;  // 1..8, see above
  std::uint32_t count = 1;    // elements; only the first is read
};

struct PointCloud2Layout {
  std::uint32_t height = 0;
  std::uint32_t width = 0;
  bool is_bigendian = false;
  std::uint32_t point_step = 0;  // bytes per point
  std::uint32_t row_step = 0;    // bytes per row
  std::vector<PointFieldLayout> fields;
};

struct LidarDecodeOptions {
  bool derive_point_times_from_azimuth = true;  // when the cloud has no time field (see lidar_point_times.h)
  AzimuthConvention azimuth_convention = kClockwiseFromFirstPoint;  // how they are derived
  double sweep_period_s = 0.1;
};

struct DecodedLidarScan {
  LidarScan scan;
  PointTimeConvention point_time = PointTimeConvention::kNone;
  std::string point_time_field;        // "time", "t", "timestamp", "offset_time"; empty when none
  std::int64_t non_finite_points = 0;  // points dropped for a NaN or infinite coordinate or time
  std::string point_times_dropped;     // non-empty: why the point times were not kept
};

// The bytes of a field's datatype, 0 for a datatype outside 1..8.
std::uint32_t PointFieldSize(std::uint8_t datatype);

// Decodes the cloud; `base` is the header stamp. An error means the message must be skipped; its text is a
// fixed description of what was expected, followed by this message's values in parentheses.
Expected<DecodedLidarScan> DecodePointCloud2(Stamp base, const PointCloud2Layout& layout,
                                             std::span<const std::uint8_t> data,
                                             const LidarDecodeOptions& options);

}  // namespace uf
