#include "odometry/estimator/lidar/voxel_downsample.h"

#include <cassert>
#include <cmath>
#include <cstdint>

#include "odometry/estimator/lidar/voxel_key.h"

namespace uf::estimator {

std::vector<LidarPoint> VoxelDownsample(const std::vector<LidarPoint>& points, double voxel_m) {
  assert(voxel_m > 0);
  const double inverse_voxel = 1.0 / voxel_m;
  const double limit = static_cast<double>(kVoxelIndexLimit) * voxel_m;
  // The set never holds more keys than points, so at most half full: probes stay short.
  VoxelKeySet seen(points.size());
  std::vector<LidarPoint> kept;
  kept.reserve(points.size() / 4);
  for (const LidarPoint& point : points) {
    const Eigen::Vector3d p(point.x, point.y, point.z);
    if (!p.allFinite() || p.cwiseAbs().maxCoeff() >= limit) continue;
    if (seen.Insert(PackVoxelKey(VoxelOf(p, inverse_voxel)))) kept.push_back(point);
  }
  return kept;
}

}  // namespace uf::estimator
