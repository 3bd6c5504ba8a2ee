// Online LiDAR-IMU calibration: the two workers of the method (docs/METHOD.md, "Online spatiotemporal
// calibration"; paper Sec. III-E) fed with the IMU and the LiDAR odometry's orientations in time order.
//
// Every solve_every_s of LiDAR time:
//   time offset  (until locked) SearchTimeOffset on the gyro and the LiDAR's interval rates of the last
//                window_s; an accepted candidate joins the history, and the offset locks by OffsetConsensus
//                once the latest candidate's correlation is at least min_lock_correlation (on simulated urban
//                driving at up to 12 deg/s, early candidates at 0.87-0.93 agreed within 2 ms while 5-7 ms
//                off; later ones at 0.97-0.998 were within 1 ms).
//   rotation     (until locked, once a time offset has been accepted) on the last rotation_window_s, once
//                they span min_rotation_span_s (three rotational degrees of freedom from small, noisy
//                rotations need more data than one offset; with 0.1 deg of pose noise 12 s gave candidates
//                0.3-0.7 deg off that still agreed with each other): pairs of mean rates over the
//                interval from each LiDAR pose i to the pose j about rotation_pair_span_s later:
//                w_L = Log(R_i^T R_j) / dt against the gyro integrated over the same interval moved onto
//                the IMU clock (R_I = prod Exp(w dt), w_I = Log(R_I) / dt). Log(R_IL A R_IL^T) = R_IL Log(A)
//                holds exactly, so the span can be long, and the pose noise then weighs less against the
//                rotation; FitRotationRobust, accepted when the excitation
//                (MeasureRotationExcitation), the residual and the inlier ratio pass; locks by
//                RotationConsensus once the latest candidate's standard deviation (RotationSigma, with
//                overlap = rotation_pair_span_s / the LiDAR interval) is at most max_lock_sigma_deg. That
//                sigma is conservative (the overlap counts the pairs as fully correlated): on simulated
//                drives the errors were a third to a half of it (wild: sigma 0.15-0.23 deg, errors
//                0.02-0.15 deg; urban, which turns mostly about its vertical, over 30 s: sigma 0.36-0.40
//                deg, errors 0.15-0.26 deg, not locked; over 60 s locked within 0.07-0.20 deg).
// A solve that falls due while the LiDAR turns faster than max_turn_rate_deg_s over its newest interval
// (a sharp turn, the paper's turning guard) waits for the first pose after the turn: the odometry's poses
// are at their least reliable there (the sweep's deskew and the registration), and a window cut in the
// middle of a turn holds only part of its rate profile. The wait is one solve record ("sharp turn").
// The workers never touch the estimator: whoever owns them reads the estimates and applies them (the
// `calibrate` command writes calibration_estimated.yaml). What is not done here: the paper's acceleration
// cue for the time offset and the translation of the extrinsic.
#pragma once

#include <deque>
#include <optional>
#include <string>
#include <vector>

#include "odometry/estimator/calib/time_offset_search.h"
#include "odometry/types/measurements.h"
#include "odometry/types/so3.h"
#include "odometry/types/stamp.h"

namespace uf::estimator {

struct OnlineCalibrationOptions {
  double window_s = 12.0;      // of both streams, per solve
  double solve_every_s = 2.0;  // LiDAR time between solves
  double max_turn_rate_deg_s = 60.0;  // a solve due while the LiDAR turns faster waits (the sharp-turn guard)
  TimeOffsetSearchOptions time;
  double rotation_window_s = 40.0;       // of both streams, per rotation solve
  double min_rotation_span_s = 20.0;     // LiDAR time the rotation pairs must span
  double rotation_pair_span_s = 0.5;     // of the rotation pairs (at least one LiDAR interval)
  int min_rotation_pairs = 40;           // pairs in the window
  double min_excitation_ratio = 0.05;    // lambda_min / lambda_max of the rate axes' scatter
  double min_rate_spread_rad_s = 0.05;   // RMS variation of the LiDAR's rate about its mean
  double rotation_huber_rad_s = 0.02;    // least Huber threshold of the rate residual (FitRotationRobust)
  double max_rotation_rms_rad_s = 0.05;  // of the inliers' residuals
  double min_inlier_ratio = 0.8;
  double max_lock_sigma_deg = 0.25;  // the rotation locks only when its standard deviation (RotationSigma) is
                                     // at most this
  int consensus_count = 3;  // agreeing accepted candidates that lock a value
  double time_tolerance_s = 0.002;
  double min_lock_correlation = 0.95;  // the offset locks only on a candidate whose correlation is this high
  double rotation_tolerance_deg = 0.2;
};

enum class CalibrationWorker { kTimeOffset, kRotation };

// One solve of one worker.
struct CalibrationSolve {
  Stamp stamp = 0;  // the LiDAR stamp that ended the window
  CalibrationWorker worker = CalibrationWorker::kTimeOffset;
  bool accepted = false;
  std::string reason;          // why not accepted
  double time_offset_s = 0.0;  // the candidate (time worker) or the offset the pairs used (rotation worker)
  SO3 R_imu_lidar;             // the candidate (rotation worker) or the rotation fitted with the offset
  double quality = 0.0;        // correlation (time worker), excitation ratio (rotation worker)
  double rms_rad_s = 0.0;      // residual of the rate fit
  double sigma_deg = 0.0;      // rotation worker: the rotation's largest standard deviation (RotationSigma)
  bool locked = false;         // this solve locked the worker's value
};

class OnlineCalibration {
 public:
  explicit OnlineCalibration(const OnlineCalibrationOptions& options = {});

  // Samples and orientations that are not finite, or not after the previous one, are left out.
  void AddImu(const ImuSample& sample);
  // One orientation of the LiDAR odometry (LiDAR frame in its world) at the LiDAR's stamp, in time order;
  // solves when due.
  void AddLidarOrientation(Stamp stamp, const SO3& R_world_lidar);

  // time_offset = -delta (time_offset_search.h): add it to LiDAR stamps to put them on the IMU clock. The
  // locked value, else the latest accepted candidate; none before the first.
  std::optional<double> time_offset_s() const;
  bool time_offset_locked() const { return time_locked_.has_value(); }
  std::optional<SO3> R_imu_lidar() const;
  bool rotation_locked() const { return rotation_locked_.has_value(); }
  const std::vector<CalibrationSolve>& solves() const { return solves_; }

 private:
  void Solve(Stamp stamp);
  // `gyro`: the held gyro track, shared by both workers' solves.
  void SolveTimeOffset(Stamp stamp, const std::vector<RateSample>& gyro,
                       const std::vector<RateSample>& lidar);
  void SolveRotation(Stamp stamp, const std::vector<RateSample>& gyro, double time_offset_s);
  double Seconds(Stamp stamp);
  // Seconds of gyro kept behind the newest LiDAR pose; and how far the gyro may run ahead of the poses.
  double GyroKept() const;
  static constexpr double kMaxImuLead_s = 120.0;
  // The first held LiDAR pose within window_s of the newest.
  std::size_t FirstPoseWithin(double window_s) const;

  OnlineCalibrationOptions options_;
  std::optional<Stamp> origin_;
  std::deque<RateSample> gyro_;  // seconds from origin_, the IMU's raw rates
  std::deque<double> lidar_t_;
  std::deque<SO3> lidar_R_;
  std::optional<double> last_solve_t_;
  bool waiting_for_turn_ = false;  // a due solve waits for a sharp turn to end (recorded once)
  std::vector<double> time_candidates_;
  std::vector<SO3> rotation_candidates_;
  std::optional<double> time_locked_;
  std::optional<SO3> rotation_locked_;
  std::vector<CalibrationSolve> solves_;
};

// The gyro integrated over [a, b] (seconds, the track's clock), the rate linear between samples (midpoint
// rule): Log(prod Exp(w dt)) / (b - a). None when the track does not cover [a, b].
std::optional<Eigen::Vector3d> MeanGyroRate(std::span<const RateSample> gyro, double a, double b);

}  // namespace uf::estimator
