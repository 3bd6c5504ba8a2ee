// Single-scan point cloud files: PCD (PCL's format; ascii, binary and binary_compressed) and KITTI Velodyne
// .bin (float32 x y z intensity per point, little-endian, no header). Pure functions of the file, safe on
// any input: a damaged file gives an error naming the file and what is wrong, never a crash.
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>

#include "odometry/io/dataset_reader.h"
#include "odometry/types/measurements.h"
#include "odometry/types/status.h"

namespace uf {

// What a point cloud file held besides the points.
struct PointCloudFileInfo {
  std::string point_time_field;  // "time", "t" or "timestamp" when the file has per-point times
  PointTimeConvention point_time = PointTimeConvention::kNone;
  std::int64_t points_in_file = 0;
  std::int64_t dropped_non_finite = 0;  // points removed because a coordinate, intensity or time was NaN/Inf
};

// Reads a PCD file. Fields: x y z (float, required); optional `intensity` (or `i`), `ring` (integer) and a
// per-point time, recognised as the ROS bag reader does:
//   `time`      float, seconds relative to the scan (Velodyne)          -> kRelativeSeconds
//   `t`         integer, nanoseconds relative to the scan (Ouster)      -> kRelativeNanoseconds
//   `timestamp` float, absolute seconds (Hesai), or absolute nanoseconds
//               when the values exceed 1e11 (Livox driver2)             -> kAbsoluteSeconds /
//               kAbsoluteNanoseconds
// Other fields are skipped. Points with a non-finite value are dropped (counted in info). With point times
// the scan's stamp is the earliest point time (relative times: relative to the file's own zero, to which
// the caller adds the scan stamp), offsets are measured from it and `end` is the latest; without them
// stamp = end = 0.
Expected<LidarScan> ReadPcdFile(const std::filesystem::path& path, PointCloudFileInfo* info = nullptr);

// Reads a KITTI Velodyne .bin file (or .bin.xz, decompressed on the fly); its size must be a multiple of 16
// bytes. No point times: stamp = end = 0.
Expected<LidarScan> ReadKittiBin(const std::filesystem::path& path, PointCloudFileInfo* info = nullptr);

// Gives every point of a spinning LiDAR's scan the time at which the beam swept its azimuth, for scans
// whose points carry no time, and sets end = stamp + sweep_period (flags point_times_from_azimuth), by the
// KITTI convention: DeriveAzimuthPointTimes (odometry/types/azimuth_convention.h) with kClockwiseFromBehind,
// the KITTI-style folder reader's default (DatasetOptions::point_time_convention chooses another).
//
// Model (KITTI's Velodyne HDL-64E, x forward, y left, z up): the head spins clockwise seen from above, so
// the azimuth atan2(y, x) decreases with time, and a sweep starts and ends behind the car (azimuth +-180
// deg); it faces forward half-way through. offset = (pi - atan2(y, x)) / (2 pi) * sweep_period.
// Evidence: Velodyne's HDL-64E manual (clockwise rotation), KISS-ICP's KITTI loader (time = 0.5 (-atan2/pi
// + 1)), and a check on ../shared/data/kitti00-keyframes: deskewing consecutive keyframes with the ground
// truth this way lowers the mean point-to-plane distance between them (0.0259 -> 0.0231 m at keyframe 10),
// while counter-clockwise raises it (0.0306 m). Note the order of the points in KITTI files (azimuth
// increasing) is not the acquisition order. KITTI's times.txt stamps the instant the head faced forward
// (the camera trigger), half a sweep after the scan start: the KITTI reader sets the scan stamp accordingly
// (DatasetOptions::folder_scan_stamp).
void DerivePointTimesFromAzimuth(LidarScan& scan, Stamp sweep_period);

}  // namespace uf
