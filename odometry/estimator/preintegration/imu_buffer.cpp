#include "odometry/estimator/preintegration/imu_buffer.h"

#include <algorithm>
#include <limits>

namespace uf::estimator {
namespace {

bool Before(const ImuSample& s, Stamp t) { return s.stamp < t; }

}  // namespace

ImuBuffer::ImuBuffer(const ImuNoiseParams& params, double max_gap_s)
    : params_(params), gravity_world_(0.0, 0.0, -params.gravity), max_gap_(FromSeconds(max_gap_s)) {}

std::optional<std::string> ImuBuffer::Add(const ImuSample& sample) {
  if (!sample.acc.allFinite() || !sample.gyro.allFinite())
    return "IMU sample at " + StampText(sample.stamp) + " skipped: not finite";
  if (!samples_.empty() && sample.stamp <= samples_.back().stamp)
    return "IMU sample at " + StampText(sample.stamp) + " skipped: not after " +
           StampText(samples_.back().stamp);
  samples_.push_back(sample);
  return std::nullopt;
}

Stamp ImuBuffer::CoveredUntil() const {
  return samples_.empty() ? std::numeric_limits<Stamp>::min() : samples_.back().stamp;
}

Stamp ImuBuffer::OldestStamp() const {
  return samples_.empty() ? std::numeric_limits<Stamp>::max() : samples_.front().stamp;
}

Expected<ImuPreintegration> ImuBuffer::Preintegrate(Stamp from, Stamp to, const Eigen::Vector3d& accel_bias,
                                                    const Eigen::Vector3d& gyro_bias) const {
  if (samples_.empty() || samples_.front().stamp > from || samples_.back().stamp < to)
    return Status::Error("no IMU samples cover " + StampText(from) + " .. " + StampText(to));
  auto first = std::lower_bound(samples_.begin(), samples_.end(), from, Before);
  if (first != samples_.begin()) --first;
  for (auto it = first; it + 1 != samples_.end() && it->stamp < to; ++it) {
    if ((it + 1)->stamp - it->stamp > max_gap_)
      return Status::Error("gap of " + std::to_string(ToSeconds((it + 1)->stamp - it->stamp)) +
                           " s between IMU samples at " + StampText(it->stamp));
  }
  auto last = std::lower_bound(first, samples_.end(), to, Before);
  if (last != samples_.end()) ++last;
  Expected<ImuPreintegration> pre = ImuPreintegration::Between(std::vector<ImuSample>(first, last), from, to,
                                                               accel_bias, gyro_bias, params_);
  if (pre) pre->SetGravityWorld(gravity_world_);
  return pre;
}

Expected<ImuPreintegration> ImuBuffer::Preintegrate(Stamp from, Stamp to, const double* speed_bias) const {
  if (!speed_bias) return Preintegrate(from, to, Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero());
  return Preintegrate(from, to, Eigen::Vector3d(speed_bias[3], speed_bias[4], speed_bias[5]),
                      Eigen::Vector3d(speed_bias[6], speed_bias[7], speed_bias[8]));
}

std::vector<ImuSample> ImuBuffer::Between(Stamp from, Stamp to) const {
  std::vector<ImuSample> out;
  for (auto it = std::lower_bound(samples_.begin(), samples_.end(), from, Before);
       it != samples_.end() && it->stamp <= to; ++it)
    out.push_back(*it);
  return out;
}

void ImuBuffer::Trim(Stamp oldest) {
  if (samples_.size() < 2) return;
  auto keep = std::lower_bound(samples_.begin(), samples_.end(), oldest, Before);
  if (keep != samples_.begin()) --keep;
  samples_.erase(samples_.begin(), keep);
}

}  // namespace uf::estimator
