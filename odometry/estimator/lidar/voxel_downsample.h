// Voxel-grid downsampling of a LiDAR scan (KISS-ICP style): keeps the FIRST point seen in each voxel, in
// input order, as a whole LidarPoint (offset_ns survives for deskewing). Voxels are the grid of
// voxel_key.h in the scan's own (lidar) frame. Non-finite points, and points beyond the key range of
// voxel_key.h, are dropped.
#pragma once

#include <vector>

#include "odometry/types/measurements.h"

namespace uf::estimator {

// voxel_m > 0 (asserted). Output order = order of first appearance in the input.
std::vector<LidarPoint> VoxelDownsample(const std::vector<LidarPoint>& points, double voxel_m);

}  // namespace uf::estimator
