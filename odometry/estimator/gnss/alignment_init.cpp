#include "odometry/estimator/gnss/alignment_init.h"

#include <algorithm>
#include <cmath>
#include <sstream>

namespace uf::estimator {
namespace {

Status Refused(const std::string& why) { return Status::Error("GNSS alignment initialization: " + why); }

}  // namespace

double HorizontalBaseline(std::span<const AlignmentPair> pairs) {
  double baseline = 0.0;
  for (const AlignmentPair& pair : pairs)
    baseline = std::max(baseline, (pair.antenna_world - pairs.front().antenna_world).head<2>().norm());
  return baseline;
}

double HorizontalWeight(const Eigen::Matrix3d& covariance) {
  return 2.0 / (covariance(0, 0) + covariance(1, 1));
}

Expected<AlignmentInit> InitializeAlignment(std::span<const AlignmentPair> pairs,
                                            const GnssFactorConfig& config) {
  const int count = static_cast<int>(pairs.size());
  if (count < config.min_alignment_fixes)
    return Refused(std::to_string(count) + " fixes, need " + std::to_string(config.min_alignment_fixes));
  for (const AlignmentPair& pair : pairs)
    if (!pair.antenna_world.allFinite() || !pair.fix_enu.allFinite() || !std::isfinite(pair.weight) ||
        !(pair.weight > 0))
      return Refused("a pair with a non-finite position or a weight that is not positive");
  AlignmentInit result;
  result.pairs = count;
  result.baseline_m = HorizontalBaseline(pairs);
  if (result.baseline_m < config.min_alignment_baseline_m) {
    std::ostringstream why;
    why << "horizontal baseline " << result.baseline_m << " m, need " << config.min_alignment_baseline_m
        << " m for the yaw";
    return Refused(why.str());
  }

  // Weighted centroids, then the cross and dot sums of the centred horizontal components.
  double W = 0.0;
  Eigen::Vector3d c_a = Eigen::Vector3d::Zero(), c_b = Eigen::Vector3d::Zero();
  for (const AlignmentPair& pair : pairs) {
    W += pair.weight;
    c_a += pair.weight * pair.antenna_world;
    c_b += pair.weight * pair.fix_enu;
  }
  c_a /= W;
  c_b /= W;
  double cross = 0.0, dot = 0.0;
  for (const AlignmentPair& pair : pairs) {
    const Eigen::Vector2d A = (pair.antenna_world - c_a).head<2>(), B = (pair.fix_enu - c_b).head<2>();
    cross += pair.weight * (A.x() * B.y() - A.y() * B.x());
    dot += pair.weight * A.dot(B);
  }
  EnuAlignment& alignment = result.alignment;
  alignment.yaw_rad = std::atan2(cross, dot);
  alignment.translation.head<2>() =
      c_b.head<2>() - RotationZ(alignment.yaw_rad).topLeftCorner<2, 2>() * c_a.head<2>();
  alignment.translation.z() = c_b.z() - c_a.z();  // = sum w_i (b_i,z - a_i,z) / W

  double squared = 0.0;
  for (const AlignmentPair& pair : pairs)
    squared += (alignment.Apply(pair.antenna_world) - pair.fix_enu).squaredNorm();
  result.rms_m = std::sqrt(squared / count);
  if (result.rms_m > config.max_alignment_rms_m) {
    std::ostringstream why;
    why << "residual RMS " << result.rms_m << " m exceeds " << config.max_alignment_rms_m << " m";
    return Refused(why.str());
  }
  return result;
}

}  // namespace uf::estimator
