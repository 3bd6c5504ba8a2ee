#include "odometry/sim/wheel_model.h"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <numbers>
#include <optional>
#include <random>
#include <sstream>
#include <string>
#include <utility>

#include "odometry/sim/sampling.h"

namespace uf::sim {
namespace {

Status CheckWindow(const std::string& name, const TimeWindow& window) {
  if (window.end >= window.begin) return Status();
  return Status::Error(name + ": end " + FormatSeconds(window.end) + " s is before begin " +
                       FormatSeconds(window.begin) + " s");
}

}  // namespace

Status WheelConfig::Validate() const {
  if (!std::isfinite(rate_hz) || rate_hz <= 0.0 || rate_hz > 10000.0) {
    return Status::Error("wheel.rate_hz: must be in (0, 10000], got " + NumberText(rate_hz));
  }
  const std::pair<const char*, double> positive[] = {{"wheel_radius_m", wheel_radius_m},
                                                     {"baseline_m", baseline_m}};
  for (const auto& [name, value] : positive) {
    if (!std::isfinite(value) || value <= 0.0) {
      return Status::Error(std::string("wheel.") + name + ": must be finite and > 0, got " +
                           NumberText(value));
    }
  }
  const std::pair<const char*, double> relative[] = {{"radius_error", radius_error},
                                                     {"baseline_error", baseline_error}};
  for (const auto& [name, value] : relative) {
    if (!std::isfinite(value) || value <= -1.0) {
      return Status::Error(std::string("wheel.") + name + ": must be finite and > -1, got " +
                           NumberText(value));
    }
  }
  const std::pair<const char*, double> non_negative[] = {
      {"encoder_resolution_ticks", encoder_resolution_ticks},
      {"wheel_speed_noise_std", wheel_speed_noise_std}};
  for (const auto& [name, value] : non_negative) {
    if (!std::isfinite(value) || value < 0.0) {
      return Status::Error(std::string("wheel.") + name + ": must be finite and >= 0, got " +
                           NumberText(value));
    }
  }
  for (std::size_t i = 0; i < slips.size(); ++i) {
    const std::string name = "wheel.slips[" + std::to_string(i) + "]";
    if (Status status = CheckWindow(name + ".window", slips[i].first); !status.ok()) return status;
    if (!std::isfinite(slips[i].second) || slips[i].second < -1.0) {
      return Status::Error(name + ".ratio: must be finite and >= -1, got " + NumberText(slips[i].second));
    }
  }
  for (std::size_t i = 0; i < floats.size(); ++i) {
    if (Status status = CheckWindow("wheel.floats[" + std::to_string(i) + "]", floats[i]); !status.ok()) {
      return status;
    }
  }
  return Status();
}

Expected<WheelSimulator> WheelSimulator::Create(TrajectorySpline trajectory, const SE3& T_body_wheel,
                                                const WheelConfig& config, std::uint64_t seed) {
  if (Status status = config.Validate(); !status.ok()) return status;
  if (!T_body_wheel.matrix().allFinite()) return Status::Error("wheel extrinsic T_body_wheel must be finite");
  return WheelSimulator(std::move(trajectory), T_body_wheel, config, seed);
}

WheelSimulator::WheelSimulator(TrajectorySpline trajectory, const SE3& T_body_wheel,
                               const WheelConfig& config, std::uint64_t seed)
    : trajectory_(std::move(trajectory)), T_body_wheel_(T_body_wheel), config_(config), seed_(seed) {}

WheelTruth WheelSimulator::TrueMotion(Stamp t) const {
  const TrajectorySpline::State body = trajectory_.Evaluate(t);
  const Eigen::Vector3d& omega = body.angular_velocity_body;
  const Eigen::Matrix3d& R_body_wheel = T_body_wheel_.rotation();
  // Velocity of the wheel origin p_body + R_world_body r: d/dt gives v_body + R_world_body (omega x r); in
  // the wheel frame v_wheel = R_body_wheel^T (R_world_body^T v_world_body + omega x r).
  const Eigen::Vector3d velocity_body = body.T_world_body.rotation().transpose() * body.velocity_world +
                                        omega.cross(T_body_wheel_.translation());
  WheelTruth truth;
  truth.stamp = t;
  truth.linear_velocity = R_body_wheel.transpose() * velocity_body;
  truth.angular_velocity = R_body_wheel.transpose() * omega;
  return truth;
}

Eigen::Vector2d WheelSimulator::WheelRates(Stamp t) const {
  const WheelTruth truth = TrueMotion(t);
  const double v = truth.linear_velocity.x();
  const double w = truth.angular_velocity.z();
  // Ground speeds v -+ w b / 2 of the left and right contact points, over the true radius, times the slip.
  double slip_factor = 1.0;
  for (const auto& [window, ratio] : config_.slips) {
    if (window.Contains(t)) slip_factor *= 1.0 + ratio;
  }
  const double half_baseline = 0.5 * config_.baseline_m;
  return slip_factor / config_.wheel_radius_m * Eigen::Vector2d(v - w * half_baseline, v + w * half_baseline);
}

Expected<SimulatedWheel> WheelSimulator::Generate(Stamp begin, Stamp end) const {
  if (Status s = sim::CheckSampleInterval("wheel", trajectory_, begin, end, config_.rate_hz); !s.ok())
    return s;
  const long double period_ns = 1e9L / static_cast<long double>(config_.rate_hz);

  // The frozen rates of float window i: those of the last grid sample before the window (k may be negative:
  // the grid extended backwards), clamped to the start of the trajectory. Computed when first needed.
  std::vector<std::optional<Eigen::Vector2d>> frozen(config_.floats.size());
  const auto frozen_rates = [&](std::size_t i) {
    if (!frozen[i]) {
      const Stamp window_begin = config_.floats[i].begin;
      auto k = static_cast<std::int64_t>(std::floor((window_begin - begin) / period_ns));
      while (GridStamp(begin, period_ns, k) >= window_begin) --k;
      while (GridStamp(begin, period_ns, k + 1) < window_begin) ++k;
      frozen[i] = WheelRates(std::max(GridStamp(begin, period_ns, k), trajectory_.begin()));
    }
    return *frozen[i];
  };

  // Calibrated geometry of the odometry and the encoder's tick size.
  const double radius = config_.wheel_radius_m * (1.0 + config_.radius_error);
  const double baseline = config_.baseline_m * (1.0 + config_.baseline_error);
  const double ticks = config_.encoder_resolution_ticks;
  const double radians_per_tick = ticks > 0.0 ? 2.0 * std::numbers::pi / ticks : 0.0;

  // Draws in a fixed order (the encoder phases, then per sample left and right noise), even when noise or
  // quantisation are off, so that switching one on leaves the other's sequence unchanged.
  std::mt19937_64 engine(seed_);
  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  std::normal_distribution<double> normal(0.0, 1.0);
  Eigen::Vector2d phase;  // fraction of a tick each encoder starts at
  phase.x() = uniform(engine);
  phase.y() = uniform(engine);

  SimulatedWheel out;
  Eigen::Vector2d angle = Eigen::Vector2d::Zero();  // true wheel angles, rad, since the first sample
  Eigen::Vector2d previous_rates = Eigen::Vector2d::Zero();
  Eigen::Vector2d previous_count = Eigen::Vector2d::Zero();
  Stamp previous_stamp = 0;
  for (std::int64_t k = 0;; ++k) {
    const Stamp stamp = GridStamp(begin, period_ns, k);
    if (stamp > end) break;
    Eigen::Vector2d rates = WheelRates(stamp);
    for (std::size_t i = 0; i < config_.floats.size(); ++i) {
      if (config_.floats[i].Contains(stamp)) {
        rates = frozen_rates(i);
        break;
      }
    }

    Eigen::Vector2d measured = rates;
    if (ticks > 0.0) {
      // Trapezoid rule for the wheel angle; the first sample assumes its rate held over one period before.
      const double dt = k == 0 ? static_cast<double>(period_ns) * 1e-9 : ToSeconds(stamp - previous_stamp);
      const Eigen::Vector2d previous_angle = k == 0 ? Eigen::Vector2d(-rates * dt) : angle;
      if (k > 0) angle += 0.5 * dt * (previous_rates + rates);
      // Whole ticks passed: count = floor(angle / tick + phase); rate = (count_k - count_{k-1}) tick / dt.
      const auto count = [&](const Eigen::Vector2d& a) {
        return Eigen::Vector2d(std::floor(a.x() / radians_per_tick + phase.x()),
                               std::floor(a.y() / radians_per_tick + phase.y()));
      };
      if (k == 0) previous_count = count(previous_angle);
      const Eigen::Vector2d current_count = count(angle);
      measured = (current_count - previous_count) * radians_per_tick / dt;
      previous_count = current_count;
    }
    measured.x() += config_.wheel_speed_noise_std * normal(engine);
    measured.y() += config_.wheel_speed_noise_std * normal(engine);
    previous_rates = rates;
    previous_stamp = stamp;

    // Odometry with the calibrated r', b': v = r' (phi_r + phi_l) / 2, w = r' (phi_r - phi_l) / b'.
    WheelSample sample;
    sample.stamp = stamp;
    sample.linear_velocity = Eigen::Vector3d(0.5 * radius * (measured.y() + measured.x()), 0.0, 0.0);
    sample.angular_velocity = Eigen::Vector3d(0.0, 0.0, radius * (measured.y() - measured.x()) / baseline);
    out.samples.push_back(sample);
    out.truth.push_back(TrueMotion(stamp));
  }
  return out;
}

}  // namespace uf::sim
