#include "odometry/io/folders/pcd_decode.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <optional>

namespace uf {
namespace {

bool IsInteger(const PcdField& field) { return field.type == 'I' || field.type == 'U'; }

template <typename T>
T Load(const char* p) {
  T value;
  std::memcpy(&value, p, sizeof(T));
  return value;
}

double AsDouble(const char* p, const PcdField& field) {
  switch (field.type) {
    case 'F':
      return field.size == 4 ? Load<float>(p) : Load<double>(p);
    case 'U':
      switch (field.size) {
        case 1:
          return Load<std::uint8_t>(p);
        case 2:
          return Load<std::uint16_t>(p);
        case 4:
          return Load<std::uint32_t>(p);
        default:
          return static_cast<double>(Load<std::uint64_t>(p));
      }
    default:
      switch (field.size) {
        case 1:
          return Load<std::int8_t>(p);
        case 2:
          return Load<std::int16_t>(p);
        case 4:
          return Load<std::int32_t>(p);
        default:
          return static_cast<double>(Load<std::int64_t>(p));
      }
  }
}

// Integer fields exactly; nullopt for a uint64 beyond the int64 range.
std::optional<std::int64_t> AsInt64(const char* p, const PcdField& field) {
  if (field.type == 'U' && field.size == 8) {
    const std::uint64_t value = Load<std::uint64_t>(p);
    if (value > static_cast<std::uint64_t>(std::numeric_limits<std::int64_t>::max())) return std::nullopt;
    return static_cast<std::int64_t>(value);
  }
  if (field.type == 'I' && field.size == 8) return Load<std::int64_t>(p);
  return static_cast<std::int64_t>(AsDouble(p, field));
}

struct TimeField {
  const PcdField* field = nullptr;
  int index = 0;
  PointTimeConvention convention = PointTimeConvention::kNone;
};

// The per-point time field, by the names and types the ROS bag reader recognises.
TimeField FindTimeField(const PcdHeader& header) {
  TimeField found;
  for (std::size_t i = 0; i < header.fields.size(); ++i) {
    const PcdField& field = header.fields[i];
    PointTimeConvention convention = PointTimeConvention::kNone;
    if (field.name == "time" && field.type == 'F') convention = PointTimeConvention::kRelativeSeconds;
    if (field.name == "t" && IsInteger(field)) convention = PointTimeConvention::kRelativeNanoseconds;
    if (field.name == "timestamp")
      convention = IsInteger(field) ? PointTimeConvention::kAbsoluteNanoseconds
                                    : PointTimeConvention::kAbsoluteSeconds;
    if (convention == PointTimeConvention::kNone) continue;
    if (found.field == nullptr || convention < found.convention)
      found = {&field, static_cast<int>(i), convention};
  }
  return found;
}

int IndexOf(const PcdHeader& header, std::initializer_list<const char*> names, bool integer_only) {
  for (const char* name : names)
    for (std::size_t i = 0; i < header.fields.size(); ++i)
      if (header.fields[i].name == name && (!integer_only || IsInteger(header.fields[i])))
        return static_cast<int>(i);
  return -1;
}

// Seconds (relative or absolute) or nanoseconds as a double -> integer nanoseconds; nullopt when out of
// range.
std::optional<Stamp> ToNanoseconds(double value, bool seconds) {
  const long double ns = seconds ? static_cast<long double>(value) * 1e9L : static_cast<long double>(value);
  if (!(std::fabs(ns) < 9.2e18L)) return std::nullopt;
  return static_cast<Stamp>(std::llround(ns));
}

}  // namespace

PcdLayout PcdLayout::PointMajor(const PcdHeader& header) {
  PcdLayout layout;
  for (const PcdField& field : header.fields) {
    layout.base.push_back(field.offset);
    layout.stride.push_back(header.point_step);
  }
  return layout;
}

PcdLayout PcdLayout::FieldMajor(const PcdHeader& header) {
  PcdLayout layout;
  for (const PcdField& field : header.fields) {
    layout.base.push_back(header.points * field.offset);  // the fields before it take offset bytes per point
    layout.stride.push_back(static_cast<std::uint64_t>(field.size) * field.count);
  }
  return layout;
}

Expected<LidarScan> DecodePcdPoints(const PcdHeader& header, const PcdLayout& layout, std::string_view body,
                                    const std::string& path, PointCloudFileInfo* info) {
  const int x = IndexOf(header, {"x"}, false), y = IndexOf(header, {"y"}, false),
            z = IndexOf(header, {"z"}, false);
  const int intensity = IndexOf(header, {"intensity", "i"}, false);
  const int ring = IndexOf(header, {"ring"}, true);
  TimeField time = FindTimeField(header);
  auto at = [&](int f, std::uint64_t point) {
    return body.data() + layout.base[f] + point * layout.stride[f];
  };

  // Absolute float timestamps are nanoseconds when their size says so (Livox), else seconds (Hesai).
  if (time.convention == PointTimeConvention::kAbsoluteSeconds && header.points > 0) {
    const double first = AsDouble(at(time.index, 0), *time.field);
    if (std::isfinite(first) && std::fabs(first) > 1e11)
      time.convention = PointTimeConvention::kAbsoluteNanoseconds;
  }
  const bool seconds = time.convention == PointTimeConvention::kRelativeSeconds ||
                       time.convention == PointTimeConvention::kAbsoluteSeconds;

  LidarScan scan;
  scan.points.reserve(header.points);
  std::vector<Stamp> times;
  std::int64_t dropped = 0;
  for (std::uint64_t i = 0; i < header.points; ++i) {
    const double px = AsDouble(at(x, i), header.fields[x]);
    const double py = AsDouble(at(y, i), header.fields[y]);
    const double pz = AsDouble(at(z, i), header.fields[z]);
    const double value = intensity >= 0 ? AsDouble(at(intensity, i), header.fields[intensity]) : 0.0;
    std::optional<Stamp> stamp;
    if (time.field != nullptr) {
      stamp = IsInteger(*time.field) ? AsInt64(at(time.index, i), *time.field)
                                     : ToNanoseconds(AsDouble(at(time.index, i), *time.field), seconds);
    }
    const float fx = static_cast<float>(px), fy = static_cast<float>(py), fz = static_cast<float>(pz);
    if (!std::isfinite(fx) || !std::isfinite(fy) || !std::isfinite(fz) || !std::isfinite(value) ||
        (time.field != nullptr && !stamp)) {
      ++dropped;
      continue;
    }
    LidarPoint& point = scan.points.emplace_back();
    point.x = fx;
    point.y = fy;
    point.z = fz;
    point.intensity = static_cast<float>(value);
    if (ring >= 0) {
      const std::optional<std::int64_t> r = AsInt64(at(ring, i), header.fields[ring]);
      if (!r || *r < 0 || *r > std::numeric_limits<std::uint16_t>::max())
        return Status::Error(path + ": point " + std::to_string(i) + ": ring " +
                             (r ? std::to_string(*r) : std::string("(beyond int64)")) +
                             " is not in 0..65535");
      point.ring = static_cast<std::uint16_t>(*r);
    }
    if (stamp) times.push_back(*stamp);
  }
  scan.has_ring = ring >= 0;
  if (time.field != nullptr && !times.empty()) {
    const auto [first, last] = std::minmax_element(times.begin(), times.end());
    const Stamp start = *first;
    // Compare as unsigned: the difference of two int64 may not fit in one.
    const std::uint64_t span = static_cast<std::uint64_t>(*last) - static_cast<std::uint64_t>(start);
    if (span > static_cast<std::uint64_t>(std::numeric_limits<std::int32_t>::max()))
      return Status::Error(path + ": field '" + time.field->name + "': point times span " +
                           std::to_string(span) + " ns, more than the ~2.1 s one scan may cover");
    for (std::size_t i = 0; i < times.size(); ++i)
      scan.points[i].offset_ns = static_cast<std::int32_t>(times[i] - start);
    scan.stamp = start;
    scan.end = *last;
    scan.has_point_times = true;
  }
  if (info) {
    *info = PointCloudFileInfo{};
    info->points_in_file = static_cast<std::int64_t>(header.points);
    info->dropped_non_finite = dropped;
    if (time.field != nullptr) {
      info->point_time_field = time.field->name;
      info->point_time = time.convention;
    }
  }
  return scan;
}

}  // namespace uf
