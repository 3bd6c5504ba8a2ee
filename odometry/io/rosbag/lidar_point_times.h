// Scan timing shared by the LiDAR decoders: per-point times -> LidarScan::stamp, end and offset_ns.
#pragma once

#include <cstdint>
#include <span>
#include <string>

#include "odometry/types/azimuth_convention.h"
#include "odometry/types/measurements.h"
#include "odometry/types/stamp.h"

namespace uf {

// `times_from_base` holds one time per point of scan.points, in ns after `base` (the message's header stamp;
// negative: before it). Sets scan.stamp = min(base, earliest point time), so every offset is >= 0 also for
// drivers that stamp the scan end, scan.end = the latest point time, and each offset_ns. When the header is
// so far before the points that offsets would overflow int32 (2.1 s), the stamp is the earliest point
// instead. Returns an empty string, or why the times were dropped (points spread over more than 2.1 s): the
// scan then has no point times and end = stamp + sweep_period_s.
std::string AssignPointTimes(Stamp base, std::span<const std::int64_t> times_from_base, double sweep_period_s,
                             LidarScan& scan);

// For a spinning LiDAR without per-point times: DeriveAzimuthPointTimes (odometry/types/azimuth_convention.h)
// by `convention`. A ROS driver publishes the points in firing order and starts a scan wherever the
// previous one ended, so the default (kClockwiseFromFirstPoint: Velodyne-style sensors spin clockwise seen
// from above) takes the first point in storage order as the start of the sweep. On entry each offset_ns
// holds a guess of the point's time from its position (its fraction of the cloud, or of its row in an
// organised cloud, times the period); it only resolves the seam of that start. Sets stamp = base, end =
// base + period, has_point_times and point_times_from_azimuth (no point times for an empty scan or a period
// outside (0, 2] s).
void AssignAzimuthPointTimes(Stamp base, double sweep_period_s, const AzimuthConvention& convention,
                             LidarScan& scan);

// No point times at all: stamp = base, end = base + period, has_point_times = false.
void AssignNoPointTimes(Stamp base, double sweep_period_s, LidarScan& scan);

// Seconds -> ns for a sweep period; 0 (unknown) outside (0, 2] s, the range int32 offsets can hold.
Stamp SweepPeriodNs(double sweep_period_s);

}  // namespace uf
