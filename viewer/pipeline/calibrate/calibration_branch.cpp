#include "viewer/pipeline/calibrate/calibration_branch.h"

#include <algorithm>

namespace uf::pipeline {

Expected<std::unique_ptr<CalibrationBranch>> CalibrationBranch::Create(
    const estimator::LidarOdometryConfig& lo, const MeasurementStream& stream, const DatasetSensors& sensors,
    double hold_s, const estimator::OnlineCalibrationOptions& options) {
  Expected<std::unique_ptr<RunEstimator>> odometry =
      CreateRunEstimator(EstimatorMode{.core = OdometryMode::kLo}, lo, {});
  if (!odometry) return odometry.status();
  CalibrateResult result;
  const DatasetDescription& description = stream.description();
  result.lidar_stream = description.streams[sensors.lidar].name;
  result.imu_stream = description.streams[sensors.imu].name;
  result.T_imu_lidar_given = sensors.T_imu_lidar;
  result.lidar_offset_read = stream.time_offset(sensors.lidar);
  result.imu_offset_read = stream.time_offset(sensors.imu);
  return std::unique_ptr<CalibrationBranch>(
      new CalibrationBranch(std::move(*odometry), std::move(result), hold_s, options));
}

CalibrationBranch::CalibrationBranch(std::unique_ptr<RunEstimator> odometry, CalibrateResult result,
                                     double hold_s, const estimator::OnlineCalibrationOptions& options)
    : odometry_(std::move(odometry)),
      calibration_(options),
      result_(std::move(result)),
      hold_(FromSeconds(hold_s)) {}

bool CalibrationBranch::Holds(Stamp stamp) {
  if (!holding_) return false;
  if (!hold_from_) hold_from_ = stamp;
  holding_ = !BothLocked() && stamp - *hold_from_ < hold_;
  summary_.held_s = std::max(summary_.held_s, ToSeconds(stamp - *hold_from_));
  return holding_;
}

void CalibrationBranch::AddImu(const ImuSample& sample) {
  ++result_.imu_samples;
  if (odometry_) calibration_.AddImu(sample);
}

Status CalibrationBranch::AddScan(const LidarScan& scan) {
  ++result_.scans;
  if (!odometry_) return {};
  ++summary_.branch_scans;
  if (Status s = odometry_->AddScan(scan); !s.ok()) return s;
  TakePoses();
  if (BothLocked()) Finish();  // nothing left to learn
  return {};
}

bool CalibrationBranch::Restamp(LidarScan& scan) {
  if (calibration_.time_offset_locked()) {
    const Stamp offset = FromSeconds(*calibration_.time_offset_s());
    scan.stamp += offset;
    scan.end += offset;
  }
  if (last_restamped_ && scan.stamp <= *last_restamped_) {
    ++summary_.scans_left_out;
    return false;
  }
  if (calibration_.time_offset_locked() && !summary_.offset_applied_from) {
    summary_.offset_applied_from = scan.stamp;
    summary_.offset_applied_s = *calibration_.time_offset_s();
  }
  last_restamped_ = scan.stamp;
  return true;
}

std::optional<SE3> CalibrationBranch::ExtrinsicToApply() const {
  if (!calibration_.rotation_locked() || applied_) return std::nullopt;
  return SE3(*calibration_.R_imu_lidar(), result_.T_imu_lidar_given.value_or(SE3()).translation());
}

void CalibrationBranch::Applied(Stamp stamp, const Status& status) {
  applied_ = true;
  if (!status.ok()) {
    summary_.rotation_refused = status.message();
    return;
  }
  summary_.rotation_applied_at = stamp;
}

void CalibrationBranch::Finish() {
  if (!odometry_) return;
  odometry_->Finish();
  TakePoses();
  result_.time_offset_s = calibration_.time_offset_s();
  result_.time_offset_locked = calibration_.time_offset_locked();
  result_.R_imu_lidar = calibration_.R_imu_lidar();
  result_.rotation_locked = calibration_.rotation_locked();
  result_.solves = calibration_.solves();
  for (const std::string& w : odometry_->warnings()) result_.warnings.push_back(w);
  odometry_.reset();
}

void CalibrationBranch::TakePoses() {
  for (const Keyframe& k : odometry_->TakeFinished()) {
    calibration_.AddLidarOrientation(k.stamp, k.T_world_body.so3());
    if (result_.poses++ == 0) result_.first_pose = k.stamp;
    result_.last_pose = k.stamp;
  }
  odometry_->TakeStepTimes();
  odometry_->TakeEvents();
}

void RestampEarlierPoses(Trajectory& trajectory, const OnlineCalibrationSummary& summary) {
  if (!summary.offset_applied_from) return;
  const Stamp offset = FromSeconds(summary.offset_applied_s);
  for (Stamp& stamp : trajectory.stamps)
    if (stamp < *summary.offset_applied_from) stamp += offset;
}

}  // namespace uf::pipeline
