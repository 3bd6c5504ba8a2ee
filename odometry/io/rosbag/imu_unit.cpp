#include "odometry/io/rosbag/imu_unit.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace uf {

std::string_view ImuAccelUnitName(ImuAccelUnit unit) {
  switch (unit) {
    case ImuAccelUnit::kMetersPerSecond2:
      return "m/s^2";
    case ImuAccelUnit::kStandardGravity:
      return "g";
    case ImuAccelUnit::kAuto:
      break;
  }
  return "auto";
}

Expected<ImuAccelUnit> DetectImuAccelUnit(std::span<const double> accel_norms, std::string_view topic) {
  std::vector<double> norms;
  for (double norm : accel_norms) {
    if (std::isfinite(norm)) norms.push_back(norm);
  }
  if (norms.empty()) {
    return Status::Error("IMU topic " + std::string(topic) +
                         ": no finite acceleration to detect its unit from; set imu_accel_unit");
  }
  auto middle = norms.begin() + static_cast<std::ptrdiff_t>(norms.size() / 2);
  std::nth_element(norms.begin(), middle, norms.end());
  const double median = *middle;
  if (median >= 0.5 && median <= 1.5) return ImuAccelUnit::kStandardGravity;
  if (median >= 5 && median <= 15) return ImuAccelUnit::kMetersPerSecond2;
  char value[32];
  std::snprintf(value, sizeof(value), "%.6g", median);
  return Status::Error("IMU topic " + std::string(topic) +
                       ": median acceleration norm over the first second is " + value +
                       ", neither near 1 (g) nor near 9.81 (m/s^2); set imu_accel_unit");
}

ImuUnitGate::ImuUnitGate(ImuAccelUnit configured, std::string topic)
    : unit_(configured), topic_(std::move(topic)) {}

void ImuUnitGate::Emit(ImuSample sample, std::vector<ImuSample>& ready) const {
  if (unit_ == ImuAccelUnit::kStandardGravity) sample.acc *= kStandardGravity;
  ready.push_back(sample);
}

Status ImuUnitGate::Resolve(std::vector<ImuSample>& ready) {
  std::vector<double> norms;
  norms.reserve(held_.size());
  for (const ImuSample& sample : held_) norms.push_back(sample.acc.norm());
  const Expected<ImuAccelUnit> unit = DetectImuAccelUnit(norms, topic_);
  if (!unit.ok()) return unit.status();
  unit_ = *unit;
  for (const ImuSample& sample : held_) Emit(sample, ready);
  held_.clear();
  held_.shrink_to_fit();
  return Status();
}

Status ImuUnitGate::Push(const ImuSample& recorded, std::vector<ImuSample>& ready) {
  if (resolved()) {
    Emit(recorded, ready);
    return Status();
  }
  held_.push_back(recorded);
  // Stamps may go backwards in a bag: the window is measured both ways from the first sample.
  const Stamp span = recorded.stamp - held_.front().stamp;
  if (span >= kDetectionWindow || span <= -kDetectionWindow || held_.size() >= kMaxHeld) {
    return Resolve(ready);
  }
  return Status();
}

Status ImuUnitGate::Flush(std::vector<ImuSample>& ready) {
  if (resolved() || held_.empty()) return Status();
  return Resolve(ready);
}

}  // namespace uf
