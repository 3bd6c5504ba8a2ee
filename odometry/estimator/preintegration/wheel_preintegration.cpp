#include "odometry/estimator/preintegration/wheel_preintegration.h"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <sstream>
#include <string>

namespace uf::estimator {
namespace {

bool Finite(const WheelSample& s) { return s.linear_velocity.allFinite() && s.angular_velocity.allFinite(); }

// Linear interpolation of two samples at t (a.stamp <= t <= b.stamp, a.stamp < b.stamp).
WheelSample Interpolate(const WheelSample& a, const WheelSample& b, Stamp t) {
  const double s = static_cast<double>(t - a.stamp) / static_cast<double>(b.stamp - a.stamp);
  WheelSample out;
  out.stamp = t;
  out.linear_velocity = (1.0 - s) * a.linear_velocity + s * b.linear_velocity;
  out.angular_velocity = (1.0 - s) * a.angular_velocity + s * b.angular_velocity;
  return out;
}

std::string Interval(Stamp from, Stamp to) {
  std::ostringstream text;  // (not "[" + std::to_string: GCC 12 warns falsely about it, -Wrestrict)
  text << "[" << from << ", " << to << "] ns";
  return text.str();
}

// Says how the wheel stamps relate to the interval's clock, when they differ.
std::string OffsetNote(const WheelFactorConfig& config) {
  if (FromSeconds(config.time_offset_s) == 0) return "";
  std::ostringstream note;
  note << " (estimator time = wheel stamp + time_offset_s " << config.time_offset_s << " s)";
  return note.str();
}

}  // namespace

std::span<const WheelSample> SamplesBracketing(std::span<const WheelSample> samples, Stamp begin, Stamp end) {
  if (samples.empty() || samples.front().stamp > begin || samples.back().stamp < end) return {};
  const auto is_before = [](const WheelSample& s, Stamp t) { return s.stamp < t; };
  const auto is_after = [](Stamp t, const WheelSample& s) { return t < s.stamp; };
  const auto first = std::upper_bound(samples.begin(), samples.end(), begin, is_after) - 1;
  const auto last = std::lower_bound(first, samples.end(), end, is_before);
  return {first, last + 1};
}

WheelPreintegration::WheelPreintegration(const WheelFactorConfig& config, Stamp from, Stamp to)
    : from_(from), to_(to) {
  const double v = config.forward_velocity_density, v_nh = config.nonholonomic_velocity_density;
  const double w_rp = config.roll_pitch_rate_density, w = config.yaw_rate_density;
  noise_density_squared_ << v * v, v_nh * v_nh, v_nh * v_nh, w_rp * w_rp, w_rp * w_rp, w * w;
  oscillation_tilt_ =
      2.0 * kSuspensionTiltTime_s * config.suspension_tilt_sigma * config.suspension_tilt_sigma;
  manoeuvre_tilt_ = 2.0 * kTiltManoeuvreTime_s * config.tilt_per_acceleration * config.tilt_per_acceleration;
}

Expected<WheelPreintegration> WheelPreintegration::Between(const std::vector<WheelSample>& samples,
                                                           Stamp from, Stamp to,
                                                           const WheelFactorConfig& config) {
  if (Status status = config.Validate(); !status.ok()) return status;
  if (to <= from) {
    return Status::Error("wheel preintegration: the interval must end after it starts, got " +
                         Interval(from, to));
  }
  // Work on the wheel's clock: t_wheel = t - offset (the shift changes no dt).
  const Stamp offset = FromSeconds(config.time_offset_s);
  const Stamp begin = from - offset, end = to - offset;
  if (samples.empty() || samples.front().stamp > begin || samples.back().stamp < end) {
    std::ostringstream message;
    message << "wheel preintegration: the wheel samples do not cover " << Interval(from, to);
    if (samples.empty()) {
      message << ": there are none";
    } else {
      message << ": they span " << Interval(samples.front().stamp + offset, samples.back().stamp + offset);
    }
    message << OffsetNote(config);
    return Status::Error(message.str());
  }

  const std::span<const WheelSample> used = SamplesBracketing(samples, begin, end);
  const auto first = used.begin(), last = used.end() - 1;
  const Stamp max_gap = FromSeconds(config.max_gap_s);
  for (auto it = first; it <= last; ++it) {
    if (!Finite(*it)) {
      return Status::Error("wheel preintegration: non-finite velocity in the wheel sample stamped " +
                           std::to_string(it->stamp) + " ns, inside " + Interval(from, to) +
                           OffsetNote(config));
    }
    if (it == last) break;
    const Stamp step = (it + 1)->stamp - it->stamp;
    if (step <= 0) {
      return Status::Error("wheel preintegration: wheel stamps must increase, got " +
                           std::to_string(it->stamp) + " then " + std::to_string((it + 1)->stamp) + " ns");
    }
    if (step > max_gap) {
      std::ostringstream message;
      message << "wheel preintegration: gap of " << ToSeconds(step) << " s between the wheel samples stamped "
              << it->stamp << " and " << (it + 1)->stamp << " ns inside " << Interval(from, to)
              << OffsetNote(config) << ", more than max_gap_s " << config.max_gap_s << " s";
      return Status::Error(message.str());
    }
  }

  WheelPreintegration result(config, from, to);
  result.longitudinal_acceleration_ =
      (last->linear_velocity.x() - first->linear_velocity.x()) / ToSeconds(last->stamp - first->stamp);
  WheelSample previous = first->stamp == begin ? *first : Interpolate(*first, *(first + 1), begin);
  result.num_samples_ = 1;
  for (auto it = first + 1; it < last; ++it) {  // the samples strictly inside (begin, end)
    result.Integrate(previous, *it);
    previous = *it;
  }
  result.Integrate(previous, last->stamp == end ? *last : Interpolate(*(last - 1), *last, end));
  return result;
}

void WheelPreintegration::Integrate(const WheelSample& begin, const WheelSample& end) {
  const Stamp dt_ns = end.stamp - begin.stamp;
  assert(dt_ns > 0);
  const double dt = ToSeconds(dt_ns);

  // Midpoint rotation, trapezoid position (see the header).
  const Eigen::Vector3d w = 0.5 * (begin.angular_velocity + end.angular_velocity);
  const Eigen::Matrix3d W = SO3::Exp(w * dt).matrix();
  const Eigen::Matrix3d R0 = delta_R_.matrix();
  const Eigen::Matrix3d R1 = R0 * W;

  // Error propagation (header): e = [dp; dtheta], n = [n_v; n_w], noise variance density^2 / dt.
  const Eigen::Matrix3d Jr = RightJacobianSO3(w * dt);
  const Eigen::Matrix3d R1_v1 = R1 * Hat(end.linear_velocity);
  Matrix6d F = Matrix6d::Identity();
  F.block<3, 3>(kWheelRotation, kWheelRotation) = W.transpose();
  F.block<3, 3>(kWheelPosition, kWheelRotation) =
      -0.5 * dt * (R0 * Hat(begin.linear_velocity) + R1_v1 * W.transpose());
  Matrix6d G = Matrix6d::Zero();
  G.block<3, 3>(kWheelRotation, 3) = -Jr * dt;
  G.block<3, 3>(kWheelPosition, 0) = -0.5 * dt * (R0 + R1);
  G.block<3, 3>(kWheelPosition, 3) = 0.5 * dt * dt * R1_v1 * Jr;
  const Matrix6d FP = F * covariance_;
  covariance_.noalias() = FP * F.transpose();
  // The step's noise: the lateral and vertical densities grow with the speed (the body's tilt, see the
  // header and wheel_factor_config.h).
  const double speed = 0.5 * std::abs(begin.linear_velocity.x() + end.linear_velocity.x());
  const double lateral_acceleration = speed * w.z();
  Eigen::Matrix<double, 6, 1> density_squared = noise_density_squared_;
  density_squared(1) +=
      speed * speed * (oscillation_tilt_ + manoeuvre_tilt_ * lateral_acceleration * lateral_acceleration);
  density_squared(2) +=
      speed * speed *
      (oscillation_tilt_ + manoeuvre_tilt_ * longitudinal_acceleration_ * longitudinal_acceleration_);
  covariance_.noalias() += G * (density_squared / dt).asDiagonal() * G.transpose();

  delta_p_ += 0.5 * dt * (R0 * begin.linear_velocity + R1 * end.linear_velocity);
  delta_R_ = SO3(R1);
  sum_dt_ += dt_ns;
  ++num_samples_;
}

}  // namespace uf::estimator
