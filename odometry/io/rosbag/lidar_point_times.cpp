#include "odometry/io/rosbag/lidar_point_times.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace uf {

Stamp SweepPeriodNs(double sweep_period_s) {
  if (!(sweep_period_s > 0 && sweep_period_s <= 2)) return 0;  // also NaN; offsets are int32 ns
  return static_cast<Stamp>(std::llround(sweep_period_s * 1e9));
}

std::string AssignPointTimes(Stamp base, std::span<const std::int64_t> times_from_base, double sweep_period_s,
                             LidarScan& scan) {
  constexpr std::int64_t kMaxOffset = std::numeric_limits<std::int32_t>::max();
  if (scan.points.empty() || times_from_base.size() != scan.points.size()) {
    AssignNoPointTimes(base, sweep_period_s, scan);
    return {};
  }
  const auto [earliest, latest] = std::minmax_element(times_from_base.begin(), times_from_base.end());
  if (*latest - *earliest > kMaxOffset) {
    AssignNoPointTimes(base, sweep_period_s, scan);
    return "point times spread over more than 2.1 s (times dropped)";
  }
  // Offsets are counted from `start`, in ns after base: the header stamp if it precedes every point (and is
  // close enough for int32 offsets), else the earliest point.
  const std::int64_t start = (*earliest >= 0 && *latest <= kMaxOffset) ? 0 : *earliest;
  for (std::size_t i = 0; i < scan.points.size(); ++i) {
    scan.points[i].offset_ns = static_cast<std::int32_t>(times_from_base[i] - start);
  }
  scan.stamp = base + start;
  scan.end = base + *latest;
  scan.has_point_times = true;
  scan.point_times_from_azimuth = false;
  return {};
}

void AssignAzimuthPointTimes(Stamp base, double sweep_period_s, const AzimuthConvention& convention,
                             LidarScan& scan) {
  const Stamp period = SweepPeriodNs(sweep_period_s);
  if (scan.points.empty() || period == 0) {
    AssignNoPointTimes(base, sweep_period_s, scan);
    return;
  }
  scan.stamp = base;
  DeriveAzimuthPointTimes(scan, period, convention);
}

void AssignNoPointTimes(Stamp base, double sweep_period_s, LidarScan& scan) {
  scan.stamp = base;
  scan.end = scan.points.empty() ? base : base + SweepPeriodNs(sweep_period_s);
  scan.has_point_times = false;
  scan.point_times_from_azimuth = false;
  for (LidarPoint& point : scan.points) point.offset_ns = 0;
}

}  // namespace uf
