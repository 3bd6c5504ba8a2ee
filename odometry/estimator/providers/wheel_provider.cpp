#include "odometry/estimator/providers/wheel_provider.h"

#include <algorithm>
#include <limits>

#include "odometry/estimator/factors/wheel_factor.h"
#include "odometry/estimator/preintegration/wheel_preintegration.h"

namespace uf::estimator {
namespace {

constexpr long kScalePriorTag = -1;

}  // namespace

WheelProvider::WheelProvider(const WheelFactorConfig& config, const SE3& T_body_wheel)
    : config_(config), T_body_wheel_(T_body_wheel) {}

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
                           Stamp to) {
  Expected<WheelPreintegration> pre = WheelPreintegration::Between(samples_, from, to, config_);
  if (!pre) {
    ++skipped_;
    return pre.status();
  }
  graph.Add(FactorKind::kWheel, tag, std::make_unique<WheelFactor>(std::move(*pre), T_body_wheel_), nullptr,
            {pose_from, pose_to, &scale_});
  ++added_;
  return {};
}

Expected<SE3> WheelProvider::Motion(Stamp from, Stamp to) const {
  Expected<WheelPreintegration> pre = WheelPreintegration::Between(samples_, from, to, config_);
  if (!pre) return pre.status();
  return T_body_wheel_ * SE3(pre->delta_R(), pre->delta_p()) * T_body_wheel_.inverse();
}

void WheelProvider::Report(SensorFactorStats& stats) const {
  stats.wheel = {added_, skipped_};
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
