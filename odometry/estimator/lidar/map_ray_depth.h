// Where a camera ray meets the LiDAR map (LVIO's landmark depth, docs/METHOD.md "LiDAR-visual-inertial
// odometry"): march along the ray in steps of one voxel and, at each step, intersect the ray with the map's
// plane near that point (VoxelHashMap::PlaneNear); the first intersection that lies within the plane's
// block (1.5 voxels of the step's point) and that the ray does not graze is where the ray meets a surface.
#pragma once

#include <Eigen/Core>
#include <optional>

#include "odometry/estimator/lidar/voxel_hash_map.h"

namespace uf::estimator {

// The first surface of `map` along origin + t direction (direction of unit length), t in [min_m, max_m]: its
// distance t and the map's plane there (LVIO's landmarks stay on it: factors/landmark_plane_factor.h); or
// nullopt. A ray that grazes a plane (the cosine of its angle to the normal below 0.1) passes it.
struct MapRayHit {
  double distance = 0;
  Plane plane;
};
std::optional<MapRayHit> MapRaySurface(const VoxelHashMap& map, const Eigen::Vector3d& origin,
                                       const Eigen::Vector3d& direction, double min_m, double max_m);

}  // namespace uf::estimator
