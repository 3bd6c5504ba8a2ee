// The camera in the LiDAR window (LVIO, see odometry_window.h and docs/METHOD.md "LiDAR-visual-inertial
// odometry"): frames join the scan nodes nearest them, landmarks take their depth from the LiDAR map, and
// leave with their anchor node (dropped, not marginalized: MarginalizeBefore).
#include "odometry/estimator/lidar/map_ray_depth.h"
#include "odometry/estimator/lidar_odometry/odometry_window.h"

namespace uf::estimator {

void LidarOdometry::Impl::AttachProviders() {
  if (wheel) wheel->Attach(graph);
  if (visual) visual->Attach(graph);
  AttachLidarTranslation();
}

// Before the window's solve, once the window is initialized (the IMU carries the poses the landmarks are
// triangulated from and the camera frames between the scans): the waiting frames join their nodes and the
// landmarks and their factors join the graph. Before that the frames only wait (TrimStreams drops them).
void LidarOdometry::Impl::LinkVisual() {
  if (!visual || !inertial) return;
  std::vector<NodeStamp> stamps;
  for (long id = first_node_id; id <= LastNodeId(); ++id) stamps.push_back({id, NodeAt(id).stamp});
  visual->ObserveNearest(stamps);
  visual->Link(graph, [this](long id) { return NodeAt(id).pose.data(); });
}

// The depth along the camera's z where the ray through xy meets the map, and the map's plane there
// (lidar/map_ray_depth.h).
std::optional<MapSurface> LidarOdometry::Impl::MapDepth(const SE3& T_world_camera,
                                                        const Eigen::Vector2d& xy) const {
  const Eigen::Vector3d ray = xy.homogeneous();
  const double norm = ray.norm();
  const std::optional<MapRayHit> hit =
      MapRaySurface(map, T_world_camera.translation(), T_world_camera.so3() * (ray / norm),
                    config.visual.min_depth_m, config.visual.max_depth_m);
  if (!hit) return std::nullopt;
  return MapSurface{hit->distance / norm, hit->plane};
}

// The inverse depths of the landmarks anchored in the nodes before keep_from: they leave with them.
std::vector<double*> LidarOdometry::Impl::AnchoredBlocks(long keep_from) const {
  std::vector<double*> blocks;
  if (!visual) return blocks;
  for (long id = first_node_id; id < keep_from && id <= LastNodeId(); ++id)
    for (double* block : visual->AnchoredBlocks(id)) blocks.push_back(block);
  return blocks;
}

void LidarOdometry::Impl::ForgetVisualBefore(long keep_from) {
  if (visual) visual->ForgetNode(keep_from - 1);
}

}  // namespace uf::estimator
