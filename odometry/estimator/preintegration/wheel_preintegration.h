// Wheel odometry preintegration between two window nodes i and j: the relative motion of the wheel frame
// (the vehicle base, x forward, y left, z up) from its measured twist, for the wheel factor (wheel_factor.h).
//
// A sample k holds the twist of the wheel frame in itself: linear velocity v_k (m/s) and angular velocity
// w_k (rad/s). Each step [t_k, t_k+1], dt = t_k+1 - t_k, is integrated like the IMU's midpoint rule:
//   dR_k+1 = dR_k Exp((w_k + w_k+1) / 2 dt)
//   dp_k+1 = dp_k + (dR_k v_k + dR_k+1 v_k+1) dt / 2                (trapezoid rule)
// from dR = I, dp = 0 at t_i, so dR and dp are the rotation and position of the wheel frame at t_j in the
// wheel frame at t_i. Both rules have an error of dt^3 / 12 times the second time derivative of the
// integrand per step: T dt^2 / 12 (second order) over an interval of T seconds.
//
// Scale: a scale s multiplies the linear velocity of every sample and leaves the rotation alone. dp is linear
// in the velocities, so dp(s) = s dp exactly, and the factor applies s without integrating again.
//
// Covariance: the measured twist is the true one plus white noise n_v, n_w (densities in WheelFactorConfig,
// per axis of the wheel frame: forward, lateral, vertical; roll, pitch, yaw), one independent draw per step
// with variance density^2 / dt (the continuous-time variance density^2 T over the interval). The lateral and
// vertical densities grow with the speed by the body's tilt on its suspension (wheel_factor_config.h): per
// step, with v = |v_x| and w_z the step's means, a_lat = v w_z and a_long the mean longitudinal acceleration
// over the samples that bracket the interval (its difference over >= one node interval, not per step,
// which a quantised encoder would make noisy),
//   density_y^2 = nh^2 + 2 v^2 (tau_osc sigma^2 + tau_man (k a_lat)^2)
//   density_z^2 = nh^2 + 2 v^2 (tau_osc sigma^2 + tau_man (k a_long)^2).
// The error state
// is e = [dp_true - dp; Log(dR^T dR_true)], the wheel factor's residual at the true poses and s = 1, and each
// step propagates e_k+1 = F e_k + G n, P_k+1 = F P_k F^T + G Q G^T (P_0 = 0), with W = Exp(w dt):
//   dtheta_k+1 = W^T dtheta_k - Jr(w dt) dt n_w
//   dp_k+1     = dp_k - dt / 2 (dR_k [v_k]x dtheta_k + dR_k+1 [v_k+1]x dtheta_k+1) - dt / 2 (dR_k + dR_k+1)
//   n_v
// (first order: dR_true v ~ dR v - dR [v]x dtheta). The covariance is that of s = 1 and is not rescaled
// with s (a scale of 1.1 would make the forward-noise part 1.21 times larger: a small change of weight).
//
// Time: the wheel stamps are shifted by config.time_offset_s onto the estimator's clock; the samples must
// be sorted by stamp and cover the interval, and the samples at t_i and t_j are interpolated linearly between
// their neighbours.
#pragma once

#include <Eigen/Core>
#include <span>
#include <vector>

#include "odometry/estimator/config/wheel_factor_config.h"
#include "odometry/types/measurements.h"
#include "odometry/types/se3.h"
#include "odometry/types/so3.h"
#include "odometry/types/stamp.h"
#include "odometry/types/status.h"

namespace uf::estimator {

// Block offsets of the error state, the covariance and the wheel factor's residual.
constexpr int kWheelPosition = 0, kWheelRotation = 3;

// The samples (sorted by stamp) an interval [begin, end] of their own clock uses: from the last at or before
// begin to the first at or after end. Empty when they do not cover it.
std::span<const WheelSample> SamplesBracketing(std::span<const WheelSample> samples, Stamp begin, Stamp end);

class WheelPreintegration {
 public:
  // Integrates the samples (sorted by stamp, on the wheel's clock) over [from, to] (estimator clock). Fails
  // naming the stamps when to <= from, when the shifted samples do not cover [from, to], when a step between
  // the samples used (those bracketing from and to included) is longer than config.max_gap_s or does not
  // increase, when a sample used is not finite (readers should drop those), or when the config does not
  // validate (its message).
  static Expected<WheelPreintegration> Between(const std::vector<WheelSample>& samples, Stamp from, Stamp to,
                                               const WheelFactorConfig& config);

  // The motion of the wheel frame over [from, to] at unit scale: dR = R_wheel(from)^T R_wheel(to) and
  // dp = R_wheel(from)^T (p_wheel(to) - p_wheel(from)).
  const SO3& delta_R() const { return delta_R_; }
  const Eigen::Vector3d& delta_p() const { return delta_p_; }
  Eigen::Vector3d ScaledDeltaP(double scale) const { return scale * delta_p_; }  // exact, see above
  // Covariance (6x6, order [dp; dtheta], at s = 1).
  const Matrix6d& covariance() const { return covariance_; }

  Stamp from() const { return from_; }  // estimator clock, ns
  Stamp to() const { return to_; }
  Stamp sum_dt() const { return sum_dt_; }  // ns (= to - from)
  double sum_dt_seconds() const { return ToSeconds(sum_dt_); }
  int num_samples() const { return num_samples_; }  // integrated, the interpolated ends included

 private:
  WheelPreintegration(const WheelFactorConfig& config, Stamp from, Stamp to);
  void Integrate(const WheelSample& begin, const WheelSample& end);  // one step, stamps increasing

  Eigen::Matrix<double, 6, 1> noise_density_squared_;  // [v_x, v_y, v_z, w_x, w_y, w_z], at standstill
  // 2 tau_osc sigma^2 and 2 tau_man k^2 (see above), and the interval's longitudinal acceleration, m/s^2.
  double oscillation_tilt_ = 0, manoeuvre_tilt_ = 0, longitudinal_acceleration_ = 0;
  Stamp from_ = 0, to_ = 0;
  Stamp sum_dt_ = 0;
  int num_samples_ = 0;
  SO3 delta_R_;
  Eigen::Vector3d delta_p_ = Eigen::Vector3d::Zero();
  Matrix6d covariance_ = Matrix6d::Zero();
};

}  // namespace uf::estimator
