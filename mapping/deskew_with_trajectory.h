// A LiDAR scan deskewed with a known trajectory and turned into a keyframe for the map: what
// `ultrafusion run --from map` does with the scans read again and the trajectory.tum of an earlier run
// (docs/ARCHITECTURE.md), so that the map is built as after the odometry (keyframe_mapper.h).
//
// Frames: the trajectory holds T_world_est(t), the pose of the estimator's body (`est`: the LiDAR in LO, the
// IMU in LIO), and T_est_lidar places the LiDAR in it. A point p measured at time t_p = scan.stamp +
// offset_ns in the LiDAR frame lands at
//   p_world = T_world_est(t_p) * T_est_lidar * p,
// with T_world_est(t) from Trajectory::PoseAt (slerp of the rotation and lerp of the translation between the
// bracketing poses, odometry/types/trajectory.h). Without per-point times (scan.has_point_times false) every
// point takes the pose of the middle of the sweep. The keyframe is stamped at that middle,
// t_mid = stamp + (end - stamp) / 2 (integer ns), with T_world_body = T_world_est(t_mid).
//
// Points kept: finite, with range |p| (in the LiDAR frame) in [min_range_m, max_range_m], and whose time lies
// in the trajectory's time span (others are dropped: no extrapolation). Each kept point keeps its intensity.
#pragma once

#include <optional>

#include "odometry/types/keyframe.h"
#include "odometry/types/measurements.h"
#include "odometry/types/se3.h"
#include "odometry/types/trajectory.h"

namespace uf::mapping {

// The deskewed keyframe (scan_world and scan_intensity filled; velocity and biases zero), or none when the
// trajectory does not cover the middle of the sweep.
std::optional<Keyframe> DeskewWithTrajectory(const LidarScan& scan, const Trajectory& T_world_est,
                                             const SE3& T_est_lidar, double min_range_m, double max_range_m);

}  // namespace uf::mapping
