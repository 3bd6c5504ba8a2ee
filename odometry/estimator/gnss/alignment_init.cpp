#include "odometry/estimator/gnss/alignment_init.h"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <vector>

#include "odometry/types/alignment.h"

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

  // A gravity-aligned world: the yaw-only weighted alignment (2D Procrustes, types/alignment.h).
  std::vector<Eigen::Vector3d> antenna, enu;
  std::vector<double> weights;
  for (const AlignmentPair& pair : pairs) {
    antenna.push_back(pair.antenna_world);
    enu.push_back(pair.fix_enu);
    weights.push_back(pair.weight);
  }
  const SE3 T_enu_world = WeightedRigidAlignment(antenna, enu, weights, /*yaw_only=*/true);
  EnuAlignment& alignment = result.alignment;
  alignment.yaw_rad = std::atan2(T_enu_world.rotation()(1, 0), T_enu_world.rotation()(0, 0));
  alignment.translation = T_enu_world.translation();

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
