#include "odometry/sim/sampling.h"

#include <sstream>

namespace uf::sim {

Status CheckSampleInterval(std::string_view sensor, const TrajectorySpline& trajectory, Stamp begin,
                           Stamp end, double rate_hz) {
  const std::string name(sensor);
  if (begin > end) {
    return Status::Error(name + " simulation interval is empty: begin " + FormatSeconds(begin) +
                         " s is after end " + FormatSeconds(end) + " s");
  }
  if (!trajectory.Contains(begin) || !trajectory.Contains(end)) {
    return Status::Error(name + " simulation interval [" + FormatSeconds(begin) + ", " + FormatSeconds(end) +
                         "] s is not inside the trajectory [" + FormatSeconds(trajectory.begin()) + ", " +
                         FormatSeconds(trajectory.end()) + "] s");
  }
  constexpr long double kMaxSamples = 1e8;
  const long double period_ns = 1e9L / static_cast<long double>(rate_hz);
  if (static_cast<long double>(end - begin) / period_ns >= kMaxSamples) {
    return Status::Error(name + " simulation at " + NumberText(rate_hz) + " Hz over " +
                         FormatSeconds(end - begin) + " s would give more than 1e8 samples");
  }
  return {};
}

std::string NumberText(double value) {
  std::ostringstream text;
  text << value;
  return text.str();
}

}  // namespace uf::sim
