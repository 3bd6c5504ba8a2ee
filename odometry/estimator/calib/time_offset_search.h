// The LiDAR-IMU time offset from angular rates (docs/METHOD.md, "Online spatiotemporal calibration"; paper
// Sec. III-E). delta is the search shift: the IMU at t is matched with the LiDAR's motion at t + delta, so
// LiDAR stamps that run d late (stamp = true time + d) give delta = d, and the offset that puts LiDAR
// stamps on the IMU clock is time_offset = -delta (the sign of dataset.time_offsets_s).
//
//   coarse  delta_c = argmin over a grid in [-max_shift, max_shift] of the robust cost J below, on every
//           k-th IMU sample (about four per LiDAR interval) among those every shift can match, refined by a
//           parabola through the minimum. (The paper's coarse step maximizes the correlation of the rate
//           norms; a few failed registrations, spikes in two interval rates each, moved that peak by
//           10-30 ms in the tests, where the Huber cost stays put.)
//   fine    delta = argmin over delta_c +- 2 coarse steps of J(delta) = (1/N) sum_k rho_H(|w_I(t_k) -
//           R w_L(t_k + delta) - b|) on every IMU sample, R and b fitted at each delta
//           (FitRotationRobust), again with a parabola through the minimum;
//   confidence  the Pearson correlation of |w_I(t_k)| and |w_L(t_k + delta)| at the result;
//   accept  when the overlap and the excitation (standard deviation of |w_I|) are large enough, the
//           correlation reaches min_correlation, the shift is not at the end of the search range and
//           J(delta) <= J(0).
// Both tracks are mean rates over the LiDAR's scan interval (rate_track.h): the IMU's gyro is box-filtered
// here to the median spacing of the LiDAR track.
#pragma once

#include <span>
#include <string>

#include "odometry/estimator/calib/rate_track.h"
#include "odometry/estimator/calib/rotation_alignment.h"

namespace uf::estimator {

struct TimeOffsetSearchOptions {
  double max_shift_s = 0.5;          // search range, +-
  double coarse_step_s = 0.002;      // grid of the correlation
  double fine_step_s = 0.0002;       // grid of the robust cost
  double min_overlap_s = 5.0;        // IMU time every shift can match
  double min_correlation = 0.6;      // of the rate norms at the peak
  double min_rate_std_rad_s = 0.02;  // excitation: standard deviation of |w_I| over the overlap
  double huber_rad_s = 0.05;         // Huber threshold of the vector residual
};

struct TimeOffsetEstimate {
  double shift_s = 0.0;  // delta (see the top of this file); time_offset = -delta
  double correlation = 0.0;
  double cost = 0.0, cost_at_zero = 0.0;  // J(delta), J(0)
  double overlap_s = 0.0;
  double rate_std_rad_s = 0.0;
  RotationFit fit;       // R_IL and b_g fitted at delta
  std::string rejected;  // why the estimate is not to be used; empty when accepted
};

// `gyro`: the IMU's raw rates (its frame); `lidar`: the LiDAR's interval rates (IntervalRates). Same time
// origin.
TimeOffsetEstimate SearchTimeOffset(std::span<const RateSample> gyro, std::span<const RateSample> lidar,
                                    const TimeOffsetSearchOptions& options);

}  // namespace uf::estimator
