// Configuration of LiDAR-only odometry (LO mode): plain struct with the paper's defaults and a Validate
// that names the first bad field ("lo.<field>: must be ..., got <value>").
#pragma once

#include "odometry/estimator/factors/constant_velocity_factor.h"
#include "odometry/estimator/lidar/voxel_hash_map.h"
#include "odometry/types/se3.h"
#include "odometry/types/status.h"

namespace uf::estimator {

struct LidarOdometryConfig {
  double input_voxel_m = 1.0;         // downsampling of each scan for registration, m
  VoxelMapConfig map;                 // voxel 0.5 m, eigen-ratio 0.12 (paper)
  int window_size = 10;               // scans (states) in the window, >= 2 (real-time profile 4)
  int max_iterations = 8;             // Ceres LM iterations per solve (paper 8 / 40 ms)
  double max_solver_time_s = 0.04;    // per solve, s
  int max_residuals_per_scan = 1500;  // point-to-plane residuals of one scan (paper 1200-2000)
  double huber_m = 0.5;               // robust loss scale, m of point-to-plane distance (paper 0.5-1.0)
  double min_range_m = 1.0, max_range_m = 100.0;  // points kept for registration and the map, m
  SE3 T_body_lidar;                               // identity in LO mode (body = lidar)
  // Beyond the list (defaults tuned on KITTI 00 keyframes and the simulator):
  double map_insert_voxel_m = 0.5;    // downsampling of the deskewed scan inserted into the map, m
  int association_rounds = 10;        // at most this many solve + re-query rounds per scan (ICP style)
  double max_plane_distance_m = 1.0;  // correspondences farther from their plane are dropped, m
  ConstantVelocityNoise motion;       // constant-velocity prior between consecutive pose nodes
  double max_correction_m = 5.0;      // a solve moving the new scan farther than this from its guess
  double max_correction_rad = 0.5;    //   (or rotating it more) is treated as divergence
  int min_points = 50;                // scans with fewer prepared points are skipped

  Status Validate() const;
};

}  // namespace uf::estimator
