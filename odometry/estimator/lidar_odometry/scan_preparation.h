// Preparation of one LiDAR scan for LO: drops non-finite points and points outside [min_range, max_range]
// (range = distance from the lidar origin), and gives each point its deskew fraction
//   alpha = clamp(offset_ns / (end - stamp), 0, 1)      (0 at the sweep start, 1 at its end)
// (alpha = 0 for every point when the scan has no point times or no duration).
#pragma once

#include <Eigen/Core>
#include <vector>

#include "odometry/types/measurements.h"

namespace uf::estimator {

struct PreparedPoint {
  Eigen::Vector3d point_lidar;  // m, lidar frame at the point's own time
  double alpha = 0;             // in [0, 1]
  float intensity = 0;
  int ring = -1;  // the scan's ring (laser) of the point; -1 when the scan has none
};

std::vector<PreparedPoint> PrepareScan(const LidarScan& scan, double min_range_m, double max_range_m);

// Voxel downsampling of prepared points in the lidar frame (voxel_m > 0): one point per voxel, drawn at
// random among the voxel's points (each with the same probability; the same scan always gives the same
// points), in the order the voxels first appear. Not the first point: the first in acquisition order lies
// where the spin enters the voxel, which turns with the viewpoint and pulls the registration's heading
// (docs/METHOD.md "Scan registration").
std::vector<PreparedPoint> DownsamplePrepared(const std::vector<PreparedPoint>& points, double voxel_m);

}  // namespace uf::estimator
