#include "odometry/types/trajectory.h"

#include <algorithm>

namespace uf {

std::optional<SE3> Trajectory::PoseAt(Stamp t) const {
  if (stamps.empty() || t < stamps.front() || t > stamps.back()) return std::nullopt;
  const auto after = std::lower_bound(stamps.begin(), stamps.end(), t);  // the first stamp >= t
  const std::size_t i = static_cast<std::size_t>(after - stamps.begin());
  if (*after == t) return poses[i];
  const double s = static_cast<double>(t - stamps[i - 1]) / static_cast<double>(stamps[i] - stamps[i - 1]);
  return Interpolate(poses[i - 1], poses[i], s);
}

}  // namespace uf
