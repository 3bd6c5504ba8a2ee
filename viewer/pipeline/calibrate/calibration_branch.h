// Online LiDAR-IMU calibration inside a LIO run (`run --calibrate-online`; docs/METHOD.md, "Online
// spatiotemporal calibration"): a LiDAR-only odometry branch beside the run's window, isolated from it as
// the paper's calibration branch is, feeds the calibration workers (online_calibration.h) with the LiDAR's
// own motion and the IMU's gyro. Once the time offset locks, every later scan reaches the run's window
// re-stamped by it (stamp and end + offset); a re-stamped scan that would not come after the last one the
// window got is left out and counted. The poses of the scans before the lock, which carry the LiDAR's clock,
// are re-stamped by the same offset when the trajectory is written (RestampEarlierPoses). The branch stops
// once both workers have locked. Once the rotation locks, the run applies it with the given translation
// (ExtrinsicToApply; the odometry stage moves the window with RunEstimator::SetLidarExtrinsic, which keeps
// the world LiDAR poses, and the poses that had left the window likewise). The keyframes mapped before
// then keep the camera poses the given extrinsic gave them.
#pragma once

#include <memory>
#include <optional>
#include <string>

#include "odometry/estimator/calib/online_calibration.h"
#include "odometry/estimator/config/lidar_odometry_config.h"
#include "odometry/io/dataset_sensors.h"
#include "odometry/io/measurement_stream.h"
#include "viewer/pipeline/calibrate/calibrate_job.h"
#include "viewer/pipeline/run/run_estimator.h"

namespace uf::pipeline {

// What the branch did to the run.
struct OnlineCalibrationSummary {
  std::optional<Stamp> offset_applied_from;  // the first re-stamped scan's stamp (after re-stamping)
  double offset_applied_s = 0.0;             // added to the LiDAR stamps from then on
  std::int64_t scans_left_out = 0;           // re-stamped scans that did not come after the previous one
  std::int64_t branch_scans = 0;             // scans the branch's odometry processed
  double held_s = 0.0;  // how long the run's window waited for the locks (Holds), stream time
  std::optional<Stamp> rotation_applied_at;  // the scan (as read) at which the locked rotation was applied
  std::string rotation_refused;              // why the window did not take it (RunEstimator's error)
};

class CalibrationBranch {
 public:
  // For the `sensors.lidar` and `sensors.imu` streams of `stream` (both present): their names, the given
  // extrinsic and the offsets they are read with go into result(). Errors: the odometry configuration's.
  // hold_s: how long the run's window may wait for the locks (Holds).
  static Expected<std::unique_ptr<CalibrationBranch>> Create(
      const estimator::LidarOdometryConfig& lo, const MeasurementStream& stream,
      const DatasetSensors& sensors, double hold_s = 0.0,
      const estimator::OnlineCalibrationOptions& options = {});

  void AddImu(const ImuSample& sample);
  // Feeds the scan, as read, to the branch (until both workers have locked; counted in result() always).
  Status AddScan(const LidarScan& scan);
  // Whether the measurement at `stamp` (as read) is to wait before it reaches the run's window: until the
  // time offset and the rotation have locked, for at most hold_s from the first measurement. Once false,
  // false for good. The run then starts with what locked (re-stamped scans, the new rotation) instead of
  // running with the given calibration until the locks.
  bool Holds(Stamp stamp);
  // Applies the locked offset to `scan` (nothing before it locks). False when the re-stamped scan does not
  // come after the last scan re-stamped: the run's window is not to get it.
  bool Restamp(LidarScan& scan);
  // Once the rotation has locked, until Applied is called: T_imu_lidar to use from now on (the locked
  // rotation, the given translation).
  std::optional<SE3> ExtrinsicToApply() const;
  // What became of ExtrinsicToApply at the scan `stamp` (summary()): applied, or refused by the window.
  void Applied(Stamp stamp, const Status& status);
  // End of data (or both workers locked): the branch's last poses go to the workers, whose estimates then
  // fill result(). Once done, later calls do nothing.
  void Finish();

  // The estimates as `calibrate` reports and writes them (WriteCalibrateOutputs): the counts as they go,
  // the estimates from Finish on.
  const CalibrateResult& result() const { return result_; }
  const OnlineCalibrationSummary& summary() const { return summary_; }

 private:
  CalibrationBranch(std::unique_ptr<RunEstimator> odometry, CalibrateResult result, double hold_s,
                    const estimator::OnlineCalibrationOptions& options);
  void TakePoses();
  bool BothLocked() const { return calibration_.time_offset_locked() && calibration_.rotation_locked(); }

  std::unique_ptr<RunEstimator> odometry_;
  estimator::OnlineCalibration calibration_;
  CalibrateResult result_;
  OnlineCalibrationSummary summary_;
  std::optional<Stamp> last_restamped_;
  bool applied_ = false;  // the locked rotation went to the run's window (or was refused)
  Stamp hold_;            // Holds
  std::optional<Stamp> hold_from_;
  bool holding_ = true;
};

// The poses before `summary.offset_applied_from` (the scans the window got before the offset locked) moved
// onto the IMU clock by the applied offset; the trajectory stays in increasing order (Restamp made every
// later scan come after them). Unchanged when no offset was applied.
void RestampEarlierPoses(Trajectory& trajectory, const OnlineCalibrationSummary& summary);

}  // namespace uf::pipeline
