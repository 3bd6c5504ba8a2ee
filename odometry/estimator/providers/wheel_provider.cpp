#include "odometry/estimator/providers/wheel_provider.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "odometry/estimator/factors/wheel_factor.h"
#include "odometry/estimator/factors/zero_motion_factor.h"
#include "odometry/estimator/schedule/wheel_consistency.h"
#include "odometry/estimator/state/nav_state.h"

namespace uf::estimator {
namespace {

constexpr long kScalePriorTag = -1;

}  // namespace

WheelProvider::WheelProvider(const WheelFactorConfig& config, const SE3& T_body_wheel)
    : config_(config),
      T_body_wheel_(T_body_wheel),
      gate_(ActivationRule{.threshold = config.schedule.threshold,
                           .release_margin = config.schedule.release_margin,
                           .release_keyframes = config.schedule.release_keyframes}) {}

std::optional<std::string> WheelProvider::Add(const WheelSample& sample) {
  if (!sample.linear_velocity.allFinite() || !sample.angular_velocity.allFinite())
    return "wheel sample at " + StampText(sample.stamp) + " skipped: not finite";
  if (!samples_.empty() && sample.stamp <= samples_.back().stamp)
    return "wheel sample at " + StampText(sample.stamp) + " skipped: not after " +
           StampText(samples_.back().stamp);
  samples_.push_back(sample);
  return std::nullopt;
}

Stamp WheelProvider::CoveredUntil() const {
  if (samples_.empty()) return std::numeric_limits<Stamp>::min();
  return samples_.back().stamp + FromSeconds(config_.time_offset_s);
}

void WheelProvider::Attach(FactorGraph& graph) {
  graph.AddEuclideanBlock(&scale_, 1);
  graph.Add(FactorKind::kWheel, kScalePriorTag,
            std::make_unique<WheelScalePriorFactor>(config_.scale_prior_sigma), nullptr, {&scale_});
}

Status WheelProvider::Link(FactorGraph& graph, long tag, double* pose_from, double* pose_to, Stamp from,
                           Stamp to, WheelReference reference, const double* speed_bias_from,
                           const double* speed_bias_to) {
  Expected<WheelPreintegration> pre = WheelPreintegration::Between(samples_, from, to, config_);
  if (!pre) {
    ++skipped_;
    return pre.status();
  }
  if (reference == WheelReference::kClipped) {
    clipped_at_ = to;
    restart_baseline_ = true;
  }
  if (reference == WheelReference::kPredicted && !predicted_from_) {
    predicted_from_ = from;
    restart_baseline_ = true;
  }
  const double settle_s = config_.schedule.change_window_s;
  const bool settled = (!clipped_at_ || ToSeconds(from - *clipped_at_) >= settle_s) &&
                       (!predicted_from_ || ToSeconds(from - *predicted_from_) >= settle_s);
  if (reference == WheelReference::kPredicted && settled &&
      !Admit(tag, *pre, pose_from, pose_to, from, to, speed_bias_from, speed_bias_to)) {
    ++suppressed_;
    return {};
  }
  graph.Add(FactorKind::kWheel, tag, std::make_unique<WheelFactor>(std::move(*pre), T_body_wheel_), nullptr,
            {pose_from, pose_to, &scale_});
  ++added_;
  return {};
}

std::optional<Eigen::Vector3d> WheelProvider::WheelVelocity(Stamp t, const SO3& R_world_body) const {
  if (samples_.empty()) return std::nullopt;
  const Stamp wheel_clock = t - FromSeconds(config_.time_offset_s);
  auto it = std::lower_bound(samples_.begin(), samples_.end(), wheel_clock,
                             [](const WheelSample& s, Stamp x) { return s.stamp < x; });
  if (it == samples_.end() ||
      (it != samples_.begin() && wheel_clock - (it - 1)->stamp < it->stamp - wheel_clock))
    --it;
  const SO3& R_bw = T_body_wheel_.so3();
  const Eigen::Vector3d w_body = R_bw * it->angular_velocity;
  const Eigen::Vector3d v_body =
      R_bw * (scale_ * it->linear_velocity) - w_body.cross(T_body_wheel_.translation());
  return (R_world_body * v_body).eval();
}

double WheelProvider::SpeedChangeDisagreement(const SE3& T_from, const SE3& T_to, Stamp from, Stamp to,
                                              const double* speed_bias_from, const double* speed_bias_to) {
  const double window_s = config_.schedule.change_window_s;
  if (!(window_s > 0) || speed_bias_from == nullptr || speed_bias_to == nullptr) return 0.0;
  const std::optional<Eigen::Vector3d> wheel_from = WheelVelocity(from, T_from.so3());
  const std::optional<Eigen::Vector3d> wheel_to = WheelVelocity(to, T_to.so3());
  if (!wheel_from || !wheel_to) return 0.0;
  // The IMU's change: v_to holds its prediction from v_from, g dt + R dV, whatever v_from is.
  const Eigen::Vector3d imu_change =
      Eigen::Map<const Eigen::Vector3d>(speed_bias_to) - Eigen::Map<const Eigen::Vector3d>(speed_bias_from);
  changes_.emplace_back(to, (*wheel_to - *wheel_from) - imu_change);
  while (!changes_.empty() && changes_.front().first <= to - FromSeconds(window_s)) changes_.pop_front();
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  for (const auto& [stamp, change] : changes_) sum += change;
  return (T_body_wheel_.so3().inverse() * (T_to.so3().inverse() * sum)).head<2>().norm();
}

bool WheelProvider::Admit(long tag, const WheelPreintegration& pre, const double* pose_from,
                          const double* pose_to, Stamp from, Stamp to, const double* speed_bias_from,
                          const double* speed_bias_to) {
  if (!config_.schedule.enabled) return true;
  if (restart_baseline_) changes_.clear();
  // The wheel's body motion at the current scale (the factor's prediction), against the IMU's.
  const SE3 wheel = T_body_wheel_ * SE3(pre.delta_R(), pre.ScaledDeltaP(scale_)) * T_body_wheel_.inverse();
  const SE3 T_from = PoseFromBlock(pose_from), T_to = PoseFromBlock(pose_to);
  const SE3 imu = T_from.inverse() * T_to;
  const double change = SpeedChangeDisagreement(T_from, T_to, from, to, speed_bias_from, speed_bias_to);
  const WheelScheduleConfig& s = config_.schedule;
  const double shut_s = gate_.active() || !shut_at_ ? 0.0 : ToSeconds(to - *shut_at_);
  const double dt = ToSeconds(to - from);
  const WheelScore score =
      ScoreWheelMotion(wheel, imu, T_body_wheel_.so3(), dt, baseline_, change,
                       {.speed_tolerance_mps = s.speed_tolerance_mps + s.drift_mps_per_s * shut_s,
                        .yaw_rate_tolerance_rad_s = s.yaw_rate_tolerance_rad_s,
                        .speed_weight = s.speed_weight,
                        .change_tolerance_mps = s.change_tolerance_mps});
  WheelConsistency consistency = score.consistency;
  const bool was_active = gate_.active();
  if (restart_baseline_ || (!was_active && shut_s >= s.max_shut_s)) {
    // After clipped IMU readings, or held out long enough: taken, its level the new u_0.
    restart_baseline_ = false;
    gate_.Open();
    baseline_ = score.disagreement;
    consistency.active = true;
  } else {
    consistency.active = gate_.Update(consistency.score);
  }
  if (was_active && !consistency.active) shut_at_ = to;
  // u_0 follows the admitted intervals (an exponential average over baseline_time_s).
  if (consistency.active) {
    const double w = s.baseline_time_s > 0 ? std::min(1.0, dt / s.baseline_time_s) : 1.0;
    baseline_ = s.baseline_time_s > 0 ? ((1 - w) * baseline_ + w * score.disagreement).eval()
                                      : Eigen::Vector2d::Zero();
  }
  scores_[tag] = consistency;
  return consistency.active;
}

std::optional<WheelConsistency> WheelProvider::TakeConsistency(long tag) {
  std::optional<WheelConsistency> score;
  if (auto it = scores_.find(tag); it != scores_.end()) score = it->second;
  scores_.erase(scores_.begin(), scores_.upper_bound(tag));
  return score;
}

Expected<SE3> WheelProvider::Motion(Stamp from, Stamp to) const {
  Expected<WheelPreintegration> pre = WheelPreintegration::Between(samples_, from, to, config_);
  if (!pre) return pre.status();
  return T_body_wheel_ * SE3(pre->delta_R(), pre->delta_p()) * T_body_wheel_.inverse();
}

Eigen::Matrix3d WheelProvider::PositionInformation(const SO3& R_world_body, double dt) const {
  const Eigen::Vector3d forward = R_world_body * T_body_wheel_.so3() * Eigen::Vector3d::UnitX();
  const double along = 1 / (std::pow(config_.forward_velocity_density, 2) * dt);
  const double across = 1 / (std::pow(config_.nonholonomic_velocity_density, 2) * dt);
  return across * Eigen::Matrix3d::Identity() + (along - across) * forward * forward.transpose();
}

bool WheelProvider::AtRest(Stamp from, Stamp to) const {
  const Stamp offset = FromSeconds(config_.time_offset_s);
  const std::span<const WheelSample> used = SamplesBracketing(samples_, from - offset, to - offset);
  return !used.empty() && std::all_of(used.begin(), used.end(), [](const WheelSample& s) {
    return s.linear_velocity.norm() <= kRestSpeed && s.angular_velocity.norm() <= kRestTurnRate;
  });
}

bool WheelProvider::LinkAtRest(FactorGraph& graph, long tag, double* pose_from, double* pose_to,
                               double* speed_bias_from, double* speed_bias_to, Stamp from, Stamp to) {
  if (!config_.stationary_updates || !AtRest(from, to)) return false;
  graph.Add(FactorKind::kWheel, tag, MakeZeroMotionFactor({}), nullptr,
            {pose_from, pose_to, speed_bias_from, speed_bias_to});
  ++at_rest_;
  return true;
}

void WheelProvider::Report(SensorFactorStats& stats) const {
  stats.wheel = {added_, skipped_, suppressed_};
  stats.wheel_at_rest = at_rest_;
  stats.wheel_scale = scale_;
}

void WheelProvider::Trim(Stamp oldest) {
  const Stamp wheel_clock = oldest - FromSeconds(config_.time_offset_s);
  auto keep = std::lower_bound(samples_.begin(), samples_.end(), wheel_clock,
                               [](const WheelSample& s, Stamp t) { return s.stamp < t; });
  if (keep != samples_.begin()) --keep;
  samples_.erase(samples_.begin(), keep);
}

}  // namespace uf::estimator
