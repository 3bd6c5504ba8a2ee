// The inertial window without a LiDAR (docs/METHOD.md "Wheel-inertial odometry" and "Visual-inertial
// odometry"; paper Section III-B with the LiDAR absent): wheel-inertial (WIO), visual-inertial (VIO) or both
// (VWIO), with GNSS factors optional (WGIO, VGIO, VWGIO).
//
// Design:
// - Nodes: without the camera one every node_interval_s of IMU time, on a grid starting where both the IMU
//   and the wheel streams have begun; with the camera one per frame, at its stamp + t_d. A node is added
//   once the IMU and the wheel (when used) cover its stamp. If the IMU runs more than wheel_max_wait_s past a
//   node the wheel does not cover, the node goes ahead without the wheel (the wheel factor of that interval
//   is skipped, a warning). State per node: T_world_imu and [v, b_a, b_g].
// - Factors: ImuFactor between consecutive nodes (preintegration over the IMU samples, refused across a gap
//   longer than imu_max_gap_s); WheelFactor between them through the WheelProvider, which owns the wheel
//   scale block and its prior; ReprojectionFactors through the VisualProvider (landmarks anchored in their
//   first node, marginalized with it); the gauge prior (factors/gauge_prior_factor.h: position and yaw of
//   the first node, the four directions the window cannot observe) until the first marginalization carries
//   it.
// - Initialization: no node is created before it; the first init_window_nodes node stamps wait (only
//   their stamps). The static alignment (IMU at rest, wheel not moving), else with the wheel the moving one
//   (LidarAidedAlignment on poses dead-reckoned from the wheel: T_lo_imu = T_lo_wheel T_body_wheel^-1),
//   gives gravity, velocities and biases; then the window is built. A failed window slides by one node.
//   Without the wheel (VIO): the static alignment when the camera sees the rest too, else the visual-inertial
//   start (mode D, init/visual_inertial_poses.h: the poses from the camera's tracks and the IMU, then the
//   moving alignment on them).
// - Solve: after each node, dense Levenberg-Marquardt on every node, the wheel scale, the landmarks' inverse
//   depths and t_d when free (max_iterations); then the camera's outliers are dropped. When the window holds
//   more than window_size nodes, the oldest leaves into the marginalization prior and becomes a keyframe.
// - Divergence: a non-finite state, a speed above max_speed_mps or a failed solve leaves the window's
//   nodes unreported (not trusted) and starts a new initialization at the last good pose (a warning). An IMU
//   gap between two nodes ends the window instead: its nodes are final (reported), and a new
//   initialization starts after the gap at the pose the wheel dead-reckons across it (without the wheel: at
//   the last pose).
// - Threads: none beyond the dense solver's evaluation.
#pragma once

#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "odometry/estimator/config/inertial_odometry_config.h"
#include "odometry/estimator/providers/sensor_factor_stats.h"
#include "odometry/estimator/visual/feature_tracker.h"
#include "odometry/types/georeference.h"
#include "odometry/types/keyframe.h"
#include "odometry/types/measurements.h"
#include "odometry/types/status.h"

namespace uf::estimator {

struct InertialOdometryStats {
  Stamp stamp = 0;            // of the node
  double solve_ms = 0;        // wall time of the node: its factors, the solve and the marginalization
  double marginalize_ms = 0;  // of which the marginalization
  int iterations = 0;         // LM iterations of the node's solve
  int landmarks = -1;         // with the camera: landmarks in the window after the solve (-1 without)
  int outliers = 0;           // with the camera: landmarks dropped after the solve
  double reprojection_px = -1;  // with the camera: mean reprojection error after the solve, px (-1 without)
};

class InertialOdometry {
 public:
  static Expected<InertialOdometry> Create(const InertialOdometryConfig& config);
  InertialOdometry(InertialOdometry&&) noexcept;
  InertialOdometry& operator=(InertialOdometry&&) noexcept;
  ~InertialOdometry();

  // Feed the samples in time order (as a MeasurementStream delivers them). Non-finite or not-increasing
  // samples are skipped with a warning (warnings()); nodes are added, solved and marginalized inside.
  Status AddImu(const ImuSample& sample);
  Status AddWheel(const WheelSample& sample);
  // Feeds one GNSS fix (config.use_gnss, WGIO; ignored otherwise): screened, then linked to the nodes
  // around its stamp once they exist and the ENU alignment has started (providers/gnss_provider.h). Bad
  // fixes are skipped with a warning.
  Status AddGnss(const GnssFix& fix);
  // Feeds one decoded frame of the tracked camera (config.use_camera, VIO and VWIO; ignored otherwise): it
  // is tracked at once, and its node is added when the IMU (and the wheel) cover the frame's stamp + t_d. A
  // frame the front end refuses (out of order, wrong size) is skipped with a warning.
  Status AddCameraFrame(const CameraFrame& frame);
  // Feeds one decoded frame of a stereo rig's right camera (config.right_camera with visual.stereo;
  // ignored otherwise): it is matched with the tracked camera's frame of its stamp.
  Status AddRightCameraFrame(const CameraFrame& frame);
  // The front end's result per frame since the last call (features and statistics).
  std::vector<TrackedFrame> TakeTrackedFrames();
  // Keyframes of the nodes that have left the window (final) since the last call: stamp, T_world_body
  // (body = IMU), velocity (world), biases; no scan.
  std::vector<Keyframe> TakeFinished();
  // End of data: adds the nodes the IMU covers (without waiting for the wheel) and releases every node
  // (each was solved when it was added).
  void Finish();
  std::vector<InertialOdometryStats> TakeProcessedStats();  // per node since the last call
  const std::vector<std::string>& warnings() const;
  bool inertial() const;                      // initialized: nodes in the window
  const std::string& initialization() const;  // how it last initialized ("static at 0.9 s ..."), or empty
  SensorFactorStats sensor_factors() const;
  // WGIO, once the ENU alignment has started: the ENU origin and T_enu_world as estimated now.
  std::optional<Georeference> georeference() const;

 private:
  struct Impl;
  explicit InertialOdometry(std::unique_ptr<Impl> impl);
  std::unique_ptr<Impl> impl_;
};

}  // namespace uf::estimator
