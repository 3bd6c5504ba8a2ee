#include "odometry/estimator/lidar_odometry/scan_preparation.h"

#include <algorithm>
#include <cmath>
#include <cstdint>

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
  // Per voxel (by its slot in the key set): the index of its kept point in `out` and how many of its points
  // were seen.
  VoxelKeySet voxels(points.size());
  std::vector<std::uint32_t> kept(voxels.capacity()), seen(voxels.capacity());
  std::vector<PreparedPoint> out;
  out.reserve(points.size() / 4);
  const double inverse = 1.0 / voxel_m;
  for (const PreparedPoint& p : points) {
    const std::uint64_t key = PackVoxelKey(VoxelOf(p.point_lidar, inverse));
    const auto [i, inserted] = voxels.InsertSlot(key);
    if (inserted) {
      kept[i] = static_cast<std::uint32_t>(out.size());
      seen[i] = 1;
      out.push_back(p);
      continue;
    }
    // A reservoir of one: the n-th point of a voxel replaces the kept one with probability 1 / n, so each of
    // its points is kept with the same probability. The draw is a hash of the voxel and n, so a scan always
    // gives the same points.
    const std::uint64_t n = ++seen[i];
    if (VoxelKeyHash()(key ^ (n * 0x9e3779b97f4a7c15ULL)) % n == 0) out[kept[i]] = p;
  }
  return out;
}

}  // namespace uf::estimator
