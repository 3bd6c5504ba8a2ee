#include "odometry/estimator/calib/calibration_consensus.h"

#include <algorithm>
#include <cmath>
#include <vector>

namespace uf::estimator {

std::optional<double> OffsetConsensus(std::span<const double> values, int count, double tolerance) {
  if (count < 1 || values.size() < static_cast<std::size_t>(count)) return std::nullopt;
  std::vector<double> last(values.end() - count, values.end());
  std::sort(last.begin(), last.end());
  const double median = count % 2 ? last[count / 2] : 0.5 * (last[count / 2 - 1] + last[count / 2]);
  for (double v : last)
    if (std::abs(v - median) > tolerance) return std::nullopt;
  return median;
}

std::optional<SO3> RotationConsensus(std::span<const SO3> values, int count, double tolerance_rad) {
  if (count < 1 || values.size() < static_cast<std::size_t>(count)) return std::nullopt;
  Eigen::Matrix3d sum = Eigen::Matrix3d::Zero();
  for (auto it = values.end() - count; it != values.end(); ++it) sum += it->matrix();
  const SO3 centre = SO3(sum).Normalized();
  for (auto it = values.end() - count; it != values.end(); ++it)
    if ((centre.inverse() * *it).angle() > tolerance_rad) return std::nullopt;
  return centre;
}

}  // namespace uf::estimator
