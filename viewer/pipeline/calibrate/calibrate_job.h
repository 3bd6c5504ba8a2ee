// `ultrafusion calibrate` as a job: the LiDAR-IMU time offset and rotation of a dataset, estimated by the
// online calibration workers (odometry/estimator/calib/online_calibration.h) on a LiDAR-only odometry pass
// (the LiDAR's own motion, free of the IMU and of the extrinsic under test), and the outputs:
//   calibration_estimated.yaml   the calibration file format (odometry/io/calibration_file.h), body = the
//   IMU:
//                                the IMU at identity, the LiDAR at (R_IL estimated or given, t_IL given, or
//                                0 when the dataset has no extrinsic) with its time offset (the one the
//                                stream was read with + the estimated one); not written when there is
//                                neither an extrinsic nor an estimated rotation
//   calibration_solves.csv       every solve of both workers: stamp, worker, accepted, offset, rotation,
//                                quality, residual, locked, reason
//   plots/calibration_time_offset.png, plots/calibration_rotation.png   the accepted estimates over time
#pragma once

#include <filesystem>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "odometry/estimator/calib/online_calibration.h"
#include "odometry/estimator/config/lidar_odometry_config.h"
#include "odometry/types/se3.h"
#include "viewer/app/config/dataset_config.h"

namespace uf::pipeline {

struct CalibrateRequest {
  std::filesystem::path dataset;
  app::DatasetConfig dataset_config;
  estimator::LidarOdometryConfig lo_config;  // the LiDAR-only pass
  estimator::OnlineCalibrationOptions options;
};

struct CalibrateResult {
  std::string lidar_stream, imu_stream;
  std::optional<SE3> T_imu_lidar_given;              // from the dataset's calibration
  Stamp lidar_offset_read = 0, imu_offset_read = 0;  // ns, what dataset.time_offsets_s added to the stamps
  std::optional<double> time_offset_s;  // estimated, on top of the offsets read with (online_calibration.h)
  bool time_offset_locked = false;
  std::optional<SO3> R_imu_lidar;  // estimated
  bool rotation_locked = false;
  std::vector<estimator::CalibrationSolve> solves;
  std::int64_t scans = 0, poses = 0, imu_samples = 0;
  Stamp first_pose = 0, last_pose = 0;  // the odometry's first and last pose stamps
  std::vector<std::string> warnings;  // the reader's and the odometry's

  // The LiDAR's offset to write (read + estimated; read alone without an estimate), s.
  double LidarTimeOffset() const;
  // Whether the estimated rotation replaces the given one: when it locked; when it did not, only when the
  // given one lies more than 3 standard deviations (the latest accepted candidate's RotationSigma) from it,
  // i.e. the data contradict the given rotation (an uncertain candidate near a good given rotation would
  // only add its own error: simulated urban, seed 2, 0.43 deg off with a 0.6 deg sigma doubled the LIO's
  // ATE). Always without a given extrinsic.
  bool UsesEstimatedRotation() const;
  // T_imu_lidar to write: the rotation UsesEstimatedRotation picks, with the given translation.
  std::optional<SE3> TImuLidar() const;
  // The latest accepted rotation candidate's standard deviation (RotationSigma), deg; 0 without one.
  double LatestRotationSigmaDeg() const;
  // The estimated rotation's angle from the given one (identity when none was given), deg; 0 without an
  // estimate.
  double RotationFromGivenDeg() const;
  // The reason of the worker's last refused solve ("" when it never refused).
  std::string LastRefusal(estimator::CalibrationWorker worker) const;
};

// Progress: the scans read so far.
using CalibrateProgress = std::function<void(std::int64_t scans)>;

// Errors: the dataset's (unreadable, damaged), one without a LiDAR or an IMU stream (naming what it has),
// and the odometry's configuration.
Expected<CalibrateResult> RunCalibrate(const CalibrateRequest& request, const CalibrateProgress& progress);

// Writes the files listed at the top of this file into `out` (created when missing); returns their names.
Expected<std::vector<std::string>> WriteCalibrateOutputs(const std::filesystem::path& out,
                                                         const CalibrateResult& result);

}  // namespace uf::pipeline
