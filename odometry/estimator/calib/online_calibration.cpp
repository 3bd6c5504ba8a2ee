#include "odometry/estimator/calib/online_calibration.h"

#include <algorithm>
#include <cmath>

#include "odometry/estimator/calib/calibration_consensus.h"
#include "odometry/types/printf_text.h"

namespace uf::estimator {
namespace {

constexpr double kDegree = 3.14159265358979323846 / 180.0;

}  // namespace

std::optional<Eigen::Vector3d> MeanGyroRate(std::span<const RateSample> gyro, double a, double b) {
  if (gyro.empty() || !(b > a) || a < gyro.front().t || b > gyro.back().t) return std::nullopt;
  auto it =
      std::upper_bound(gyro.begin(), gyro.end(), a, [](double t, const RateSample& s) { return t < s.t; });
  std::size_t k = static_cast<std::size_t>(std::max<std::ptrdiff_t>(it - gyro.begin() - 1, 0));
  // A sample is the rate at its stamp; between two samples the rate is taken as linear, so the mean over a
  // piece [t, end] is the rate at its middle (the midpoint rule of the IMU preintegration). Holding each
  // sample until the next instead lags by half a sample, which shows as a rotation: on simulated wild
  // drives 0.2 deg about the vertical per 2.5 ms (docs/METHOD.md, "Online spatiotemporal calibration").
  // The track covers [a, b] and increases, so while t < b there is a sample after k, and t < its stamp.
  SO3 R;
  for (double t = a; t < b; ++k) {
    const RateSample &s0 = gyro[k], &s1 = gyro[k + 1];
    const double end = std::min(b, s1.t), mid = 0.5 * (t + end);
    R = R * SO3::Exp((s0.omega + (s1.omega - s0.omega) * ((mid - s0.t) / (s1.t - s0.t))) * (end - t));
    t = end;
  }
  return (R.Log() / (b - a)).eval();
}

OnlineCalibration::OnlineCalibration(const OnlineCalibrationOptions& options) : options_(options) {}

double OnlineCalibration::Seconds(Stamp stamp) {
  if (!origin_) origin_ = stamp;
  return ToSeconds(stamp - *origin_);
}

void OnlineCalibration::AddImu(const ImuSample& sample) {
  if (!sample.gyro.allFinite()) return;
  const double t = Seconds(sample.stamp);
  if (!gyro_.empty() && t <= gyro_.back().t) return;  // keep the track increasing
  gyro_.push_back({t, sample.gyro});
  // The LiDAR poses trim the gyro (they may come later than the IMU: an odometry releases a pose when it
  // leaves its window, the last ones at the end of the data); this bound only holds memory when they stop.
  while (!gyro_.empty() && gyro_.front().t < t - kMaxImuLead_s - GyroKept()) gyro_.pop_front();
}

double OnlineCalibration::GyroKept() const {
  return std::max(options_.window_s, options_.rotation_window_s) + 2 * options_.time.max_shift_s + 1.0;
}

void OnlineCalibration::AddLidarOrientation(Stamp stamp, const SO3& R_world_lidar) {
  if (!R_world_lidar.matrix().allFinite()) return;
  const double t = Seconds(stamp);
  if (!lidar_t_.empty() && t <= lidar_t_.back()) return;
  lidar_t_.push_back(t);
  lidar_R_.push_back(R_world_lidar);
  while (!lidar_t_.empty() &&
         lidar_t_.front() < t - std::max(options_.window_s, options_.rotation_window_s)) {
    lidar_t_.pop_front();
    lidar_R_.pop_front();
  }
  // Keep the longer window plus the search range behind the newest pose.
  while (!gyro_.empty() && gyro_.front().t < t - GyroKept()) gyro_.pop_front();
  if (time_locked_ && rotation_locked_) return;
  if (last_solve_t_ && t - *last_solve_t_ < options_.solve_every_s) return;
  if (t - lidar_t_.front() < options_.time.min_overlap_s + 2 * options_.time.max_shift_s) return;
  if (lidar_t_.size() >= 2) {  // the sharp-turn guard (see online_calibration.h)
    const std::size_t n = lidar_t_.size();
    const double rate = (lidar_R_[n - 2].inverse() * lidar_R_[n - 1]).angle() / (t - lidar_t_[n - 2]);
    if (rate > options_.max_turn_rate_deg_s * kDegree) {
      if (!waiting_for_turn_) {  // one record per turn
        CalibrationSolve wait;
        wait.stamp = stamp;
        wait.worker = time_locked_ ? CalibrationWorker::kRotation : CalibrationWorker::kTimeOffset;
        wait.reason = PrintfText("sharp turn: the LiDAR turns at %.0f deg/s > %.0f; the solve waits",
                                 rate / kDegree, options_.max_turn_rate_deg_s);
        solves_.push_back(std::move(wait));
      }
      waiting_for_turn_ = true;
      return;
    }
  }
  waiting_for_turn_ = false;
  last_solve_t_ = t;
  Solve(stamp);
}

std::optional<double> OnlineCalibration::time_offset_s() const {
  if (time_locked_) return time_locked_;
  if (!time_candidates_.empty()) return time_candidates_.back();
  return std::nullopt;
}

std::optional<SO3> OnlineCalibration::R_imu_lidar() const {
  if (rotation_locked_) return rotation_locked_;
  if (!rotation_candidates_.empty()) return rotation_candidates_.back();
  return std::nullopt;
}

std::size_t OnlineCalibration::FirstPoseWithin(double window_s) const {
  std::size_t first = 0;
  while (first + 1 < lidar_t_.size() && lidar_t_[first] < lidar_t_.back() - window_s) ++first;
  return first;
}

void OnlineCalibration::Solve(Stamp stamp) {
  const std::size_t first = FirstPoseWithin(options_.window_s);
  const std::vector<double> t(lidar_t_.begin() + first, lidar_t_.end());
  const std::vector<SO3> R(lidar_R_.begin() + first, lidar_R_.end());
  const std::vector<RateSample> gyro(gyro_.begin(), gyro_.end());
  if (!time_locked_) SolveTimeOffset(stamp, gyro, IntervalRates(t, R));
  if (!rotation_locked_) {
    if (const std::optional<double> offset = time_offset_s()) SolveRotation(stamp, gyro, *offset);
  }
}

void OnlineCalibration::SolveTimeOffset(Stamp stamp, const std::vector<RateSample>& gyro,
                                        const std::vector<RateSample>& lidar) {
  const TimeOffsetEstimate e = SearchTimeOffset(gyro, lidar, options_.time);
  CalibrationSolve solve{.stamp = stamp,
                         .worker = CalibrationWorker::kTimeOffset,
                         .accepted = e.rejected.empty(),
                         .reason = e.rejected,
                         .time_offset_s = -e.shift_s,
                         .R_imu_lidar = e.fit.R_imu_lidar,
                         .quality = e.correlation,
                         .rms_rad_s = e.fit.rms_residual};
  if (solve.accepted) {
    time_candidates_.push_back(solve.time_offset_s);
    // As for the rotation: agreeing windows may share a bias; the lock also asks for a sharp match.
    if (solve.quality >= options_.min_lock_correlation)
      time_locked_ = OffsetConsensus(time_candidates_, options_.consensus_count, options_.time_tolerance_s);
    solve.locked = time_locked_.has_value();
  }
  solves_.push_back(std::move(solve));
}

void OnlineCalibration::SolveRotation(Stamp stamp, const std::vector<RateSample>& gyro,
                                      double time_offset_s) {
  // LiDAR time t is IMU time t + offset.
  const std::size_t first = FirstPoseWithin(options_.rotation_window_s);
  const double span = lidar_t_.back() - lidar_t_[first];
  std::vector<RatePair> pairs;
  for (std::size_t i = first, j = first + 1; j < lidar_t_.size(); ++i) {
    j = std::max(j, i + 1);
    while (j + 1 < lidar_t_.size() && lidar_t_[j] - lidar_t_[i] < options_.rotation_pair_span_s) ++j;
    const double a = lidar_t_[i], b = lidar_t_[j];
    if (b - a < options_.rotation_pair_span_s) break;
    if (const std::optional<Eigen::Vector3d> imu = MeanGyroRate(gyro, a + time_offset_s, b + time_offset_s))
      pairs.push_back({(lidar_R_[i].inverse() * lidar_R_[j]).Log() / (b - a), *imu});
  }
  CalibrationSolve solve;
  solve.stamp = stamp;
  solve.worker = CalibrationWorker::kRotation;
  solve.time_offset_s = time_offset_s;
  const RotationExcitation excitation = MeasureRotationExcitation(pairs);
  solve.quality = excitation.ratio;
  if (span < options_.min_rotation_span_s) {
    solve.reason = PrintfText("%.1f s of LiDAR poses < %.1f s", span, options_.min_rotation_span_s);
  } else if (static_cast<int>(pairs.size()) < options_.min_rotation_pairs) {
    solve.reason =
        PrintfText("%.0f rotation pairs with IMU data < %.0f", pairs.size(), options_.min_rotation_pairs);
  } else if (excitation.rate_spread_rad_s < options_.min_rate_spread_rad_s) {
    solve.reason = PrintfText("too little rotation: the rate varies by %.3f rad/s < %.3f",
                              excitation.rate_spread_rad_s, options_.min_rate_spread_rad_s);
  } else if (excitation.ratio < options_.min_excitation_ratio) {
    solve.reason = PrintfText("rotation about too few axes: lambda_min / lambda_max %.3f < %.3f",
                              excitation.ratio, options_.min_excitation_ratio);
  } else {
    const RotationFit fit = FitRotationRobust(pairs, options_.rotation_huber_rad_s);
    solve.R_imu_lidar = fit.R_imu_lidar;
    solve.rms_rad_s = fit.rms_residual;
    // Pairs start at every pose and span rotation_pair_span_s: that many intervals share each stretch.
    const double overlap =
        options_.rotation_pair_span_s / (span / static_cast<double>(lidar_t_.size() - first - 1));
    solve.sigma_deg = RotationSigma(pairs, fit, overlap) / kDegree;
    if (fit.rms_residual > options_.max_rotation_rms_rad_s)
      solve.reason =
          PrintfText("residual %.3f rad/s > %.3f", fit.rms_residual, options_.max_rotation_rms_rad_s);
    else if (fit.inlier_ratio < options_.min_inlier_ratio)
      solve.reason = PrintfText("inliers %.2f < %.2f", fit.inlier_ratio, options_.min_inlier_ratio);
  }
  solve.accepted = solve.reason.empty();
  if (solve.accepted) {
    rotation_candidates_.push_back(solve.R_imu_lidar);
    // Agreeing candidates from overlapping windows share most of their data: the lock also asks that the
    // latest be certain enough on its own.
    if (solve.sigma_deg <= options_.max_lock_sigma_deg)
      rotation_locked_ = RotationConsensus(rotation_candidates_, options_.consensus_count,
                                           options_.rotation_tolerance_deg * kDegree);
    solve.locked = rotation_locked_.has_value();
  }
  solves_.push_back(std::move(solve));
}

}  // namespace uf::estimator
