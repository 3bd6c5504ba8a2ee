// The estimator a run drives, whichever window it is: the LiDAR window (estimator::LidarOdometry: LO, LIO and
// their wheel and GNSS factors) or the wheel-inertial one (estimator::InertialOdometry: WIO, WGIO). The
// odometry stage feeds it the dataset's measurements in time order and collects the keyframes that leave its
// window; nothing in the stage depends on which window it is.
#pragma once

#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "odometry/estimator/config/inertial_odometry_config.h"
#include "odometry/estimator/config/lidar_odometry_config.h"
#include "odometry/estimator/lidar_odometry/track_event.h"
#include "odometry/estimator/providers/sensor_factor_stats.h"
#include "odometry/estimator/visual/feature_tracker.h"
#include "odometry/types/georeference.h"
#include "odometry/types/keyframe.h"
#include "odometry/types/measurements.h"
#include "odometry/types/status.h"
#include "viewer/pipeline/run/run_mode.h"
#include "viewer/pipeline/run_files.h"

namespace uf::pipeline {

// The wall time of one step of the estimator: a scan (LiDAR window) or a node (wheel-inertial window).
struct StepTime {
  Stamp stamp = 0;
  double ms = 0;
  // With the camera (the V modes of either window): landmarks in the window after the step's solve and
  // their mean reprojection error, pixels; -1 without.
  int landmarks = -1;
  double reprojection_px = -1;
  std::optional<StageTimes> stages;  // the LiDAR window's; none in WIO
};

class RunEstimator {
 public:
  virtual ~RunEstimator() = default;

  // Each takes what its window reads; the wheel-inertial window ignores the scans. The meaning of each
  // (skipped samples, waiting for the IMU) is the window's (lidar_odometry.h, inertial_odometry.h).
  virtual Status AddScan(const LidarScan& scan) = 0;
  virtual Status AddImu(const ImuSample& sample) = 0;
  virtual Status AddWheel(const WheelSample& sample) = 0;
  virtual Status AddGnss(const GnssFix& fix) = 0;
  // A decoded frame of the tracked camera (the inertial window with the camera; ignored otherwise).
  virtual Status AddCameraFrame(const CameraFrame& frame) = 0;
  // A decoded frame of a stereo rig's right camera (with the tracked camera's factors; ignored otherwise).
  virtual Status AddRightCameraFrame(const CameraFrame& frame) = 0;
  // The visual front end's result per frame since the last call (none without the camera).
  virtual std::vector<estimator::TrackedFrame> TakeTrackedFrames() = 0;
  // The keyframes that left the window since the last call (the LiDAR window's carry the deskewed scan).
  virtual std::vector<Keyframe> TakeFinished() = 0;
  // The steps processed since the last call.
  virtual std::vector<StepTime> TakeStepTimes() = 0;
  // The LiDAR window's tracking events since the last call (none in the wheel-inertial window).
  virtual std::vector<estimator::TrackEvent> TakeEvents() = 0;
  // A new LiDAR extrinsic from now on, the window's LiDAR poses unchanged (LidarOdometry::SetLidarExtrinsic).
  // Errors: the window has no LiDAR extrinsic (LO, WIO).
  virtual Status SetLidarExtrinsic(const SE3& T_body_lidar) = 0;
  // End of data: every remaining state is released.
  virtual void Finish() = 0;

  virtual const std::vector<std::string>& warnings() const = 0;
  virtual const std::string& initialization() const = 0;  // how the inertial core started; "" in LO
  virtual estimator::SensorFactorStats sensor_factors() const = 0;
  virtual std::optional<Georeference> georeference() const = 0;  // G modes, once aligned to ENU
  virtual std::string step() const = 0;                          // "scan" or "node"
};

// The window of `mode`'s core: LidarOdometry with `lo` for LO and LIO, InertialOdometry with `wio` for the
// inertial window (wio, vio and their variants).
// Errors: the configuration's (Validate of the window's config).
Expected<std::unique_ptr<RunEstimator>> CreateRunEstimator(const EstimatorMode& mode,
                                                           const estimator::LidarOdometryConfig& lo,
                                                           const estimator::InertialOdometryConfig& wio);

}  // namespace uf::pipeline
