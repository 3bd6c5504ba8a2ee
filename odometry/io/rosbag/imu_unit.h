// Unit of sensor_msgs/Imu linear_acceleration. REP-103 says m/s^2, but some drivers publish g. With
// ImuAccelUnit::kAuto the first second of a topic decides: at rest or moving, the median norm of the specific
// force stays near 1 g, so a median in 0.5..1.5 means g and one in 5..15 means m/s^2; anything else is an
// error naming the topic and the value.
#pragma once

#include <cstddef>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "odometry/io/dataset_options.h"
#include "odometry/types/measurements.h"
#include "odometry/types/status.h"

namespace uf {

inline constexpr double kStandardGravity = 9.80665;  // m/s^2 per g

std::string_view ImuAccelUnitName(ImuAccelUnit unit);  // "m/s^2", "g", "auto"

// Decides from acceleration norms (in the unknown unit); never returns kAuto.
Expected<ImuAccelUnit> DetectImuAccelUnit(std::span<const double> accel_norms, std::string_view topic);

// Holds back the samples of one IMU topic until their unit is known, then hands them on in m/s^2. With a
// configured unit nothing is held. With kAuto the samples of the first second (at most kMaxHeld) are held,
// so memory stays bounded whatever the rate.
class ImuUnitGate {
 public:
  static constexpr std::size_t kMaxHeld = 4000;
  static constexpr Stamp kDetectionWindow = kNanosecondsPerSecond;

  ImuUnitGate(ImuAccelUnit configured, std::string topic);

  bool resolved() const { return unit_ != ImuAccelUnit::kAuto; }
  ImuAccelUnit unit() const { return unit_; }

  // Takes a sample as recorded; appends to `ready` every sample that can now be emitted, in order.
  Status Push(const ImuSample& recorded, std::vector<ImuSample>& ready);
  // End of data: decides from what is held (if anything) and releases it.
  Status Flush(std::vector<ImuSample>& ready);

 private:
  Status Resolve(std::vector<ImuSample>& ready);
  void Emit(ImuSample sample, std::vector<ImuSample>& ready) const;

  ImuAccelUnit unit_;
  std::string topic_;
  std::vector<ImuSample> held_;
};

}  // namespace uf
