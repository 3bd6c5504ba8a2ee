// LiDAR odometry of the sliding-window estimator (docs/METHOD.md "Sliding window and solve" and "LO and LIO
// modes"; paper Section III-A/B): LiDAR-only (LO, a constant-velocity prior between states) or
// LiDAR-inertial (LIO, config.use_imu: IMU preintegration factors).
//
// Design:
// - Nodes: each scan has a begin node (sweep start) and an end node (sweep end), T_world_body as 7-wide
//   blocks on PoseManifold (body = the LiDAR in LO, the IMU in LIO), plus [v, b_a, b_g] in LIO; a scan that
//   starts where the previous one ended (< 1 ms) shares that end node as its begin. Deskew happens inside
//   PointToPlaneFactor (pose interpolated at each point's fraction alpha).
// - Motion factors: LO: ConstantVelocityFactor on every three consecutive nodes; its segments are divided by
//   their own durations, so the non-uniform gaps of keyframe data are handled. LIO: ImuFactor between
//   consecutive nodes; across an IMU gap (or before initialization) the constant-velocity prior instead.
// - Initial guess: LO: constant-velocity extrapolation of the twist between the last two nodes; LIO: the
//   IMU prediction from the last node.
// - Registration: the new scan (downsampled at input_voxel_m) against the VoxelHashMap built from earlier
//   scans; up to max_residuals_per_scan points with a plane within max_plane_distance_m, taken at an even
//   stride over the scan so they spread over it; Huber loss (huber_m). ICP style: up to association_rounds
//   rounds of (re-query planes, max_iterations LM iterations moving only the new scan's nodes) until a
//   round leaves them within 5 mm / 1 mrad of where this or an earlier round left them (converged, or the
//   association cycling through the same plane sets); then one solve of the whole window. Older scans keep
//   the factors of their own registration (planes fixed), so the window smooths the trajectory through the
//   motion factors. The very first scan (nothing to register against) gets a single node at its middle.
// - Map update right after the new scan's registration, with the scan deskewed by its solved poses: the
//   keyframe data are ~2 m apart, and waiting until a scan leaves the window would leave the map ~20 m
//   behind the vehicle (little overlap in turns).
// - Window: the last window_size scans. The oldest scan's states leave into a marginalization prior (Schur
//   complement of its point-to-plane residuals, the motion factors and the previous prior; window/
//   marginalization.h), which is the gauge of the next solves; before the first one (or with marginalize
//   off) the oldest scan's begin node is held constant.
// - LIO initialization (init/inertial_initializer.h): the scans run as LO in the first IMU pose's frame; from
//   the second scan on, each scan measures the excitation and LiDAR support of the window and chooses the
//   static mode S, the LiDAR-aided short-window MAP M or deferral A; S or M give gravity, velocities and
//   biases, which are admitted only after a consistency check of the IMU against them (a rejection retries
//   with the next scan, the oldest dropped); then the window is rotated into the gravity-aligned world (z up)
//   and the IMU factors take over. LIO waits with each scan until the IMU covers its end (at most
//   imu_max_wait_s of stream time).
// - Threads: the plane association of the new scan, the solver's evaluation and the keyframe's deskew run
//   on all cores (TBB); the residuals are taken in visiting order and partial sums added in a fixed order,
//   so the results do not depend on the number of threads.
// - Registration acceptance and recovery (docs/METHOD.md "Registration, acceptance and recovery"): a
//   registration is rejected when its solve fails or leaves a non-finite state, when fewer of its points lie
//   near a map plane than min_match_ratio of what the recent scans reached, or when it moved faster than
//   max_speed_mps / max_angular_rate_rad_s since the last registered scan. A rejected first guess is
//   followed by fallback guesses (no motion; in LIO also constant velocity); the accepted result matching
//   the most points is kept. A scan rejected from every guess keeps its predicted pose, stays out of the map,
//   and leaves as a keyframe without points; after max_rejected_scans rejections in a row the local map
//   restarts with the newest scan at the last registered pose (a discontinuity). Every rejection, fallback
//   and restart is a TrackEvent. In LIO a non-finite or faster-than-max_speed_mps state re-initializes
//   (logged), starting again at the last pose.
#pragma once

#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "odometry/estimator/config/lidar_odometry_config.h"
#include "odometry/estimator/init/inertial_initializer.h"
#include "odometry/estimator/lidar_odometry/track_event.h"
#include "odometry/estimator/providers/sensor_factor_stats.h"
#include "odometry/estimator/visual/feature_tracker.h"
#include "odometry/types/georeference.h"
#include "odometry/types/keyframe.h"
#include "odometry/types/measurements.h"
#include "odometry/types/status.h"
#include "odometry/types/trajectory.h"

namespace uf::estimator {

struct OdometryStats {
  Stamp stamp = 0;      // of the scan
  double solve_ms = 0;  // wall time of the scan's processing (preparation, association, solves, map)
  int residuals = 0;    // point-to-plane residuals of the new scan
  int iterations = 0;   // LM iterations, all solves of the scan
  // Where solve_ms went, ms: scan preparation (range filter, downsampling), plane association, the new
  // scan's registration solves, the window solve, map insertion, marginalization.
  double prepare_ms = 0, associate_ms = 0, register_ms = 0, window_ms = 0, map_ms = 0, marginalize_ms = 0;
  // LVIO: landmarks in the window after the scan's solve and their mean reprojection error, pixels; -1
  // without the camera.
  int landmarks = -1;
  double reprojection_px = -1;
};

class LidarOdometry {
 public:
  static Expected<LidarOdometry> Create(const LidarOdometryConfig& config);
  LidarOdometry(LidarOdometry&&) noexcept;
  LidarOdometry& operator=(LidarOdometry&&) noexcept;
  ~LidarOdometry();

  // Feeds one scan (time-ordered). Scans with too few points (after range filtering / downsampling) or all
  // non-finite points are skipped with a warning (see warnings()), never an error; time going backwards is
  // skipped likewise. Returns an error only for programmer misuse (end before stamp). LIO processes the
  // scan once the IMU covers its end (so it may happen in a later AddImu).
  Status AddScan(const LidarScan& scan);
  // Feeds one IMU sample (LIO; ignored in LO). Non-finite or not-increasing samples are skipped with a
  // warning.
  Status AddImu(const ImuSample& sample);
  // Feeds one wheel odometry sample (config.use_wheel; ignored otherwise). Non-finite or not-increasing
  // samples are skipped with a warning; a node interval the samples do not cover gets no wheel factor.
  Status AddWheel(const WheelSample& sample);
  // Feeds one decoded frame of the tracked camera (config.use_camera, LVIO; ignored otherwise). It joins
  // the scan node nearest its stamp + t_d once the window is initialized (providers/visual_provider.h). A
  // frame the front end refuses (out of order, another size) is skipped with a warning.
  Status AddCameraFrame(const CameraFrame& frame);
  // Feeds one decoded frame of a stereo rig's right camera (config.right_camera with visual.stereo;
  // ignored otherwise): it is matched with the tracked camera's frame of its stamp.
  Status AddRightCameraFrame(const CameraFrame& frame);
  // The front end's result per frame since the last call (none without the camera).
  std::vector<TrackedFrame> TakeTrackedFrames();
  // Feeds one GNSS fix (config.use_gnss; ignored otherwise). Fixes that fail the screening (status, NaN,
  // covariance) or come out of time order are skipped with a warning; accepted ones join the window once
  // its nodes cover them and the alignment has started (providers/gnss_provider.h).
  Status AddGnss(const GnssFix& fix);
  // Keyframes whose state has left the window (final) since the last call: stamp = the scan's middle
  // (stamp + (end - stamp) / 2), T_world_body = pose at that time, scan_world = deskewed points (world),
  // scan_intensity, velocity from the estimate. LIO holds them back until its initialization and rotates
  // them into the gravity-aligned world with the window (at most 200; docs/METHOD.md "Observability-aware
  // initialization").
  std::vector<Keyframe> TakeFinished();
  // Optimises once more and releases every remaining state (end of data).
  void Finish();
  // LIO: a new T_body_lidar (T_imu_lidar) from now on, e.g. a locked online calibration. The world LiDAR
  // poses of the window stay where they are (every body pose moves to T_WB T_BL_old T_BL_new^-1, docs/
  // METHOD.md "Online spatiotemporal calibration"), so does the map; gravity turns in the world by what
  // the new rotation says the map's world is tilted; the marginalization prior is dropped. Errors: LO (no
  // extrinsic), GNSS factors (their alignment needs the world level), a non-finite extrinsic.
  Status SetLidarExtrinsic(const SE3& T_body_lidar);
  // The states still in the window, oldest first: their stamps and T_world_body.
  Trajectory WindowPoses() const;
  // The statistics of each scan processed since the last call.
  std::vector<OdometryStats> TakeProcessedStats();
  // The tracking events since the last call, in scan order.
  std::vector<TrackEvent> TakeEvents();
  const std::vector<std::string>& warnings() const;
  const OdometryStats& last_stats() const;  // of the last processed scan
  std::size_t map_point_count() const;      // points in the local map now (bounded by its range)
  bool inertial() const;                    // LIO initialized (IMU factors active)
  // How LIO initialized: InitializationRecord::Summary() ("S (static) after 0.2 s, ..."), empty before.
  const std::string& initialization() const;
  // The initialization's mode, latency, state and attempts (of the last initialization, or the one under
  // way).
  const InitializationRecord& initialization_record() const;
  SensorFactorStats sensor_factors() const;
  // With GNSS factors, once the world -> ENU alignment has started: the ENU origin and T_enu_world as
  // estimated now (after Finish: at the end of the run).
  std::optional<Georeference> georeference() const;

 private:
  struct Impl;
  explicit LidarOdometry(std::unique_ptr<Impl> impl);
  std::unique_ptr<Impl> impl_;
};

}  // namespace uf::estimator
