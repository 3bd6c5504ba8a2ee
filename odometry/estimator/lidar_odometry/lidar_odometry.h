// LiDAR-only odometry (LO mode) of the sliding-window estimator (METHOD.md, paper Section III without IMU).
//
// Design:
// - Pose nodes: each scan has a begin node (sweep start) and an end node (sweep end), T_world_body as 7-wide
//   blocks on PoseManifold; a scan that starts where the previous one ended (< 1 ms) shares that end node as
//   its begin. Deskew happens inside PointToPlaneFactor (pose interpolated at each point's fraction alpha).
// - Motion prior: ConstantVelocityFactor on every three consecutive nodes (LO has no IMU); its segments are
//   divided by their own durations, so the non-uniform gaps of keyframe data are handled.
// - Initial guess: constant-velocity extrapolation of the twist between the last two nodes.
// - Registration: the new scan (downsampled at input_voxel_m) against the VoxelHashMap built from earlier
//   scans; up to max_residuals_per_scan points with a plane within max_plane_distance_m, taken at an even
//   stride over the scan so they spread over it; Huber loss (huber_m). ICP style: up to association_rounds
//   rounds of (re-query planes, max_iterations LM iterations moving only the new scan's nodes) until a
//   round moves them < 5 mm / 1 mrad; then one solve of the whole window. Older scans keep the factors of
//   their own registration (planes fixed), so the window smooths the trajectory through the motion prior.
//   The very first scan (nothing to register against) gets a single node at its middle.
// - Map update right after the new scan's registration, with the scan deskewed by its solved poses: the
//   keyframe data are ~2 m apart, and waiting until a scan leaves the window would leave the map ~20 m
//   behind the vehicle (little overlap in turns).
// - Window: the last window_size scans. No marginalization prior yet: the oldest scan's begin node is held
//   constant instead (a marginalization prior plugs in exactly there later).
// - Divergence (non-finite result, solver failure, correction beyond max_correction_m / _rad): the scan
//   keeps its constant-velocity guess, a warning is recorded, and it is not inserted into the map.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "odometry/estimator/lidar_odometry/lidar_odometry_config.h"
#include "odometry/types/keyframe.h"
#include "odometry/types/measurements.h"
#include "odometry/types/status.h"

namespace uf::estimator {

struct OdometryStats {
  double solve_ms = 0;  // wall time of AddScan's registration (association + solves)
  int residuals = 0;    // point-to-plane residuals of the new scan
  int iterations = 0;   // LM iterations, all solves of the scan
};

class LidarOdometry {
 public:
  static Expected<LidarOdometry> Create(const LidarOdometryConfig& config);
  LidarOdometry(LidarOdometry&&) noexcept;
  LidarOdometry& operator=(LidarOdometry&&) noexcept;
  ~LidarOdometry();

  // Feeds one scan (time-ordered). Scans with too few points (after range filtering / downsampling) or all
  // non-finite points are skipped with a warning (see warnings()), never an error; time going backwards is
  // skipped likewise. Returns an error only for programmer misuse (end before stamp).
  Status AddScan(const LidarScan& scan);
  // Keyframes whose state has left the window (final) since the last call: stamp = the scan's middle
  // (stamp + (end - stamp) / 2), T_world_body = pose at that time, scan_world = deskewed points (world),
  // scan_intensity, velocity from the estimate.
  std::vector<Keyframe> TakeFinished();
  // Optimises once more and releases every remaining state (end of data).
  void Finish();
  const std::vector<std::string>& warnings() const;
  const OdometryStats& last_stats() const;  // of the last AddScan

 private:
  struct Impl;
  explicit LidarOdometry(std::unique_ptr<Impl> impl);
  std::unique_ptr<Impl> impl_;
};

}  // namespace uf::estimator
