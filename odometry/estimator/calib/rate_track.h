// Angular-rate tracks of the LiDAR-IMU calibration workers (online_calibration.h): the LiDAR's from its
// odometry poses, the IMU's from its gyro, both as mean rates over the LiDAR's scan interval so that the two
// are comparable (docs/METHOD.md, "Online spatiotemporal calibration").
//
//   LiDAR   w_L(t_mid) = Log(R_i^T R_{i+1}) / (t_{i+1} - t_i), in the LiDAR frame, stamped at the middle of
//           each interval between consecutive poses (the mean rate over the interval);
//   IMU     the gyro averaged over a centred window of the median LiDAR interval (a box filter: the mean
//           rate over an interval of that length, as the LiDAR's is);
//   between samples, cubic Hermite interpolation with Catmull-Rom tangents (the paper's spline of the
//   LiDAR motion cues), linear at the ends.
// Times are seconds relative to an origin chosen by the caller (doubles keep sub-microsecond resolution
// over days that way).
#pragma once

#include <Eigen/Core>
#include <optional>
#include <span>
#include <vector>

#include "odometry/types/so3.h"

namespace uf::estimator {

struct RateSample {
  double t = 0.0;                                   // s
  Eigen::Vector3d omega = Eigen::Vector3d::Zero();  // rad/s
};

// The mean rates between consecutive orientations (stamps t, strictly increasing); empty for fewer than 2.
std::vector<RateSample> IntervalRates(std::span<const double> t, std::span<const SO3> R_world_sensor);

// Each sample replaced by the mean of the samples within +-width/2 of it (the track unchanged for width <=
// 0).
std::vector<RateSample> BoxSmoothed(std::span<const RateSample> track, double width);

// The track's rate at t (see the top of this file); none outside [front.t, back.t] or for an empty track.
std::optional<Eigen::Vector3d> InterpolateRate(std::span<const RateSample> track, double t);

// The median spacing of the samples (0 for fewer than 2).
double MedianSpacing(std::span<const RateSample> track);

}  // namespace uf::estimator
