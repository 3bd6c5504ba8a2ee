// What the fixed-rate sensor models (IMU, wheel, GNSS) share: their sample grid, the check of the interval
// they are asked for, and numbers in error messages.
#pragma once

#include <cstdint>
#include <string>
#include <string_view>

#include "odometry/sim/trajectory_spline.h"
#include "odometry/types/stamp.h"
#include "odometry/types/status.h"

namespace uf::sim {

// Stamp of sample k (any integer k) of the grid begin + round(k * period_ns). Each stamp is rounded on its
// own, so a period that is not a whole number of nanoseconds does not drift.
inline Stamp GridStamp(Stamp begin, long double period_ns, std::int64_t k) {
  return begin + std::llround(static_cast<long double>(k) * period_ns);
}

// Fails, naming the sensor ("imu", "wheel", "gnss") and the values, when [begin, end] is empty, not inside
// the trajectory, or would hold 1e8 samples or more at rate_hz (a mistaken rate or range).
Status CheckSampleInterval(std::string_view sensor, const TrajectorySpline& trajectory, Stamp begin,
                           Stamp end, double rate_hz);

// A number as it reads in an error message ("-5", "0.25", "nan").
std::string NumberText(double value);

}  // namespace uf::sim
