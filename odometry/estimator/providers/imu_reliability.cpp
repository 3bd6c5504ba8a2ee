#include "odometry/estimator/providers/imu_reliability.h"

#include "odometry/estimator/factors/imu_factor.h"
#include "odometry/estimator/schedule/imu_score.h"

namespace uf::estimator {

std::optional<ImuReliability> ScoreImuFactor(const FactorGraph& graph, long tag) {
  for (const Factor& entry : graph.Entries(FactorKind::kImu)) {
    const auto* factor = dynamic_cast<const ImuFactor*>(entry.cost.get());
    if (entry.tag != tag || factor == nullptr || entry.blocks.size() != 4) continue;
    const double *speed_bias_i = entry.blocks[1], *speed_bias_j = entry.blocks[3];
    const Vector15d r = factor->Residual(entry.blocks[0], speed_bias_i, entry.blocks[2], speed_bias_j);
    const ImuPreintegration& pre = factor->preintegration();
    const double T = pre.sum_dt_seconds();
    const Eigen::Vector3d gyro_bias = Eigen::Map<const Eigen::Vector3d>(speed_bias_i + 6);
    const Eigen::Vector3d dv =
        Eigen::Map<const Eigen::Vector3d>(speed_bias_j) - Eigen::Map<const Eigen::Vector3d>(speed_bias_i);
    return ScoreImuInterval({.rate_rad_s = pre.CorrectedDeltaR(gyro_bias).Log().norm() / T,
                             .acceleration_mps2 = dv.norm() / T,
                             .chi2 = (factor->sqrt_information() * r).squaredNorm(),
                             .clipped_steps = pre.clipped_steps()});
  }
  return std::nullopt;
}

}  // namespace uf::estimator
