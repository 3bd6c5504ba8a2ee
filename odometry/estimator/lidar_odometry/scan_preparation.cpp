#include "odometry/estimator/lidar_odometry/scan_preparation.h"

#include <algorithm>
#include <cmath>

#include "odometry/estimator/lidar/voxel_key.h"

namespace uf::estimator {

std::vector<PreparedPoint> PrepareScan(const LidarScan& scan, double min_range_m, double max_range_m) {
  std::vector<PreparedPoint> out;
  out.reserve(scan.points.size());
  const double duration_ns = static_cast<double>(scan.end - scan.stamp);
  const bool timed = scan.has_point_times && duration_ns > 0;
  const double min2 = min_range_m * min_range_m, max2 = max_range_m * max_range_m;
  for (const LidarPoint& p : scan.points) {
    const Eigen::Vector3d q(p.x, p.y, p.z);
    if (!q.allFinite()) continue;
    const double r2 = q.squaredNorm();
    if (r2 < min2 || r2 > max2) continue;
    const double alpha = timed ? std::clamp(p.offset_ns / duration_ns, 0.0, 1.0) : 0.0;
    out.push_back({q, alpha, p.intensity, scan.has_ring ? static_cast<int>(p.ring) : -1});
  }
  return out;
}

std::vector<PreparedPoint> DownsamplePrepared(const std::vector<PreparedPoint>& points, double voxel_m) {
  VoxelKeySet seen(points.size());
  std::vector<PreparedPoint> out;
  const double inverse = 1.0 / voxel_m;
  for (const PreparedPoint& p : points) {
    if (seen.Insert(PackVoxelKey(VoxelOf(p.point_lidar, inverse)))) out.push_back(p);
  }
  return out;
}

}  // namespace uf::estimator
