#include "odometry/io/rosbag/pointcloud2_decode.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <initializer_list>
#include <limits>
#include <string_view>

#include "odometry/io/rosbag/lidar_point_times.h"

namespace uf {
namespace {

template <typename T>
T LoadField(const std::uint8_t* bytes, bool swap) {
  T value;
  if (!swap) {
    std::memcpy(&value, bytes, sizeof(T));
  } else {
    std::uint8_t reversed[sizeof(T)];
    for (std::size_t i = 0; i < sizeof(T); ++i) reversed[i] = bytes[sizeof(T) - 1 - i];
    std::memcpy(&value, reversed, sizeof(T));
  }
  return value;
}

// One field of the point, read as a number whatever its datatype.
struct FieldReader {
  std::uint32_t offset = 0;
  std::uint8_t datatype = 0;
  bool swap = false;

  double Read(const std::uint8_t* point) const {
    const std::uint8_t* bytes = point + offset;
    switch (datatype) {
      case 1:
        return LoadField<std::int8_t>(bytes, swap);
      case 2:
        return LoadField<std::uint8_t>(bytes, swap);
      case 3:
        return LoadField<std::int16_t>(bytes, swap);
      case 4:
        return LoadField<std::uint16_t>(bytes, swap);
      case 5:
        return LoadField<std::int32_t>(bytes, swap);
      case 6:
        return LoadField<std::uint32_t>(bytes, swap);
      case 7:
        return LoadField<float>(bytes, swap);
      case 8:
        return LoadField<double>(bytes, swap);
      default:
        return 0;
    }
  }
  bool IsFloat32() const { return datatype == 7 && !swap; }
};

const PointFieldLayout* FindField(const PointCloud2Layout& layout,
                                  std::initializer_list<std::string_view> names) {
  for (std::string_view name : names) {
    for (const PointFieldLayout& field : layout.fields) {
      if (field.name == name) return &field;
    }
  }
  return nullptr;
}

FieldReader ReaderFor(const PointFieldLayout& field, bool swap) {
  return {field.offset, field.datatype, swap};
}

bool IsFloatType(std::uint8_t datatype) { return datatype == 7 || datatype == 8; }

// The time field, if any, by name and type (see the header); the convention is settled from the values.
const PointFieldLayout* FindTimeField(const PointCloud2Layout& layout) {
  for (const PointFieldLayout& field : layout.fields) {
    const bool is_float = IsFloatType(field.datatype);
    if ((field.name == "time" || field.name == "timestamp") && is_float) return &field;
    if ((field.name == "t" || field.name == "offset_time") && !is_float) return &field;
  }
  return nullptr;
}

// Magnitude decides between relative and absolute times: no scan is 1e6 s long, and no absolute time in
// seconds since 1970 exceeds 1e12 (year 33658).
PointTimeConvention ConventionOf(const PointFieldLayout& field, double first_value) {
  if (!IsFloatType(field.datatype)) return PointTimeConvention::kRelativeNanoseconds;
  const double magnitude = std::fabs(first_value);
  if (magnitude > 1e12) return PointTimeConvention::kAbsoluteNanoseconds;
  if (magnitude > 1e6) return PointTimeConvention::kAbsoluteSeconds;
  return PointTimeConvention::kRelativeSeconds;
}

// std::llround, inlined (it runs per point); |x| < 2^62. From 2^52 up every double is an integer already,
// and below it x +- 0.5 is exact, so truncating that rounds halves away from zero.
std::int64_t RoundToInt64(double x) {
  constexpr double kAllIntegers = 4503599627370496.0;  // 2^52
  if (x >= kAllIntegers || x <= -kAllIntegers) return static_cast<std::int64_t>(x);
  return static_cast<std::int64_t>(x >= 0 ? x + 0.5 : x - 0.5);
}

// A point time in ns after `base`, or false when the value cannot be one. Times are kept within +-4e18 ns
// of base so that differences of two of them, and base plus one, stay inside int64.
bool TimeFromBase(PointTimeConvention convention, double value, Stamp base, std::int64_t* time) {
  constexpr double kLimit = 4e18;
  const double base_ns = static_cast<double>(base);
  switch (convention) {
    case PointTimeConvention::kRelativeSeconds:
      if (!(std::fabs(value * 1e9) < kLimit)) return false;
      *time = RoundToInt64(value * 1e9);
      return true;
    case PointTimeConvention::kRelativeNanoseconds:
      *time = static_cast<std::int64_t>(value);  // an integer field of at most 32 bits
      return true;
    case PointTimeConvention::kAbsoluteSeconds: {
      if (!(std::fabs(value) < 4e9) || !(std::fabs(value * 1e9 - base_ns) < kLimit)) return false;
      const double whole = std::floor(value);  // split, so the fraction keeps its precision
      *time = static_cast<std::int64_t>(whole) * kNanosecondsPerSecond + RoundToInt64((value - whole) * 1e9) -
              base;
      return true;
    }
    case PointTimeConvention::kAbsoluteNanoseconds:
      if (!(std::fabs(value) < kLimit) || !(std::fabs(value - base_ns) < kLimit)) return false;
      *time = RoundToInt64(value) - base;
      return true;
    default:
      return false;
  }
}

// double -> float without undefined behaviour for values beyond the float range (they become infinite).
float NarrowToFloat(double value) {
  if (std::fabs(value) > std::numeric_limits<float>::max()) return value > 0 ? HUGE_VALF : -HUGE_VALF;
  return static_cast<float>(value);  // also NaN and infinities
}

std::uint16_t ToRing(double value) {
  if (!(value >= 0)) return 0;  // negative or NaN
  return static_cast<std::uint16_t>(std::min(value, 65535.0));
}

std::string FieldList(const PointCloud2Layout& layout) {
  std::string names;
  for (const PointFieldLayout& field : layout.fields) names += (names.empty() ? "" : ", ") + field.name;
  return names;
}

// Checks everything the decoding loop relies on; on success sets *row_step to the stride of rows in `data`.
Status CheckLayout(const PointCloud2Layout& layout, std::size_t data_size, std::uint64_t* row_step) {
  for (const PointFieldLayout& field : layout.fields) {
    const std::uint32_t size = PointFieldSize(field.datatype);
    if (size == 0) {
      return Status::Error("PointCloud2 field has an unknown datatype, expected 1..8 (field '" + field.name +
                           "' datatype " + std::to_string(field.datatype) + ")");
    }
    const std::uint64_t end =
        std::uint64_t{field.offset} + std::uint64_t{size} * std::max<std::uint32_t>(field.count, 1);
    if (end > layout.point_step) {
      return Status::Error("PointCloud2 field extends past point_step (field '" + field.name +
                           "' ends at byte " + std::to_string(end) + ", point_step " +
                           std::to_string(layout.point_step) + ")");
    }
  }
  if (!FindField(layout, {"x"}) || !FindField(layout, {"y"}) || !FindField(layout, {"z"})) {
    return Status::Error("PointCloud2 lacks an x, y or z field (fields: " + FieldList(layout) + ")");
  }
  if (layout.point_step == 0) {
    return Status::Error("PointCloud2 point_step is 0 (width " + std::to_string(layout.width) + ")");
  }
  const std::uint64_t row_bytes = std::uint64_t{layout.width} * layout.point_step;
  const std::uint64_t by_row_step = std::uint64_t{layout.row_step} * layout.height;
  if (layout.row_step >= row_bytes && by_row_step == data_size) {
    *row_step = layout.row_step;
    return Status();
  }
  // Some writers leave row_step wrong on dense clouds: accept data that is exactly width*height*point_step.
  if (layout.height <= data_size / std::max<std::uint64_t>(row_bytes, 1) &&
      row_bytes * layout.height == data_size) {
    *row_step = row_bytes;
    return Status();
  }
  return Status::Error(
      "PointCloud2 data size disagrees with row_step*height and width*height*point_step (data " +
      std::to_string(data_size) + " bytes, row_step*height " + std::to_string(by_row_step) + ", width " +
      std::to_string(layout.width) + " height " + std::to_string(layout.height) + " point_step " +
      std::to_string(layout.point_step) + ")");
}

}  // namespace

std::uint32_t PointFieldSize(std::uint8_t datatype) {
  static constexpr std::uint32_t kSizes[] = {0, 1, 1, 2, 2, 4, 4, 4, 8};
  return datatype < 9 ? kSizes[datatype] : 0;
}

Expected<DecodedLidarScan> DecodePointCloud2(Stamp base, const PointCloud2Layout& layout,
                                             std::span<const std::uint8_t> data,
                                             const LidarDecodeOptions& options) {
  DecodedLidarScan decoded;
  LidarScan& scan = decoded.scan;
  if (std::uint64_t{layout.width} * layout.height == 0) {
    AssignNoPointTimes(base, options.sweep_period_s, scan);
    return decoded;
  }
  std::uint64_t row_step = 0;
  if (Status checked = CheckLayout(layout, data.size(), &row_step); !checked.ok()) return checked;

  const bool swap = layout.is_bigendian;
  const FieldReader x = ReaderFor(*FindField(layout, {"x"}), swap);
  const FieldReader y = ReaderFor(*FindField(layout, {"y"}), swap);
  const FieldReader z = ReaderFor(*FindField(layout, {"z"}), swap);
  const bool xyz_float32 = x.IsFloat32() && y.IsFloat32() && z.IsFloat32();
  const PointFieldLayout* intensity_field = FindField(layout, {"intensity", "reflectivity", "i"});
  const PointFieldLayout* ring_field = FindField(layout, {"ring", "line"});
  const PointFieldLayout* time_field = FindTimeField(layout);
  const FieldReader intensity = intensity_field ? ReaderFor(*intensity_field, swap) : FieldReader{};
  const FieldReader ring = ring_field ? ReaderFor(*ring_field, swap) : FieldReader{};
  const FieldReader time = time_field ? ReaderFor(*time_field, swap) : FieldReader{};
  scan.has_ring = ring_field != nullptr;

  const std::size_t count =
      static_cast<std::size_t>(layout.width) * layout.height;  // <= data.size(): checked
  scan.points.reserve(count);
  std::vector<std::int64_t> times;  // ns after base, one per kept point
  if (time_field) times.reserve(count);
  PointTimeConvention convention = PointTimeConvention::kNone;
  bool times_in_range = true;

  // Azimuth-derived times need a guess of each point's time from its position (see AssignAzimuthPointTimes):
  // its fraction of the cloud, or of its row when the cloud is organised (one sweep per row).
  const bool guess_azimuth_turns = !time_field && options.derive_point_times_from_azimuth;
  const double period_ns = static_cast<double>(SweepPeriodNs(options.sweep_period_s));
  const double guess_per_column = period_ns / (layout.height > 1 ? layout.width : static_cast<double>(count));
  for (std::uint32_t row = 0; row < layout.height; ++row) {
    const std::uint8_t* point = data.data() + row * row_step;
    for (std::uint32_t col = 0; col < layout.width; ++col, point += layout.point_step) {
      LidarPoint out;
      if (xyz_float32) {
        std::memcpy(&out.x, point + x.offset, 4);
        std::memcpy(&out.y, point + y.offset, 4);
        std::memcpy(&out.z, point + z.offset, 4);
      } else {
        out.x = NarrowToFloat(x.Read(point));
        out.y = NarrowToFloat(y.Read(point));
        out.z = NarrowToFloat(z.Read(point));
      }
      if (!std::isfinite(out.x) || !std::isfinite(out.y) || !std::isfinite(out.z)) {
        ++decoded.non_finite_points;
        continue;
      }
      if (time_field) {
        const double value = time.Read(point);
        if (!std::isfinite(value)) {
          ++decoded.non_finite_points;
          continue;
        }
        if (convention == PointTimeConvention::kNone) convention = ConventionOf(*time_field, value);
        std::int64_t from_base = 0;
        times_in_range = times_in_range && TimeFromBase(convention, value, base, &from_base);
        times.push_back(from_base);
      }
      if (intensity_field) out.intensity = NarrowToFloat(intensity.Read(point));
      if (ring_field) out.ring = ToRing(ring.Read(point));
      if (guess_azimuth_turns) out.offset_ns = static_cast<std::int32_t>(col * guess_per_column);
      scan.points.push_back(out);
    }
  }

  if (time_field && times_in_range) {
    decoded.point_time = convention == PointTimeConvention::kNone ? ConventionOf(*time_field, 0) : convention;
    decoded.point_time_field = time_field->name;
    decoded.point_times_dropped = AssignPointTimes(base, times, options.sweep_period_s, scan);
  } else if (time_field) {
    decoded.point_times_dropped = "point time values out of range (times dropped)";
    AssignNoPointTimes(base, options.sweep_period_s, scan);
  } else if (options.derive_point_times_from_azimuth) {
    decoded.point_time = PointTimeConvention::kAzimuth;
    AssignAzimuthPointTimes(base, options.sweep_period_s, options.azimuth_convention, scan);
  } else {
    AssignNoPointTimes(base, options.sweep_period_s, scan);
  }
  return decoded;
}

}  // namespace uf
