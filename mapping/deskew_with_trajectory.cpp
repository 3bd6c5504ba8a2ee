#include "mapping/deskew_with_trajectory.h"

namespace uf::mapping {

std::optional<Keyframe> DeskewWithTrajectory(const LidarScan& scan, const Trajectory& T_world_est,
                                             const SE3& T_est_lidar, double min_range_m, double max_range_m) {
  Keyframe keyframe;
  keyframe.stamp = scan.stamp + (scan.end - scan.stamp) / 2;
  const std::optional<SE3> middle = T_world_est.PoseAt(keyframe.stamp);
  if (!middle) return std::nullopt;
  keyframe.T_world_body = *middle;
  keyframe.scan_world.reserve(scan.points.size());
  keyframe.scan_intensity.reserve(scan.points.size());
  const SE3 T_world_lidar_middle = *middle * T_est_lidar;
  for (const LidarPoint& point : scan.points) {
    const Eigen::Vector3d p(point.x, point.y, point.z);
    const double range = p.norm();
    if (!p.allFinite() || range < min_range_m || range > max_range_m) continue;
    // Without per-point times the whole scan takes the pose of its middle.
    std::optional<SE3> T_world_est_point = middle;
    if (scan.has_point_times) T_world_est_point = T_world_est.PoseAt(scan.stamp + point.offset_ns);
    if (!T_world_est_point) continue;
    const SE3 T_world_lidar = scan.has_point_times ? *T_world_est_point * T_est_lidar : T_world_lidar_middle;
    keyframe.scan_world.push_back((T_world_lidar * p).cast<float>());
    keyframe.scan_intensity.push_back(point.intensity);
  }
  return keyframe;
}

}  // namespace uf::mapping
